"""The pairs behind R(F, F_d) (Fig. 20, docs/model.md §5), as rows that travel.

R(F, F_d) pairs each snapshot at y_I = 20...150 mm (the paper's Fig. 20) with the
run's mean load over y_I ± 5 mm (F̄) and the displaced rubble's buoyant load
F_d(K) (eq 14). The pairs are kept from 20 mm to the end of the record, and R
reads those up to 150 mm (in_fig20). Both need
the run file: the displacement field of each snapshot and the force record. A
study longer than one machine's life (docs/postproc.md, "Runs known by their
rows") keeps its runs' summary rows in summary.csv; the pairs are kept beside it,
in fd_pairs.csv, one row per (run, snapshot), so that R, too, is computed over
every run of the study and not only over the files at hand.

A pair is stored as measured (F̄, the single sample F(y_I) that R was once
computed from, F_d at the two K of R) with 17 significant digits, so that R from
stored pairs is R from the files.
"""
import csv
import os

import numpy as np

from icerubble.files.output_path import whole_file

from . import displaced_area as dA
from . import loads

FILE_NAME = "fd_pairs.csv"           # beside summary.csv
R_K = (0.45, 0.9)                    # the K of R(F, F_d) in docs/model.md §5
Y_MIN = 20e-3                        # m: pairs are kept from the first travel of Fig. 20 on
SNAPSHOT_SLACK = 0.5e-3              # m: a snapshot is taken at the first step past its travel
COLUMNS = ("file", "run_id", "y_I_mm", "F_mean_kN_per_m", "F_sample_kN_per_m") + tuple(
    f"F_d_K{K:g}_kN_per_m" for K in R_K)


def f_d_column(K):
    if K not in R_K:
        raise ValueError(f"K {K:g}: stored pairs hold F_d at K in {R_K} only")
    return f"F_d_K{K:g}_kN_per_m"


def of_run(run, file, run_id, y_min=Y_MIN):
    """The run's pairs, one per snapshot from y_min on within its record (the
    snapshot's own y_I): dicts with COLUMNS."""
    ys = [s.y_I for s in run.snapshots if y_min - SNAPSHOT_SLACK <= s.y_I <= run.force_y[-1]]
    F_d = dA.displaced_loads(run, R_K, ys)   # each snapshot's field read once for both K
    out = []
    for y_I, F_d_K in zip(ys, F_d):
        p = {"file": file, "run_id": run_id, "y_I_mm": y_I * 1e3,
             "F_mean_kN_per_m": dA.paired_load(run, y_I) / 1e3,
             "F_sample_kN_per_m": loads.load_at(run.force_y, run.force_F, y_I) / 1e3}
        for K, f in zip(R_K, F_d_K):
            p[f_d_column(K)] = float(f) / 1e3
        out.append(p)
    return out


def in_fig20(pair):
    """Whether a pair lies within Fig. 20's travels, y_I = 20...150 mm (the paper's
    R: "y_I = {20, 30, 40, ..., 150} mm ... for each simulation")."""
    lo, hi = dA.FIG20_TRAVELS[0], dA.FIG20_TRAVELS[-1]
    return lo - SNAPSHOT_SLACK <= pair["y_I_mm"] * 1e-3 <= hi + SNAPSHOT_SLACK


def write_csv(pairs, path):
    with whole_file(path, newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=COLUMNS)
        w.writeheader()
        for p in pairs:
            w.writerow({k: (p[k] if k in ("file", "run_id") else f"{p[k]:.17g}") for k in COLUMNS})


def beside(summary_path):
    """The fd_pairs.csv that belongs to a summary.csv: in its folder."""
    return os.path.join(os.path.dirname(os.path.abspath(summary_path)), FILE_NAME)


def read(path):
    """{(file, run_id): [pair, ...]} of an fd_pairs.csv. ValueError naming the file,
    the line and what is wrong."""
    with open(path, newline="") as fh:
        reader = csv.DictReader(fh)
        absent = [c for c in COLUMNS if c not in (reader.fieldnames or ())]
        if absent:
            raise ValueError(f"{path!r}: not an fd_pairs.csv of this version: column(s) {', '.join(absent)} absent")
        out = {}
        for k, raw in enumerate(reader, start=2):
            p = {"file": raw["file"], "run_id": raw["run_id"]}
            for c in COLUMNS[2:]:
                try:
                    p[c] = float(raw[c])
                except (TypeError, ValueError):
                    raise ValueError(f"{path!r}, line {k}: column {c!r} holds {raw[c]!r}, not a number") from None
            out.setdefault((p["file"], p["run_id"]), []).append(p)
    return out

