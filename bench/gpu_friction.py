"""Friction (eq 4) on the GPU against the CPU on a wall of pressed blocks (not
a test; docs/gpu.md). Writes bench/results/gpu_friction.json.

    python3 bench/gpu_friction.py [--rows 40 --cols 100] [--quick]

A wall of rows x cols square blocks (0.1 m, eight triangles each), each
pressed 10 um into its neighbours, nudged, with random velocities of a few
mm/s, stepped once (the warm start): thousands of touching pairs that stick
or slip and share nodes, more than a paper-scene step has. Times the CPU's
friction (ContactSolver.apply_friction on OpenMP's default threads: the sweeps
colour by colour, threaded where the colours hold 256 pairs or more)
and, where the GPU backend runs, the GPU's (the colouring in parallel rounds,
the sweeps, the node sums; device events), and whether the GPU gives the
CPU's colours and bits.
"""
import argparse
import os
import time

import numpy as np

import result_file

from icerubble import _engine, engine
from icerubble.code_identity import code_version, source_hash
from icerubble.engine import gpu
from icerubble.machine import processor
from icerubble.openmp_threads import default_threads

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "bench", "results", "gpu_friction.json")
SIDE = 0.1
OVERLAP = 1e-5
PENALTY = 2e11
MU = 0.3


def wall(rows, cols, rng):
    nodes, tris, body = [], [], []
    offset = 0
    for r in range(rows):
        for c in range(cols):
            n, t = engine.rectangle_mesh(2, 2, SIDE / 2, origin=(c * (SIDE - OVERLAP), r * (SIDE - OVERLAP)))
            nodes.append(n)
            tris.append(t + offset)
            offset += len(n)
            body += [r * cols + c] * len(t)
    nodes = np.vstack(nodes)
    m = engine.Model(nodes, np.vstack(tris), np.array(body),
                     materials={b: dict(E=5e9, nu=0.3, rho=920.0) for b in range(rows * cols)})
    m.set(penalty=PENALTY, mu=MU, dt_fraction=0.8)
    m.set_positions(nodes + rng.uniform(-2e-6, 2e-6, nodes.shape))
    m.set_velocities(rng.normal(0.0, 3e-3, nodes.shape))
    m.step(1)
    return m


def cpu_friction_ms(m, repeats):
    """ms per apply_friction call of a contact solver on the model's state
    (its normal pass once, then friction repeatedly on the same forces)."""
    xy, v = m.positions, m.velocities
    tri = np.ascontiguousarray(m._m.triangle_array("triangles"), dtype=np.int32)
    body = np.ascontiguousarray(m._m.triangle_array("body"), dtype=np.int32)
    surface = np.ascontiguousarray(m.surface_triangles, dtype=np.int32)
    mass = np.ascontiguousarray(m._m.node_array("mass"), dtype=float)
    args = (np.ascontiguousarray(xy[:, 0]), np.ascontiguousarray(xy[:, 1]), np.ascontiguousarray(v[:, 0]),
            np.ascontiguousarray(v[:, 1]), mass, tri, body, surface)
    s = _engine.ContactSolver(0.1)
    fx, fy = np.zeros(len(xy)), np.zeros(len(xy))
    touching = s.compute_normal(*args, fx, fy, penalty=PENALTY, mu=MU, dt=m.dt)
    s.apply_friction(*args, fx.copy(), fy.copy(), penalty=PENALTY, mu=MU, dt=m.dt)
    t0 = time.perf_counter()
    for _ in range(repeats):
        s.apply_friction(*args, fx.copy(), fy.copy(), penalty=PENALTY, mu=MU, dt=m.dt)
    return 1e3 * (time.perf_counter() - t0) / repeats, touching, s.sweep_order


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--rows", type=int, default=40)
    ap.add_argument("--cols", type=int, default=100)
    ap.add_argument("--repeats", type=int, default=200, help="GPU runs timed (the CPU's: a tenth)")
    ap.add_argument("--quick", action="store_true", help="a 20 x 25 wall")
    ap.add_argument("--out", default=OUT)
    a = ap.parse_args(argv)
    if a.quick:
        a.rows, a.cols = 20, 25
    m = wall(a.rows, a.cols, np.random.default_rng(1))
    cpu_ms, touching, order = cpu_friction_ms(m, max(a.repeats // 10, 3))
    colours = len(order["colour_start"]) - 1
    threads = default_threads()   # the solver's (in.threads 0: OpenMP's default)
    out = dict(rows=a.rows, cols=a.cols, n_triangles=m.n_triangles, n_nodes=m.n_nodes, touching_pairs=touching,
               colours=colours, cpu_ms=cpu_ms, cpu_threads=threads, processor=processor(), cpu_count=os.cpu_count(),
               code_version=code_version(), source_hash=source_hash(), measured=time.strftime("%Y-%m-%d"), gpu=None)
    print(f"wall of {a.rows} x {a.cols} blocks ({m.n_triangles:,} triangles): {touching:,} touching pairs in "
          f"{colours} colours; CPU friction {cpu_ms:.3f} ms ({threads} thread{'s' if threads > 1 else ''})",
          flush=True)
    if gpu.available():
        cmp = gpu.compare_friction(m)
        stage = gpu.Friction(m)
        us = 1e6 * stage.seconds_per_run(a.repeats)
        out["gpu"] = dict(device=gpu.device_name(), friction_us=us, rounds=cmp["rounds"], same=bool(cmp["ok"]),
                          colour_differs=cmp["colour"], power_rel=cmp["power_rel"])
        print(f"GPU {gpu.device_name()}: friction {us:.1f} us ({cpu_ms * 1e3 / us:.0f}x the CPU), coloured in "
              f"{cmp['rounds']} rounds; the CPU's colours and bits: {'yes' if cmp['ok'] else 'NO'} ({cmp})")
    else:
        print(f"GPU: {gpu.why_unavailable()}")
    result_file.write(a.out, out)


if __name__ == "__main__":
    main()
