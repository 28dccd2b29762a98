"""The cohesive peak F^m of the paper scene under each numerical preset,
against a reference (not a test).

The paper scene costs hours per preset (bench/paper_cost.py), most of it
the settle and the slow start of the indenter's 2 s ramp. F^m comes at
~1 mm of travel, so the runs here stop at --travel-mm (2 mm: 0.57 s of
loading) and all start from ONE rest state, settled once with --settle-numerics:
what differs between them is the loading's numerics alone (step, masses,
contact reach). Each preset's own settle reaches another rest within the
settle tolerance (every body in balance to 1e-4 of its weight), not
compared here.

    /usr/bin/python3 bench/paper_peak.py [--ridge 1] [--travel-mm 2] [--only fast balanced ...] [--device cuda]

Variants: the presets `fast`, `balanced` and `paper`, run in that order
(measured 0.55 h and 0.76 h; `paper` 3.6 million steps, ~4 h, on 2 cores), and
on request (--only reference) `reference`: the paper preset's masses at half
its step (0.08 µs, ~10 h).
The errors are against the smallest step that has been run (`paper`, the
faithful numerics: at 0.16 µs the blocks' own contact modes run at ~0.15 of
their stable step; only the few mass-scaled nodes of tiny elements run near
theirs). Runs are kept in --out-dir and reused; each is resumable from its
checkpoint (run the script again). Writes bench/results/paper_peak.json.

--device cuda runs the settle and the loadings as whole steps on one GPU
(docs/gpu.md), in a folder of their own, and writes
bench/results/paper_peak_cuda.json: the same errors, and the wall time of
each preset's travel on the GPU (issue 28, item 3; --travel-mm 300 for the
whole run, --only reference for the reference run never made on a CPU).

A lent GPU has minutes, not the settle's hours: make the rest state where
there is time (--settle-only, on the CPU) and carry it there (--rest PATH):
the loadings then start from the rest state the CPU's runs started from, so
the GPU's F^m of a preset is also checked against the CPU's (issue 28, item 2).

    /usr/bin/python3 bench/paper_peak.py --settle-only             # here: writes ridge1_2mm/rest_fast.checkpoint.h5
    python3 bench/paper_peak.py --device cuda --rest runs/bench/paper_peak/ridge1_2mm/rest_fast.checkpoint.h5
"""
import argparse
import json
import os
import time

import h5py
import numpy as np

from icerubble.files import results
from icerubble.run.presets import numerics, scene
from icerubble.run.punch_through_run import PunchThrough, RunOptions
from icerubble.run.scene_cache import scene_files
from postproc import loads

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT_JSON = os.path.join(ROOT, "bench", "results", "paper_peak.json")
ORDER = ("fast", "balanced", "paper", "reference")
DEFAULT = ORDER[:3]


def variant_options(name, device="cpu", threads=0):
    if name == "reference":
        return RunOptions.from_numerics(dict(numerics("paper", "paper"), dt_fraction=0.4), name="reference",
                                        progress_every_s=60.0, device=device, threads=threads)
    return RunOptions.from_numerics(numerics("paper", name), name=name, progress_every_s=60.0, device=device,
                                    threads=threads)


def rest_state(mesh_path, params, out_dir, settle_numerics, device="cpu", threads=0):
    """The checkpoint of a run of this scene at the start of its loading
    (settled with the preset `settle_numerics`); made once, resumable."""
    path = os.path.join(out_dir, f"rest_{settle_numerics}.checkpoint.h5")
    if not os.path.exists(path):
        run = PunchThrough(mesh_path, os.path.join(out_dir, f"settle_{settle_numerics}.h5"), params,
                           variant_options(settle_numerics, device, threads))
        run.settle_only(path)
    return path


def load_from_rest(name, mesh_path, params, rest, out_dir, ridge, device="cpu", threads=0):
    out = os.path.join(out_dir, f"{name}.h5")
    if not os.path.exists(out):
        PunchThrough(mesh_path, out, params, variant_options(name, device, threads),
                     meta=dict(ridge=ridge)).run_from_rest(rest)
    with h5py.File(out, "r") as f:   # a stored run is reused only if it loaded from this rest state
        came_from = f.attrs.get("rest_state_from", "")
    if os.path.basename(str(came_from)) != os.path.basename(rest):
        raise ValueError(f"{out} was loaded from the rest state {came_from!r}, not {rest!r}: move it away")
    return out


