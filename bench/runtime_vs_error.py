"""Run time against error on the punch-through's own outputs (not a test).

A reference run of one scene and ridge (a small time step, nothing skipped),
then variants that trade accuracy for speed: the time step fraction, the
sleeping far field and its thresholds, the indenter ramp. For each: wall time
of the load phase, element-steps computed, and the errors against the
reference in F^m, y_I at F^m, F at 5 / 10 / 20 mm, n_t/n_s and the energy
residual. Writes bench/results/runtime_vs_error.json and a Pareto plot (wall
time against F^m error) bench/results/runtime_vs_error.png.

    /usr/bin/python3 bench/runtime_vs_error.py [--scene demo] [--ridge 1] [--travel-mm 20]
                                               [--only NAME ...] [--out-dir runs/bench]

Runs are kept in --out-dir (identity-checked: a variant already run is
reused); delete the folder to measure again. One run at a time: the machine's
two cores go to each run's threads.
"""
import argparse
import json
import os
import time

import h5py

from icerubble.run.presets import scene
from icerubble.run.punch_through_run import RunOptions
from icerubble.run.study import run_one
from postproc import loads, results
from postproc.summary import summarize

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT_JSON = os.path.join(ROOT, "bench", "results", "runtime_vs_error.json")
OUT_PNG = os.path.join(ROOT, "bench", "results", "runtime_vs_error.png")

SLEEP_DEFAULT = dict(velocity=1e-4, force=1e-3, quiet_time=1e-3)


def variants(sc):
    """(name, run options, parameter overrides): the reference first."""
    f0 = sc["dt_fraction"]
    ms = sc.get("mass_scaling_dt")
    opt = lambda f=f0, sleep=None: RunOptions(dt_fraction=f, mass_scaling_dt=ms, sleep=sleep)
    return [
        ("reference", opt(f=0.25), {}),
        ("dt 0.5", opt(f=0.5), {}),
        ("dt 0.8 (scene)", opt(), {}),
        ("dt 1.0", opt(f=1.0), {}),
        ("sleep", opt(sleep=SLEEP_DEFAULT), {}),
        ("sleep loose", opt(sleep=dict(velocity=1e-3, force=1e-2, quiet_time=1e-3)), {}),
        ("sleep tight", opt(sleep=dict(velocity=1e-5, force=1e-4, quiet_time=1e-3)), {}),
        ("dt 1.0 + sleep", opt(f=1.0, sleep=SLEEP_DEFAULT), {}),
    ]


def measures(path):
    run = results.load(path)
    s = summarize(run)
    y, F = run.force_y, run.force_F
    out = {k: s[k] for k in ("F_m_kN_per_m", "y_I_peak_mm", "nt_ns", "n_failed", "alpha_mean_1_20mm_deg")}
    for mm in (5, 10, 20):
        try:
            out[f"F_{mm}mm_kN_per_m"] = float(loads.load_at(y, F, mm * 1e-3)) / 1e3
        except ValueError:
            out[f"F_{mm}mm_kN_per_m"] = float("nan")
    with h5py.File(path, "r") as f:
        e = f["energy"]
        # the ledger's residual against the work the indenter did
        out["energy_residual_rel"] = float(abs(e["residual"][-1]) / max(abs(e["work_boundary"][-1]), 1e-30))
    a = run.attrs
    out.update(load_steps=int(a.get("load_steps", 0)), load_element_steps=int(a.get("load_element_steps", 0)),
               n_triangles=int(a.get("n_triangles", 0)), dt=float(run.parameters["dt"]),
               added_mass_fraction=float(a.get("added_mass_fraction", 0.0)))
    if out["load_steps"] and out["n_triangles"]:
        out["element_fraction"] = out["load_element_steps"] / (out["load_steps"] * out["n_triangles"])
    return out


