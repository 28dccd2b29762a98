"""One summary row per run (CSV), in the paper's units: kN/m, mm, kPa, degrees, m^2.

`python3 -m postproc.summary RESULTS_DIR [-o summary.csv]`
"""
import argparse
import csv
import os
import sys

import numpy as np

from icerubble import cli
from icerubble.files import results
from icerubble.files.output_path import check_output_file, whole_file

from . import failure_plane, loads, plug, shear_strength

F20_TRAVEL = 20e-3  # m: the paper's "after the steep decrease" instant (Figs. 13-15, Table 2)
POST_PEAK_INTERVALS = ((20e-3, 150e-3), (150e-3, 300e-3))  # m (section 3.1.1, Figs. 18, 20)

COLUMNS = [
    "file", "scene", "ridge", "model", "force_direction", "seed", "mu", "tau_cr_kPa", "sigma_cr_kPa",
    "porosity", "keel_depth_m", "indenter_width_m", "y_I_end_mm",
    "bond_points", "F_m_kN_per_m", "y_I_peak_mm", "F_record_max_kN_per_m", "y_I_record_max_mm",
    "F_20mm_kN_per_m",
    "F_mean_20_150mm_kN_per_m", "F_mean_150_300mm_kN_per_m",
    "alpha_left_20mm_deg", "alpha_right_20mm_deg",
    "alpha_mean_1_20mm_deg", "alpha_sd_1_20mm_deg", "alpha_n_1_20mm",
    "A_p_20mm_m2", "A_p_mean_1_20mm_m2", "F_b_Ap_20mm_kN_per_m",
    "tau1_kPa", "tau2_kPa", "tau3_kPa", "tau1_record_max_kPa",
    "n_split", "n_failed", "n_split_settle", "failed_fraction", "n_t", "n_s", "nt_ns", "n_t_init", "n_s_init", "nt_ns_init",
    "n_snapshots", "missing",
    # added later (a summary.csv made before lacks them: postproc/stored_rows.py)
    "F_b_cylinder_kN_per_m", "run_id", "code_version",
]


def _try(fn, *args):
    try:
        return fn(*args)
    except ValueError:
        return np.nan


def summarize(run, plug_force=shear_strength.CYLINDRICAL_PLUG_FORCE,
              bond_points=failure_plane.DEFAULT_BOND_POINTS):
    """Dict of the per-run scalars of the paper's analyses (keys: COLUMNS).
    F^m is the cohesive peak (loads.cohesive_peak), the record maximum beside it;
    ``bond_points`` picks the points behind alpha and A_p (failure_plane)."""
    failure_plane.check_bond_points(bond_points)
    y, F = run.force_y, run.force_F
    F_m, y_peak = loads.cohesive_peak(y, F)
    F_max, y_max = loads.record_maximum(y, F)
    F20 = _try(loads.load_at, y, F, F20_TRAVEL)
    means = [_try(loads.mean_load, y, F, a, b) for a, b in POST_PEAK_INTERVALS]
    aL, aR = failure_plane.alpha_at(run, F20_TRAVEL, bond_points)
    a_samples = failure_plane.alpha_samples(run, bond_points=bond_points)
    a_mean, a_sd = failure_plane.mean_sd(a_samples)
    Ap20 = plug.plug_area(run, F20_TRAVEL, bond_points)
    Ap_all = [plug.plug_area(run, t, bond_points) for t in failure_plane.ALPHA_TRAVELS]
    Ap_mean = failure_plane.mean_sd(Ap_all)[0]
    Fb = float(plug.run_buoyant_load(run, Ap20))
    h = run.keel_depth
    t1, t2, t3 = shear_strength.three_strengths(F_m, h, plug_force, Fb)
    t1_max = float(shear_strength.shear_strength(F_max, 0.0, h))
    b = run.bonds
    n_t, n_s, ratio = shear_strength.failure_mode_ratio(b["mode"], b["y_I_fail"])
    n_t0, n_s0, ratio0 = shear_strength.initiation_side_ratio(b["y_I_split"], b.get("split_tn"))
    n_split = int(np.count_nonzero(np.isfinite(np.asarray(b["y_I_split"], dtype=float))))
    n_failed = int(np.count_nonzero(np.isfinite(np.asarray(b["y_I_fail"], dtype=float))))
    p = run.parameters
    return {
        "file": run.path, "scene": run.scene, "ridge": run.ridge, "model": run.model,
        "force_direction": run.force_direction,
        "seed": run.attrs.get("seed", ""), "mu": run.mu, "tau_cr_kPa": run.tau_cr / 1e3,
        "sigma_cr_kPa": float(p.get("sigma_cr", np.nan)) / 1e3,
        "porosity": run.porosity, "keel_depth_m": h, "indenter_width_m": run.indenter_width,
        "y_I_end_mm": float(y[-1]) * 1e3, "bond_points": bond_points,
        "F_m_kN_per_m": F_m / 1e3, "y_I_peak_mm": y_peak * 1e3,
        "F_record_max_kN_per_m": F_max / 1e3, "y_I_record_max_mm": y_max * 1e3,
        "F_20mm_kN_per_m": F20 / 1e3,
        "F_mean_20_150mm_kN_per_m": means[0] / 1e3, "F_mean_150_300mm_kN_per_m": means[1] / 1e3,
        "alpha_left_20mm_deg": aL, "alpha_right_20mm_deg": aR,
        "alpha_mean_1_20mm_deg": a_mean, "alpha_sd_1_20mm_deg": a_sd,
        "alpha_n_1_20mm": int(a_samples.size),
        "A_p_20mm_m2": Ap20, "A_p_mean_1_20mm_m2": Ap_mean, "F_b_Ap_20mm_kN_per_m": Fb / 1e3,
        "tau1_kPa": t1 / 1e3, "tau2_kPa": t2 / 1e3, "tau3_kPa": t3 / 1e3, "tau1_record_max_kPa": t1_max / 1e3,
        "n_split": n_split, "n_failed": n_failed,
        # split while settling (settle_bonds='checked'): the initial state, in none of the counts above
        "n_split_settle": int(run.attrs.get("settle_splits", 0)),
        "failed_fraction": shear_strength.failed_fraction(b["y_I_split"], b["y_I_fail"]),
        "n_t": n_t, "n_s": n_s, "nt_ns": ratio, "n_t_init": n_t0, "n_s_init": n_s0, "nt_ns_init": ratio0,
        "n_snapshots": len(run.snapshots), "missing": "; ".join(sorted(run.missing)),
        # F_b of the cylindrical plug w_I h (eq 13): tau^(2) of `icerubble compare`
        "F_b_cylinder_kN_per_m": float(plug.run_buoyant_load(run, run.indenter_width * h)) / 1e3,
        # what made the run, for a row read later without its file (stored_rows)
        "run_id": str(run.attrs.get("run_id", "")), "code_version": str(run.attrs.get("code_version", "")),
    }