def measures(path, travel_mm):
    r = results.load(path)
    y, F = np.asarray(r.force_y), np.asarray(r.force_F)
    i = int(np.argmax(F))
    out = dict(F_m_kN_per_m=float(F[i]) / 1e3, y_I_peak_mm=float(y[i]) * 1e3,
               dt=float(r.parameters["dt"]), load_steps=int(r.attrs.get("load_steps", 0)),
               added_mass_fraction=float(r.attrs.get("added_mass_fraction", 0.0)),
               # the reach guard and the splits change it as the run goes
               added_mass_fraction_end=float(r.attrs.get("added_mass_fraction_end", np.nan)),
               wall_load_s=float(r.attrs.get("wall_load_s", np.nan)))
    for a, b in ((0.1, 0.5), (0.5, 1.0), (1.0, travel_mm)):   # the plateau at the peak, and after
        if b <= a:   # a load to 1 mm or less has no window after it
            continue
        try:
            out[f"F_mean_{a:g}_{b:g}mm_kN_per_m"] = float(loads.mean_load(y, F, a * 1e-3, b * 1e-3)) / 1e3
        except ValueError:
            out[f"F_mean_{a:g}_{b:g}mm_kN_per_m"] = float("nan")
    out["n_failed"] = int(np.count_nonzero(np.isfinite(np.asarray(r.bonds["y_I_fail"], dtype=float))))
    with h5py.File(path, "r") as f:
        e = f["energy"]
        out["energy_residual_rel"] = float(abs(e["residual"][-1]) / max(abs(e["work_boundary"][-1]), 1e-30))
    return out


