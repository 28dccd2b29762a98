"""FEM-DEM beside rigid-DEM for one ridge (docs/model.md §6): what block
deformability changes in F-y_I, F^m, y_I at F^m, alpha, A_p and n_t/n_s, and
what it costs in wall time.

    python3 -m postproc.model_comparison FEM.h5 RIGID.h5 [-o OUT_DIR]

Writes OUT_DIR/model_comparison.png/.pdf (F-y_I of both, and the first 5 mm)
and model_comparison.md/.csv (the scalars side by side, with the wall times
and their ratio). The two files must be the same ridge (mesh, mu, tau_cr).
"""
import argparse
import csv
import os

import numpy as np

from icerubble.files import results

from . import plotting, summary

ROWS = [  # (summary column, label, unit)
    ("F_m_kN_per_m", "F^m", "kN/m"),   # the cohesive peak (loads.cohesive_peak)
    ("y_I_peak_mm", "y_I at F^m", "mm"),
    ("F_record_max_kN_per_m", "record maximum", "kN/m"),
    ("y_I_record_max_mm", "y_I at the record maximum", "mm"),
    ("F_20mm_kN_per_m", "F at 20 mm", "kN/m"),
    ("alpha_mean_1_20mm_deg", "alpha (mean 1-20 mm)", "deg"),
    ("A_p_20mm_m2", "A_p at 20 mm", "m^2"),
    ("n_split", "bond points opened", "-"),
    ("n_failed", "bond points failed", "-"),
    ("nt_ns", "n_t/n_s (mode at full failure)", "-"),
    ("nt_ns_init", "n_t/n_s at initiation (t_n >= 0 : t_n < 0)", "-"),
]


def wall_time(run):
    """Settle + load wall time of a run [s] (NaN if not recorded)."""
    a = run.attrs
    return float(a.get("wall_settle_s", np.nan)) + float(a.get("wall_load_s", np.nan))


def compare(fem, rigid):
    """Rows (label, unit, FEM-DEM value, rigid-DEM value) of the two runs."""
    for key in ("mu", "tau_cr"):
        if not np.isclose(float(fem.parameters[key]), float(rigid.parameters[key])):
            raise ValueError(f"the two runs differ in {key}: {fem.parameters[key]} and {rigid.parameters[key]}")
    if fem.ridge != rigid.ridge:
        raise ValueError(f"the two runs are different ridges: {fem.ridge!r} and {rigid.ridge!r}")
    a, b = summary.summarize(fem), summary.summarize(rigid)
    rows = [(label, unit, a[k], b[k]) for k, label, unit in ROWS]
    wf, wr = wall_time(fem), wall_time(rigid)
    rows.append(("wall time (settle + load)", "s", wf, wr))
    rows.append(("wall time ratio rigid / FEM-DEM", "-", 1.0, wr / wf if wf > 0 else np.nan))
    return rows


def figure(fem, rigid, out_dir):
    fig, ax = plotting.new(ncols=2, width=9.0, height=3.4)
    for run, name, style in ((fem, "FEM-DEM (deformable blocks)", dict(color="tab:blue")),
                             (rigid, "rigid-DEM (YADE polyhedra)", dict(color="tab:red", ls="--"))):
        y, F = run.force_y * 1e3, run.force_F / 1e3
        ax[0, 0].plot(y, F, label=name, **style)
        near = y <= 5.0
        ax[0, 1].plot(y[near], F[near], **style)
    for a in ax[0]:
        a.set_xlabel("indenter travel y_I [mm]")
        a.set_ylabel("F [kN/m]")
    ax[0, 0].legend()
    ax[0, 1].set_title("first 5 mm")
    return plotting.save(fig, out_dir, "model_comparison",
                         f"{fem.ridge}, mu = {fem.mu:g}, tau_cr = {fem.tau_cr / 1e3:g} kPa: FEM-DEM and rigid-DEM")


def write_tables(rows, out_dir):
    def cell(v):
        return "" if isinstance(v, float) and not np.isfinite(v) else (f"{v:.4g}" if isinstance(v, float) else str(v))
    with open(os.path.join(out_dir, "model_comparison.csv"), "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["quantity", "unit", "fem_dem", "rigid_dem"])
        for r in rows:
            w.writerow([r[0], r[1], cell(r[2]), cell(r[3])])
    lines = ["| quantity | unit | FEM-DEM | rigid-DEM |", "|---|---|---|---|"]
    lines += [f"| {r[0]} | {r[1]} | {cell(r[2])} | {cell(r[3])} |" for r in rows]
    with open(os.path.join(out_dir, "model_comparison.md"), "w") as fh:
        fh.write("\n".join(lines) + "\n")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python3 -m postproc.model_comparison", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("fem_dem", help="result file of the FEM-DEM run")
    ap.add_argument("rigid_dem", help="result file of the rigid-DEM run of the same ridge")
    ap.add_argument("-o", "--out-dir", default="model_comparison")
    args = ap.parse_args(argv)
    try:
        fem, rigid = results.load(args.fem_dem), results.load(args.rigid_dem)
    except (results.ResultFileError, OSError) as e:
        ap.error(str(e))
    if fem.model != "fem-dem" or rigid.model != "rigid-dem":
        ap.error(f"expected a fem-dem and a rigid-dem result, got {fem.model!r} and {rigid.model!r}")
    try:
        rows = compare(fem, rigid)
    except ValueError as e:
        ap.error(str(e))
    os.makedirs(args.out_dir, exist_ok=True)
    figure(fem, rigid, args.out_dir)
    print(write_tables(rows, args.out_dir))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
