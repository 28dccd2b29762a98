"""Cost of the freeze-bond passes (docs/freeze_bonds.md) on a bonded scene.

A 4 x 4 grid of ice blocks, each 20 x 10 cells of h = 0.05 m (400 triangles,
1.0 m x 0.5 m), 6,400 triangles in all, every block interface bonded
(bond points from icerubble.geometry.bond_points, junctions at the block corners);
E = 2 GPa, nu = 0.3, rho = 920 kg/m³, no gravity, no water, dt = 0.9 x the
stable step. Left and bottom edges held (x, y), right and top edges pulled out at 1e-4 m/s.

Cases (each ``--steps`` steps after a warm-up, wall time of the bond passes
from Model.timings()['bonds'] and of the whole step):
  intact_no_screen   sigma_cr = 1e4 Pa: nothing splits; every point checked every step
  intact_screen      the same with pre-screening (screen_interval 8, fraction 0.5)
  opened             sigma_cr = 100 Pa, G = 0.01 J/m²: every point splits within the
                     warm-up and softens (delta_f = 2e-4 m, past the rigid phase
                     after a few steps): the cohesive pass on all pairs

Writes bench/results/bonds.json. Not a test: figures depend on the machine and
its load (2 shared cores when written).
    /usr/bin/python3 bench/bonds.py [--quick] [--steps 2000] [--threads 0]
"""
import argparse
import json
import os
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "bench", "results", "bonds.json")

from icerubble import engine
from icerubble.geometry.bond_points import find_bond_points


def scene(sigma_cr, G, screen_interval, threads):
    h = 0.05
    nodes, tri = engine.rectangle_mesh(80, 40, h)
    c = nodes[tri].mean(axis=1)
    body = ((c[:, 0] // 1.0) + 4 * (c[:, 1] // 0.5)).astype(np.int32)
    m = engine.Model(nodes, tri, body, dict(E=2e9, nu=0.3, rho=920.0))
    bp = find_bond_points(nodes, tri, body, keel_top_y=2.0, keel_depth=2.0, sigma_cr=sigma_cr,
                          tau_cr=5 * sigma_cr, G=G, bottom_fraction=1.0)
    m.set(gravity=False, penalty=1e9, threads=threads)
    m.set_bond_points(bp, screen_interval=screen_interval)
    m.add_node_set("left", np.flatnonzero(nodes[:, 0] == 0.0))
    m.add_node_set("right", np.flatnonzero(nodes[:, 0] == nodes[:, 0].max()))
    m.add_node_set("bottom", np.flatnonzero(nodes[:, 1] == 0.0))
    m.add_node_set("top", np.flatnonzero(nodes[:, 1] == nodes[:, 1].max()))
    m.fix("left", x=True, y=False)
    m.fix("bottom", x=False, y=True)
    m.prescribe_velocity("right", (1, 0), v_final=1e-4, ramp_time=0.0, y=False)
    m.prescribe_velocity("top", (0, 1), v_final=1e-4, ramp_time=0.0, x=False)
    m.set(dt=0.9 * m.stable_time_step()["dt"])
    return m, bp


def measure(m, steps, warmup):
    m.step(warmup)
    while m.bonds.counts['split'] < m.bonds.counts['points'] and m.step_count < 20 * warmup:
        m.step(warmup)
    t0 = m.timings()
    w0 = time.perf_counter()
    m.step(steps)
    wall = time.perf_counter() - w0
    t1 = m.timings()
    bonds = (t1["bonds"] - t0["bonds"]) / steps
    total = (t1["total"] - t0["total"]) / steps
    return dict(bond_us_per_step=1e6 * bonds, step_us=1e6 * total, bond_share=bonds / total,
                wall_s=wall, checks_per_step=None)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="400 steps per case")
    ap.add_argument("--steps", type=int, default=2000)
    ap.add_argument("--threads", type=int, default=0, help="0: OMP_NUM_THREADS / all cores")
    a = ap.parse_args()
    steps = 400 if a.quick else a.steps
    cases = [("intact_no_screen", 1e4, 15.0, 1), ("intact_screen", 1e4, 15.0, 8),
             ("opened", 100.0, 0.01, 8)]
    out = []
    for name, sigma, G, k in cases:
        m, bp = scene(sigma, G, k, a.threads)
        c0 = m.bonds.counts["checks"]
        r = measure(m, steps, warmup=50)
        counts = m.bonds.counts
        r.update(case=name, triangles=m.n_triangles, bond_points=counts["points"],
                 pairs=counts["pairs"], split=counts["split"], failed=counts["failed"],
                 screen_interval=k, steps=steps, threads=a.threads or os.cpu_count(),
                 checks_per_step=(counts["checks"] - c0) / m.step_count)
        if name.startswith("intact"):
            assert counts["split"] == 0, "bench scene must stay intact"
        else:
            assert counts["split"] >= 0.99 * counts["points"], "bench scene must be opened"
        out.append(r)
        print(f"{name:17s} {r['bond_points']} points {r['pairs']} pairs: bonds "
              f"{r['bond_us_per_step']:7.1f} us/step = {100 * r['bond_share']:5.1f} % of a "
              f"{r['step_us']:7.1f} us step; {r['checks_per_step']:.0f} point checks/step",
              flush=True)
    gain = out[0]["bond_us_per_step"] / out[1]["bond_us_per_step"]
    print(f"pre-screening: bond check {gain:.1f}x cheaper on the intact scene")
    os.makedirs(os.path.dirname(RESULTS), exist_ok=True)
    with open(RESULTS, "w") as f:
        json.dump(dict(cases=out, screening_gain=gain,
                       note="wall times on a shared, loaded 2-core machine: noisy"), f, indent=1)
    print("wrote", RESULTS)


if __name__ == "__main__":
    main()