def add_bond_points_option(parser):
    """--bond-points split|failed, the same on every command that fits alpha and A_p."""
    parser.add_argument("--bond-points", choices=tuple(failure_plane.BOND_POINTS),
                        default=failure_plane.DEFAULT_BOND_POINTS,
                        help="bond points behind alpha and A_p: 'split' (eq 5 reached, the paper's; "
                             "default) or 'failed' (fully failed, delta_e = delta_f)")


def _fmt(v):
    if isinstance(v, float):
        return "" if not np.isfinite(v) else f"{v:.{shear_strength.ROW_SIGNIFICANT_DIGITS}g}"
    return v


def write_csv(rows, path):
    """Write summary rows (dicts with COLUMNS) to ``path``; NaN becomes an empty cell."""
    with whole_file(path, newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=COLUMNS)
        w.writeheader()
        for r in rows:
            w.writerow({k: _fmt(r.get(k, "")) for k in COLUMNS})


def main(argv=None):
    ap = argparse.ArgumentParser(prog="icerubble summary", description=__doc__)
    ap.add_argument("results_dir")
    ap.add_argument("-o", "--output", default="summary.csv")
    ap.add_argument("--plug-force", type=float, default=shear_strength.CYLINDRICAL_PLUG_FORCE,
                    help="F_b of tau^(2) [N/m] (default 11e3)")
    add_bond_points_option(ap)
    args = ap.parse_args(argv)
    if not os.path.isdir(args.results_dir):
        ap.error(f"RESULTS_DIR {args.results_dir!r} is not a folder")
    check_output_file(args.output, "--output")
    runs, skipped = results.load_folder(args.results_dir)
    for why in skipped:
        print(f"skipped: {why}", file=sys.stderr)
    if not runs:   # an empty table would look like a summary of nothing
        ap.error(f"no result files to summarise under {args.results_dir!r} ({len(skipped)} file(s) skipped)")
    rows = [summarize(r, args.plug_force, args.bond_points) for r in runs]
    write_csv(rows, args.output)
    print(f"{len(rows)} run(s) -> {args.output}")
    return 0


if __name__ == "__main__":
    sys.exit(cli.run("summary", sys.argv[1:]))
