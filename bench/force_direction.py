"""Eq 11's two forms side by side on the paper-depth scene (issue 26, item 4; not a test).

The cohesive force of an opened pair points along eq 11 as printed ('paper')
or with work-conjugate weights (beta^2 on the tangential opening, Ortiz &
Pandolfi 1999: 'work_conjugate'). Which of them the study keeps is the one
whose trends with tau_cr match the paper's Tables 2-3 and Figs. 10-13: the
first peak (tau^(1)), alpha, and how the bond points fail, n_t/n_s (Table 3:
0.38, 1.44, 2.54 at tau_cr 5, 50, 100 kPa, counted at full failure over
300 mm). This measures finished runs (to 20 or 300 mm) of data/study_deep.table and
data/study_deep_direction.table (or any table of the deep scene):

    /usr/bin/python3 bench/force_direction.py --measure runs/deep/deep_ridge4_mu0.3_tau5k.h5 ...

and keeps one row per (ridge, mu, tau_cr, travel, force direction, settle procedure) in
bench/results/force_direction.json (a row measured again replaces the old
one). Per run: the first peak (the largest F before 1 mm) and the 5 mm
rule's F^m, alpha and A_p over y_I = 1-20 mm through the split points,
F(20 mm) and the mean F over 15-20 mm, the points split and fully failed while loading, n_t/n_s at full
failure (Table 3's count, within the run's travel) and at initiation (the
side of eq 6 on which each point split); a run to 300 mm also its count within
20 and 100 mm, its mean F over 20-150 and 150-300 mm (the paper's intervals,
postproc/summary.py) and its record maximum.
"""
import argparse
import json
import os
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [ROOT, os.path.join(ROOT, "bench")]

from deep_vs_paper import measures  # noqa: E402
from icerubble import machine, parameters as P  # noqa: E402
from icerubble.files import results  # noqa: E402
from postproc import loads, shear_strength, summary  # noqa: E402

OUT_JSON = os.path.join(ROOT, "bench", "results", "force_direction.json")
DIRECTIONS = P.FORCE_DIRECTIONS   # their order: the rows' order
# Table 3 of the paper: n_t/n_s at full failure over 300 mm (mean, sd over
# ridges 1-4 and both mu), by tau_cr [kPa]
TABLE_3 = {5.0: (0.38, 0.14), 50.0: (1.44, 0.61), 100.0: (2.54, 0.91)}
# the load after the peak, as a mean over the last 5 mm of a 20 mm run: F(20 mm), one
# sample, swings by tens of kN/m there (two runs of one line whose bits differ gave
# 19.0 and 30.1 kN/m; docs/study_paper_depth.md)
LATE_WINDOW = (0.015, 0.020)
# travels [m] within which a long run's failures are counted again (how the count
# moves from the 20 mm runs' window to Table 3's 300 mm)
COUNT_WITHIN = (0.02, 0.1)


def long_run(r, mode, y_fail):
    """A run beyond 20 mm: n_t/n_s at full failure within each COUNT_WITHIN travel,
    the mean F over each of the paper's post-peak intervals the record covers and
    the record's maximum, as postproc/summary.py takes them."""
    out = {}
    for w in COUNT_WITHIN:
        n_t, n_s, _ = shear_strength.failure_mode_ratio(mode, np.where(y_fail <= w, y_fail, np.nan))
        out[f"n_t_within_{w * 1e3:.0f}mm"], out[f"n_s_within_{w * 1e3:.0f}mm"] = int(n_t), int(n_s)
    y, F = r.force_y, r.force_F
    for a, b in summary.POST_PEAK_INTERVALS:
        if y[-1] >= b:
            out[f"F_mean_{a * 1e3:.0f}_{b * 1e3:.0f}mm_kN_per_m"] = loads.mean_load(y, F, a, b) / 1e3
    F_max, y_max = loads.record_maximum(y, F)
    out.update(F_record_max_kN_per_m=F_max / 1e3, y_I_record_max_mm=y_max * 1e3)
    return out


