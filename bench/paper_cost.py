"""The paper scene's cost (not a test): stable step, added mass, time per
step and the projected wall time of a full 300 mm run and of its first 20 mm,
for each numerical preset of icerubble/run/presets.py (NUMERICS), on this
machine. Writes bench/results/paper_cost.json.

    /usr/bin/python3 bench/paper_cost.py [--ridge 1] [--steps 300] [--threads 2]

The per-step cost is measured on the paper mesh in the load phase's
configuration (water, drag, contact, held layer top, driven indenter) from
rest. No preset uses the sleeping far field (docs/model.md §3.5).
"""
import argparse
import json
import os
import time

import numpy as np

from icerubble import parameters as P
from icerubble.files.mesh_file import read_mesh
from icerubble.run.presets import NUMERICS, scene
from icerubble.run.loading import smooth_ramp_table
from icerubble.run.scene import Scene
from icerubble.run.scene_cache import scene_files

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "bench", "results", "paper_cost.json")
# s simulated to bring the scene to rest: measured on the paper scene's
# ridge 1 as remade at the paper's porosity (410-413 blocks) with `fast`
# (settling at 2.28 us, 46 % more inertial mass on the boundary nodes): at
# rest after 1.646 s (runs/bench/paper_peak's rest state of 2026-11-30, its
# driver's settle_time: every node slower than 1e-4 m/s, every block in
# balance to 1e-4 of its weight). The other presets are assumed to need as
# long. (The earlier dense ridge 1 took 1.006 s.)
SETTLE_TIME = 1.646


def time_to_travel(travel, v_final, ramp_time):
    """Simulated time for the indenter to travel this far on the smooth ramp [s]."""
    t, v = smooth_ramp_table(0.0, v_final, ramp_time)
    y = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * np.diff(t))])
    if travel <= y[-1]:
        return float(np.interp(travel, y, t))
    return float(t[-1] + (travel - y[-1]) / v_final)


def measure(mesh, params, numerics, steps, threads, settle=False):
    """The load phase's cost; settle: at the preset's settle step instead (its
    masses, the same fraction of the stable step)."""
    s = Scene(mesh, params, threads=threads)
    m = s.model
    target = numerics.get("settle_mass_scaling_dt") if settle else numerics.get("mass_scaling_dt")
    m.set(contact_reach=numerics.get("contact_reach", float("inf")), mass_scaling_dt=target or 0.0)
    m.set(dt_fraction=numerics["dt_fraction"])
    m.fix("layer_top")
    t, v = smooth_ramp_table(0.0, params["v_final"], params["ramp_time"])
    m.prescribe_velocity("indenter_top", direction=(0.0, -1.0), table=(t, v))
    st = m.stable_time_step()
    m.step(20)
    t0 = m.timings()
    w0 = time.perf_counter()
    m.step(steps)
    wall = (time.perf_counter() - w0) / steps
    t1 = m.timings()
    share = (t1["elements"] - t0["elements"]) / max(t1["total"] - t0["total"], 1e-30)
    return dict(dt=m.dt, stable_dt=st["dt"], added_mass_fraction=st["added_mass_fraction"],
                scaled_nodes=st["scaled_nodes"], s_per_step=wall, element_share=share,
                n_triangles=m.n_triangles, n_nodes=m.n_nodes)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ridge", type=int, default=1)
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--quick", action="store_true", help="50 steps per preset (make bench --quick)")
    a = ap.parse_args(argv)
    if a.quick:
        a.steps = 50
    sc = scene("paper")
    _, mesh_path = scene_files("paper", a.ridge)
    mesh = read_mesh(mesh_path)
    params = P.validate(dict(sc["params"]))
    rows = []
    for name, numerics in NUMERICS["paper"].items():
        r = measure(mesh, params, numerics, a.steps, a.threads)
        out = dict(preset=name, numerics=numerics, **r)
        settle = r
        if numerics.get("settle_mass_scaling_dt"):
            settle = measure(mesh, params, numerics, a.steps, a.threads, settle=True)
            out["settle"] = settle
        settle_hours = SETTLE_TIME / settle["dt"] * settle["s_per_step"] / 3600
        for mm in (20, 300):
            t_load = time_to_travel(mm * 1e-3, params["v_final"], params["ramp_time"])
            out[f"steps_{mm}mm"] = SETTLE_TIME / settle["dt"] + t_load / r["dt"]
            out[f"hours_{mm}mm"] = settle_hours + t_load / r["dt"] * r["s_per_step"] / 3600
        rows.append(out)
        settle_text = "" if settle is r else (f"; settle at {settle['dt']:.2e} s (+{100 * settle['added_mass_fraction']:.1f} "
                                              f"% mass), {settle_hours:.2f} h")
        print(f"{name:9s} dt {r['dt']:.2e} s (+{100 * r['added_mass_fraction']:.2f} % mass on {r['scaled_nodes']} "
              f"nodes), {1e3 * r['s_per_step']:.2f} ms/step ({100 * r['element_share']:.0f} % elements){settle_text}: "
              f"first 20 mm {out['hours_20mm']:.1f} h, 300 mm {out['hours_300mm']:.1f} h", flush=True)
    os.makedirs(os.path.dirname(OUT), exist_ok=True)
    with open(OUT, "w") as f:
        json.dump(dict(ridge=a.ridge, threads=a.threads, settle_time_s=SETTLE_TIME,
                       load_average=os.getloadavg()[0], rows=rows), f, indent=1)
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