def errors(m, ref):
    err = {}
    for k in ("F_m_kN_per_m", "F_5mm_kN_per_m", "F_10mm_kN_per_m", "F_20mm_kN_per_m"):
        err[k.replace("_kN_per_m", "_rel_err")] = abs(m[k] - ref[k]) / abs(ref[k])
    err["y_I_peak_abs_err_mm"] = abs(m["y_I_peak_mm"] - ref["y_I_peak_mm"])
    err["nt_ns_abs_err"] = abs(m["nt_ns"] - ref["nt_ns"])
    return err


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for r in rows:
        if r["name"] == "reference":
            continue
        e = max(r["errors"]["F_m_rel_err"], 1e-5)
        ax.loglog(r["wall_load_s"], e * 100, "o")
        ax.annotate(r["name"], (r["wall_load_s"], e * 100), fontsize=7, xytext=(3, 3),
                    textcoords="offset points")
    ax.set_xlabel("wall time of the load phase [s]")
    ax.set_ylabel("error in F^m against the reference [%]")
    ax.set_title(f"{rows[0]['scene']} scene, ridge {rows[0]['ridge']}: run time against error", fontsize=9)
    ax.grid(True, which="both", lw=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=130)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default="demo")
    ap.add_argument("--ridge", type=int, default=1)
    ap.add_argument("--travel-mm", type=float, default=20.0)
    ap.add_argument("--only", nargs="*", help="variant names to run (the reference always runs)")
    ap.add_argument("--out-dir", default=os.path.join("runs", "bench"))
    a = ap.parse_args(argv)
    sc = scene(a.scene)
    rows = []
    for name, options, over in variants(sc):
        if a.only and name != "reference" and name not in a.only:
            continue
        desc = f"{a.scene}_r{a.ridge}_" + name.replace(" ", "_").replace("(", "").replace(")", "").replace("+", "and")
        path = os.path.join(a.out_dir, desc + ".h5")
        fresh = not os.path.exists(path)
        t0 = time.perf_counter()
        run_one(a.scene, ridge=a.ridge, overrides=dict(over, target_travel=a.travel_mm * 1e-3),
                out_dir=a.out_dir, description=desc, options=options)
        wall = time.perf_counter() - t0
        m = measures(path)
        row = dict(name=name, scene=a.scene, ridge=a.ridge, travel_mm=a.travel_mm, file=path,
                   dt_fraction=options.dt_fraction, sleep=options.sleep, overrides=over,
                   wall_run_s=wall if fresh else None, **m)
        row["wall_load_s"] = results.load(path).attrs.get("wall_load_s", float("nan"))
        rows.append(row)
        print(f"{name:18s} F^m {m['F_m_kN_per_m']:7.3f} kN/m @ {m['y_I_peak_mm']:6.3f} mm  "
              f"F(5/10/20) {m['F_5mm_kN_per_m']:6.2f} {m['F_10mm_kN_per_m']:6.2f} {m['F_20mm_kN_per_m']:6.2f}  "
              f"nt/ns {m['nt_ns']:5.2f}  elements {100 * m.get('element_fraction', 1.0):5.1f} %  "
              f"load {row['wall_load_s']:6.1f} s", flush=True)
    ref = rows[0]
    for r in rows:
        r["errors"] = errors(r, ref)
    os.makedirs(os.path.dirname(OUT_JSON), exist_ok=True)
    with open(OUT_JSON, "w") as f:
        json.dump(rows, f, indent=1, default=float)
    plot(rows, OUT_PNG)
    print(f"wrote {OUT_JSON} and {OUT_PNG}")
    for r in rows:
        e = r["errors"]
        print(f"{r['name']:18s} err F^m {100 * e['F_m_rel_err']:6.2f} %  F(5) {100 * e['F_5mm_rel_err']:6.2f} %  "
              f"F(10) {100 * e['F_10mm_rel_err']:6.2f} %  F(20) {100 * e['F_20mm_rel_err']:6.2f} %  "
              f"y_I@F^m {e['y_I_peak_abs_err_mm']:6.3f} mm")


if __name__ == "__main__":
    main()