def measure(path):
    r = results.load(path)
    b = r.bonds
    n_t, n_s, ratio = shear_strength.failure_mode_ratio(b["mode"], b["y_I_fail"])
    n_t0, n_s0, ratio0 = shear_strength.initiation_side_ratio(b["y_I_split"], b.get("split_tn"))
    y_fail = np.asarray(b["y_I_fail"], dtype=float)
    extra = long_run(r, np.asarray(b["mode"]), y_fail) if r.force_y[-1] > 1.5 * COUNT_WITHIN[0] else {}
    return dict(file=os.path.basename(path), ridge=int(r.attrs["seed"]), mu=float(r.mu),
                tau_cr_kPa=float(r.tau_cr) / 1e3, force_direction=r.force_direction,
                n_split=int(np.count_nonzero(np.isfinite(np.asarray(b["y_I_split"], dtype=float)))),
                n_failed=int(np.count_nonzero(np.isfinite(y_fail))),
                n_t=int(n_t), n_s=int(n_s), nt_ns=float(ratio), n_t_init=int(n_t0), n_s_init=int(n_s0),
                nt_ns_init=float(ratio0), y_I_end_mm=float(r.force_y[-1]) * 1e3,
                F_15_20mm_mean_kN_per_m=loads.mean_load(r.force_y, r.force_F, *LATE_WINDOW) / 1e3,
                **measures(path), **extra)


def travel_mm(row):
    """The travel a run was made for (20 or 300 mm: Figs. 8-15 or Table 3)."""
    return float(round(row["y_I_end_mm"]))


SETTLE_PROCEDURE = ("settle_bonds", "settle_indenter", "side_walls")


def settle_procedure(row):
    """(settle_bonds, settle_indenter, side_walls) of a row; a row measured before a settle
    parameter existed was made with its default, as measures() reads it."""
    return tuple(str(row.get(k, P.REGISTRY[k].default)) for k in SETTLE_PROCEDURE)


def key(row):
    """One row per line: a run that settled another way (bonds, indenter, side walls) is another line,
    not a remeasurement (deep_ridge1_mu0.3_tau5k_wc_ih once replaced deep_ridge1_mu0.3_tau5k_wc)."""
    return ((row["ridge"], row["mu"], row["tau_cr_kPa"], travel_mm(row), DIRECTIONS.index(row["force_direction"]))
            + settle_procedure(row))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--measure", nargs="+", metavar="RESULT.h5", required=True, help="finished runs")
    a = ap.parse_args(argv)
    rows = {}
    if os.path.exists(OUT_JSON):
        with open(OUT_JSON) as f:
            rows = {key(r): r for r in json.load(f)["runs"]}
    for path in a.measure:
        row = measure(path)
        rows[key(row)] = row
        print(f"ridge {row['ridge']} mu {row['mu']:g} tau_cr {row['tau_cr_kPa']:g} kPa to {travel_mm(row):g} mm "
              f"{row['force_direction']:14s} "
              f"first peak {row['first_peak_kN_per_m']:.1f} kN/m at {row['y_I_first_peak_mm']:.2f} mm, "
              f"alpha {row['alpha_mean_1_20mm_deg']:.1f} +- {row['alpha_sd_1_20mm_deg']:.1f} deg, "
              f"n_t/n_s {row['n_t']}/{row['n_s']} at full failure, {row['n_t_init']}/{row['n_s_init']} at "
              f"initiation", flush=True)
        if "F_record_max_kN_per_m" in row:
            print("  " + ", ".join(f"{row[f'n_t_within_{w * 1e3:.0f}mm']}/{row[f'n_s_within_{w * 1e3:.0f}mm']} "
                                   f"within {w * 1e3:.0f} mm" for w in COUNT_WITHIN)
                  + "; mean F " + ", ".join(f"{row[k]:.1f}" for k in row if k.startswith("F_mean_"))
                  + f" kN/m; record max {row['F_record_max_kN_per_m']:.1f} kN/m at {row['y_I_record_max_mm']:.1f} mm",
                  flush=True)
    os.makedirs(os.path.dirname(OUT_JSON), exist_ok=True)
    with open(OUT_JSON + ".part", "w") as f:
        json.dump(dict(machine=machine.processor(), table_3=TABLE_3, runs=[rows[k] for k in sorted(rows)]),
                  f, indent=1, default=float)
    os.replace(OUT_JSON + ".part", OUT_JSON)
    print(f"wrote {OUT_JSON}")


if __name__ == "__main__":
    main()
