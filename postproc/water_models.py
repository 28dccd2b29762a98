"""Compare the water-model candidates against the paper's evidence (issue 8;
docs/model.md, "Water drag: the choice").

Reads the runs of data/water_models.table (descriptions ``wm_<candidate>_r<ridge>_v<speed>``)
and prints, per candidate and ridge:

- F^m, the cohesive peak (maximum over the first 5 mm), and its y_I at 0.1 m/s, and the
  record maximum beside it (paper: a cohesive peak at ~1 mm, the maximum of the record);
- F^m(0.01)/F^m(0.1): cohesive peaks within the travel both records cover, same 2 s ramp
  (paper section 2.4: 0.97);
- F(20 mm)/F^m (paper: a steep drop until ~20 mm);
- F̄ / F_d(K = 0.45) at the snapshots from 20 mm on, F̄ the mean load over y_I ± 5 mm
  (paper Figs. 18, 20: post-peak F lies near the buoyant load of the displaced rubble,
  R = 0.88 across ridges);
- the shares of the indenter work that went into drag and into viscous damping.

    /usr/bin/python3 -m postproc.water_models RESULTS_DIR [-o table.md]
"""
import argparse
import os
import re
import sys

import h5py
import numpy as np

from icerubble.files.results import find_results, load

from . import displaced_area as dA
from .loads import cohesive_peak, load_at, record_maximum

NAME = re.compile(r"wm_(?P<cand>.+)_r(?P<ridge>\d+)_v(?P<v>[0-9.]+)\.h5$")
K = 0.45


def energy_shares(path):
    """(drag, damping) dissipation over the indenter's work, at the end of the record."""
    with h5py.File(path, "r") as f:
        if "energy" not in f:
            return np.nan, np.nan
        e = f["energy"]
        w = float(e["work_boundary"][-1])
        return float(e["drag"][-1]) / w, float(e["damping"][-1]) / w


def run_metrics(fast, slow):
    y, F = fast.force_y, fast.force_F
    Fm, ym = cohesive_peak(y, F)
    F_max, y_max = record_maximum(y, F)
    out = dict(Fm=Fm / 1e3, y_m=ym * 1e3, F_max=F_max / 1e3, y_max=y_max * 1e3)
    out["F20_over_Fm"] = load_at(y, F, 20e-3) / Fm if y[-1] >= 20e-3 else np.nan
    ratios, pairs = [], []
    for s in fast.snapshots:
        if s.y_I < 19.5e-3 or s.y_I > y[-1]:
            continue
        Fd = dA.displaced_load(fast, K, s.y_I)
        Fy = dA.paired_load(fast, s.y_I)
        ratios.append(Fy / Fd if Fd > 0 else np.nan)
        pairs.append((Fd, Fy))
    out["F_over_Fd"] = ratios
    out["pairs"] = pairs
    out["drag_share"], out["damping_share"] = energy_shares(fast.path)
    if slow is not None:
        common = min(y[-1], slow.force_y[-1])
        f_fast = cohesive_peak(y[y <= common], F[y <= common])[0]
        f_slow = cohesive_peak(slow.force_y[slow.force_y <= common], slow.force_F[slow.force_y <= common])[0]
        out["slow_over_fast"] = f_slow / f_fast
        out["common_mm"] = common * 1e3
        out["slow_F"] = {mm: load_at(slow.force_y, slow.force_F, mm * 1e-3) / load_at(y, F, mm * 1e-3)
                         for mm in (1, 5, 10) if mm * 1e-3 <= common}
    return out


def collect(folder):
    runs = {}
    for path in find_results(folder)[0]:
        m = NAME.search(os.path.basename(path))
        if m:
            runs[(m["cand"], int(m["ridge"]), float(m["v"]))] = load(path)
    table = {}
    for (cand, ridge, v), run in sorted(runs.items()):
        if v != 0.1:
            continue
        table[(cand, ridge)] = run_metrics(run, runs.get((cand, ridge, 0.01)))
    return table


