"""The sleeping far field on the punch-through (not a test): how much element
work it saves and what it changes, against the same run without it.

For one scene, ridge and numerical preset, the run without sleeping and then
the same run with each set of sleep thresholds (engine sleeping.hpp). For each:
the fraction of the load phase's element-steps computed, wall time of the load
phase, and the errors against the run without sleeping in F^m, y_I at F^m, the
mean F over 1-5, 5-10 and 10-20 mm, n_t/n_s, and the energy residual. Writes
bench/results/sleeping_<scene>.json.

    /usr/bin/python3 bench/sleeping.py [--scene wide] [--ridge 1] [--numerics balanced]
                                       [--travel-mm 20] [--quick] [--out-dir runs/bench/sleeping]

--quick: the demo scene over 5 mm, one threshold set. Runs are kept in
--out-dir (identity-checked: a variant already run is reused).
"""
import argparse
import json
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from runtime_vs_error import errors, measures  # noqa: E402

from icerubble.files import results  # noqa: E402
from icerubble.run.presets import numerics  # noqa: E402
from icerubble.run.punch_through_run import RunOptions  # noqa: E402
from icerubble.study.line import run_one  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# (name, thresholds): velocity [m/s] every node of a body stays under for a
# window of quiet_time [s], force the fraction of its weight its mean
# resultant stays under (and an asleep node's force may move by)
THRESHOLDS = [
    ("sleep 1e-4 m/s, 1e-3, 2 ms", dict(velocity=1e-4, force=1e-3, quiet_time=2e-3)),
    ("sleep 1e-3 m/s, 1e-2, 10 ms", dict(velocity=1e-3, force=1e-2, quiet_time=1e-2)),
    ("sleep 3e-3 m/s, 3e-2, 10 ms", dict(velocity=3e-3, force=3e-2, quiet_time=1e-2)),
]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default="wide")
    ap.add_argument("--ridge", type=int, default=1)
    ap.add_argument("--numerics", default="balanced")
    ap.add_argument("--travel-mm", type=float, default=20.0)
    ap.add_argument("--out-dir", default=os.path.join("runs", "bench", "sleeping"))
    ap.add_argument("--quick", action="store_true", help="demo scene, 5 mm, one threshold set")
    a = ap.parse_args(argv)
    thresholds = THRESHOLDS
    if a.quick:
        a.scene, a.travel_mm, thresholds = "demo", 5.0, THRESHOLDS[:1]
        a.out_dir = os.path.join(a.out_dir, "quick")
    settings = numerics(a.scene, a.numerics)
    rows = []
    for name, sleep in [("no sleeping", None)] + thresholds:
        options = RunOptions.from_numerics(dict(settings, sleep=sleep), name=a.numerics)
        desc = f"{a.scene}_r{a.ridge}_{a.numerics}_" + name.replace(" ", "_").replace("/", "").replace(",", "")
        path = os.path.join(a.out_dir, desc + ".h5")
        fresh = not os.path.exists(path)
        t0 = time.perf_counter()
        run_one(a.scene, ridge=a.ridge, overrides=dict(target_travel=a.travel_mm * 1e-3),
                out_dir=a.out_dir, description=desc, options=options)
        m = measures(path)
        row = dict(name=name, scene=a.scene, ridge=a.ridge, numerics=a.numerics, travel_mm=a.travel_mm,
                   sleep=sleep, file=path,
                   wall_s=time.perf_counter() - t0 if fresh else float("nan"),   # reused: not timed
                   wall_load_s=results.load(path).attrs.get("wall_load_s", float("nan")), **m)
        rows.append(row)
    ref = rows[0]
    for r in rows:
        r["errors"] = errors(r, ref)
        e = r["errors"]
        print(f"{r['name']:22s} element-steps {100 * r.get('element_fraction', 1.0):5.1f} %  "
              f"load {r['wall_load_s']:7.1f} s  F^m {r['F_m_kN_per_m']:7.3f} kN/m (err "
              f"{100 * e['F_m_rel_err']:5.2f} %, y_I {e['y_I_peak_abs_err_mm']:.3f} mm)  mean F err "
              f"1-5 {100 * e['F_mean_1_5mm_rel_err']:5.2f} %  5-10 {100 * e['F_mean_5_10mm_rel_err']:5.2f} %  "
              f"10-20 {100 * e['F_mean_10_20mm_rel_err']:5.2f} %  n_t/n_s {e['nt_ns_abs_err']:.2f}  "
              f"energy residual {r['energy_residual_rel']:.1e}", flush=True)
    out = os.path.join(ROOT, "bench", "results", f"sleeping_{a.scene}{'_quick' if a.quick else ''}.json")
    with open(out, "w") as f:
        json.dump(dict(runs=rows), f, indent=1, default=float)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