def against(path, rows, rest, travel_mm):
    """The run in `path` (the same preset's load from the same rest state,
    on the other device) against this device's run of that preset: its
    measures, where it was made, and how far the two force records part."""
    with h5py.File(path, "r") as f:
        came_from, numerics = str(f.attrs.get("rest_state_from", "")), str(f.attrs.get("numerics", ""))
        made = {k: str(f.attrs.get(k, "")) for k in ("code_version", "processor", "created", "engine_build")}
    if os.path.basename(came_from) != os.path.basename(rest):
        raise SystemExit(f"paper_peak: --against {path} was loaded from the rest state {came_from!r}, not {rest!r}")
    mine = next((r for r in rows if r["name"] == numerics), None)
    if mine is None:
        raise SystemExit(f"paper_peak: --against {path} ran the preset {numerics!r}, which this run did not")
    m = measures(path, travel_mm)
    a, b = results.load(mine["file"]), results.load(path)
    n = min(len(a.force_F), len(b.force_F))
    same_y = bool(np.array_equal(np.asarray(a.force_y)[:n], np.asarray(b.force_y)[:n]))
    dF = np.abs(np.asarray(a.force_F)[:n] - np.asarray(b.force_F)[:n])
    return dict(file=path, preset=numerics, **made, **m, same_samples=same_y,
                F_m_rel_diff=abs(m["F_m_kN_per_m"] - mine["F_m_kN_per_m"]) / mine["F_m_kN_per_m"],
                y_I_peak_diff_mm=abs(m["y_I_peak_mm"] - mine["y_I_peak_mm"]),
                largest_F_diff_of_peak=float(dF.max() / max(np.max(a.force_F), 1e-300)))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ridge", type=int, default=1)
    ap.add_argument("--travel-mm", type=float, default=2.0)
    ap.add_argument("--settle-numerics", default="fast", choices=ORDER[:3])
    ap.add_argument("--only", nargs="*", choices=ORDER, help="variants to run (default: fast balanced paper); those run before are reported too")
    ap.add_argument("--out-dir", default=os.path.join("runs", "bench", "paper_peak"))
    ap.add_argument("--device", default="cpu", choices=("cpu", "cuda"),
                    help="where the steps run (cuda: whole steps on one GPU, runs and results of their own)")
    ap.add_argument("--settle-only", action="store_true", help="make the rest state (resumable) and stop")
    ap.add_argument("--rest", help="load from this rest state (a --settle-only checkpoint, e.g. the CPU's carried "
                                   "to a GPU) instead of settling here")
    ap.add_argument("--against", metavar="RUN_H5",
                    help="the same load of the same preset from the same rest state on the other device (e.g. the "
                         "CPU's run beside a GPU's): its F^m and its force record's largest difference are added")
    ap.add_argument("--threads", type=int, default=0,
                    help="CPU threads of each run (0: all cores; 1 for study lines run side by side; another count "
                         "changes a run's sums in round-off, docs/reproducibility.md)")
    a = ap.parse_args(argv)
    if a.threads < 0:
        raise SystemExit(f"paper_peak: --threads {a.threads} must be >= 0 (0: all cores)")
    if a.against and not os.path.exists(a.against):
        raise SystemExit(f"paper_peak: --against {a.against}: no such file")
    if a.rest and not os.path.exists(a.rest):
        raise SystemExit(f"paper_peak: --rest {a.rest}: no such file (make it with --settle-only)")
    if a.rest and a.settle_only:
        raise SystemExit("paper_peak: --rest and --settle-only exclude each other: the first loads from a rest "
                         "state, the second makes one")
    try:
        variant_options("fast", a.device)   # a GPU that cannot run is refused here, before any work
    except ValueError as e:
        raise SystemExit(f"paper_peak: {e}") from None
    sc = scene("paper")
    params = dict(sc["params"], target_travel=a.travel_mm * 1e-3)
    out_dir = os.path.join(a.out_dir, f"ridge{a.ridge}_{a.travel_mm:g}mm" + ("" if a.device == "cpu" else "_" + a.device))
    os.makedirs(out_dir, exist_ok=True)
    _, mesh_path = scene_files("paper", a.ridge)   # the scene cache of every run (runs/scenes)
    rest = a.rest or rest_state(mesh_path, params, out_dir, a.settle_numerics, a.device, a.threads)
    if a.settle_only:
        print(f"wrote the rest state {rest}")
        return
    rows = []
    for name in ORDER:
        out = os.path.join(out_dir, f"{name}.h5")
        if name not in (a.only or DEFAULT) and not os.path.exists(out):
            continue
        load_from_rest(name, mesh_path, params, rest, out_dir, a.ridge, a.device, a.threads)
        m = measures(out, a.travel_mm)
        rows.append(dict(name=name, file=out, **m))
        print(f"{name:10s} dt {m['dt'] * 1e6:5.3f} us  F^m {m['F_m_kN_per_m']:8.3f} kN/m @ "
              f"{m['y_I_peak_mm']:6.3f} mm  failed {m['n_failed']:4d}  load {m['wall_load_s'] / 3600:5.2f} h",
              flush=True)
    ref = min(rows, key=lambda r: r["dt"])
    for r in rows:
        r["F_m_rel_err"] = abs(r["F_m_kN_per_m"] - ref["F_m_kN_per_m"]) / ref["F_m_kN_per_m"]
        r["y_I_peak_abs_err_mm"] = abs(r["y_I_peak_mm"] - ref["y_I_peak_mm"])
        for k in [k for k in r if k.startswith("F_mean_")]:
            r[k.replace("_kN_per_m", "_rel_err")] = abs(r[k] - ref[k]) / abs(ref[k])
    with h5py.File(rest, "r") as f:
        d = f["driver"].attrs
        rest_attrs = dict(numerics=a.settle_numerics, settle_time_s=float(d["settle_time"]),
                          F_at_rest_N_per_m=float(d["F_at_rest"]), dt=json.loads(d["params"])["dt"])
    out_json = OUT_JSON if a.device == "cpu" else OUT_JSON.replace(".json", f"_{a.device}.json")
    os.makedirs(os.path.dirname(out_json), exist_ok=True)
    result = dict(ridge=a.ridge, travel_mm=a.travel_mm, rest_state=rest_attrs, reference=ref["name"],
                  device=a.device, threads=a.threads or os.cpu_count(), measured=time.strftime("%Y-%m-%d"),
                  runs=rows)
    if a.against:
        result["against"] = against(a.against, rows, rest, a.travel_mm)
    with open(out_json, "w") as f:
        json.dump(result, f, indent=1, default=float)
    print(f"wrote {out_json} (errors against {ref['name']})")
    for r in rows:
        means = "  ".join(f"{k[7:-8]} {100 * v:5.2f} %" for k, v in r.items()
                          if k.startswith("F_mean_") and k.endswith("_rel_err"))
        print(f"{r['name']:10s} err F^m {100 * r['F_m_rel_err']:6.2f} %  y_I@F^m {r['y_I_peak_abs_err_mm']:6.3f} mm  "
              f"mean F {means}  ({r['load_steps']} steps, {r['wall_load_s'] / r['load_steps'] * 1e3:.2f} ms per step)")


if __name__ == "__main__":
    main()