def fmt(x, spec=".2f"):
    return "—" if x is None or (isinstance(x, float) and not np.isfinite(x)) else format(x, spec)


def markdown(table):
    lines = ["| candidate | ridge | F^m [kN/m] | y_I at F^m [mm] | record max [kN/m] at [mm] | "
             "F^m(0.01)/F^m(0.1) | F(0.01)/F(0.1) at 1, 5, 10 mm | F(20)/F^m | F̄/F_d(0.45) at 20, 30 mm | "
             "drag / damping share of indenter work |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for (cand, ridge), r in table.items():
        slow = r.get("slow_F", {})
        lines.append(
            f"| {cand} | {ridge} | {fmt(r['Fm'], '.1f')} | {fmt(r['y_m'], '.2f')} | "
            f"{fmt(r['F_max'], '.1f')} at {fmt(r['y_max'], '.2f')} | "
            f"{fmt(r.get('slow_over_fast'))} | {', '.join(fmt(slow.get(mm)) for mm in (1, 5, 10))} | "
            f"{fmt(r['F20_over_Fm'])} | {', '.join(fmt(x) for x in r['F_over_Fd'])} | "
            f"{fmt(r['drag_share'])} / {fmt(r['damping_share'])} |")
    # correlation of post-peak F with F_d across the ridges of each candidate
    lines.append("")
    lines.append("| candidate | R(F̄, F_d(0.45)) over ridges and snapshots >= 20 mm | points |")
    lines.append("|---|---|---|")
    for cand in sorted({c for c, _ in table}):
        pts = [p for (c, _), r in table.items() if c == cand for p in r["pairs"]]
        R = dA.correlation([p[0] for p in pts], [p[1] for p in pts])[0] if len(pts) > 2 else np.nan
        lines.append(f"| {cand} | {fmt(R)} | {len(pts)} |")
    return "\n".join(lines)


def figure(folder, out_png):
    """F-y_I of every candidate (rows: ridges; solid 0.1 m/s, dashed 0.01 m/s)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    runs = {}
    for path in find_results(folder)[0]:
        m = NAME.search(os.path.basename(path))
        if m:
            runs[(m["cand"], int(m["ridge"]), float(m["v"]))] = load(path)
    ridges = sorted({r for _, r, _ in runs})
    cands = sorted({c for c, _, _ in runs})
    fig, axes = plt.subplots(len(ridges), 2, figsize=(11, 3.6 * len(ridges)), squeeze=False)
    for i, ridge in enumerate(ridges):
        for j, y_max in enumerate((None, 5e-3)):
            ax = axes[i, j]
            for k, cand in enumerate(cands):
                for v, ls in ((0.1, "-"), (0.01, "--")):
                    run = runs.get((cand, ridge, v))
                    if run is None:
                        continue
                    keep = run.force_y <= (y_max or np.inf)
                    ax.plot(run.force_y[keep] * 1e3, run.force_F[keep] / 1e3, ls, color=f"C{k}", lw=1,
                            label=f"{cand}, {v:g} m/s")
            ax.set_xlabel("y_I [mm]")
            ax.set_ylabel("F [kN/m]")
            ax.set_title(f"ridge {ridge}" + (" (first 5 mm)" if y_max else ""))
    axes[0, 0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out_png, dpi=110)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results", help="folder with the wm_* result files")
    ap.add_argument("-o", "--out", help="write the Markdown table here too")
    ap.add_argument("--figure", help="draw the F-y_I records of all candidates into this PNG")
    a = ap.parse_args(argv)
    table = collect(a.results)
    if not table:
        sys.exit(f"water_models: no wm_*_v0.1.h5 results under {a.results}")
    text = markdown(table)
    print(text)
    if a.out:
        with open(a.out, "w") as f:
            f.write(text + "\n")
    if a.figure:
        figure(a.results, a.figure)


if __name__ == "__main__":
    main()
