"""Runs known by their summary rows only: rows of a summary.csv that an earlier
make_figures (or `icerubble summary`) wrote from run files no longer at hand.

A study longer than one machine's life (docs/study_paper_depth.md: ~50 lines of
30-70 min of one core each, on machines not kept between sessions) cannot hold
all its run files in one folder. Its per-run scalars can travel: each row of
summary.csv is what Tables 2-3 and Figs. 8, 10, 11, 13-15 read of a run
(postproc/summary.py). So `icerubble figures --stored-rows CSV` and `icerubble
compare --stored-rows CSV` take such rows beside the runs of RESULTS_DIR; the
figures drawn from records (F-y_I, failure planes, u_y fields: Figs. 6, 7, 9,
12, 16-20) use the run files only, and MISSING.md names what the stored rows
could not give. R(F, F_d) needs a pair of numbers per snapshot, and those travel
too: an fd_pairs.csv beside the summary.csv (postproc/fd_pairs.py) gives each
stored run its pairs.

What is stored is a measurement, and is taken as it was made: a row measured
through other bond points than this call's (--bond-points) is refused, since
alpha, A_p and tau^(3) cannot be measured again without the run's file. The
strengths that depend on this call's choices are computed again from the row:
tau^(2) from F^m and the plug force of this call.
"""
import csv
import os
from dataclasses import dataclass

import numpy as np

from . import fd_pairs as fd
from . import shear_strength, summary
from .catalog import Missing

TEXT_COLUMNS = ("file", "scene", "ridge", "model", "force_direction", "bond_points", "missing",
                "run_id", "code_version")
# columns a row must have; the later ones (run_id, code_version, F_b_cylinder)
# were added after the first summaries were written and may be absent
OPTIONAL_COLUMNS = ("run_id", "code_version", "F_b_cylinder_kN_per_m")
REQUIRED_COLUMNS = tuple(c for c in summary.COLUMNS if c not in OPTIONAL_COLUMNS)


@dataclass
class StoredRun:
    """A run by its summary row: what a Catalog groups by (ridge, mu, tau_cr,
    variant) and its row. Anything drawn from records raises Missing."""
    row: dict
    source: str                 # the summary.csv it was read from
    fd_pairs: list = None       # its (F̄, F_d) pairs (postproc/fd_pairs.py); None: none stored

    @property
    def path(self):
        return self.row["file"]

    @property
    def name(self):
        return os.path.basename(self.row["file"])

    ridge = property(lambda self: self.row["ridge"])
    scene = property(lambda self: self.row["scene"])
    model = property(lambda self: self.row["model"])
    force_direction = property(lambda self: self.row["force_direction"])
    mu = property(lambda self: self.row["mu"])
    tau_cr = property(lambda self: self.row["tau_cr_kPa"] * 1e3)
    keel_depth = property(lambda self: self.row["keel_depth_m"])
    indenter_width = property(lambda self: self.row["indenter_width_m"])
    porosity = property(lambda self: self.row["porosity"])
    travel = property(lambda self: self.row["y_I_end_mm"] * 1e-3)

    def with_strengths(self, plug_force):
        return row_with_strengths(self.row, plug_force)

    def __getattr__(self, what):
        # only reached for what a StoredRun does not have: the run file's records
        if what.startswith("__"):
            raise AttributeError(what)
        raise Missing(f"{self.name}: known here by its summary row only ({self.source}); "
                      f"its {what} is in the run file")


def _value(column, text):
    if column in TEXT_COLUMNS:
        return text
    if text == "":
        return np.nan
    try:
        return float(text)
    except ValueError:
        raise ValueError(f"column {column!r} holds {text!r}, not a number") from None


def plug_force_of(row):
    """F_b [kN/m] of the cylindrical plug w_I h (eq 13): the row's own, else from
    F_b(A_p) at 20 mm, since eq 13 is linear in the area (rows written before
    the column existed)."""
    fb = row.get("F_b_cylinder_kN_per_m", np.nan)
    if np.isfinite(fb):
        return fb
    return row["F_b_Ap_20mm_kN_per_m"] * row["indenter_width_m"] * row["keel_depth_m"] / row["A_p_20mm_m2"]


def row_with_strengths(row, plug_force):
    """The row with Table 2's strengths computed again: tau^(2) with ``plug_force``
    [N/m] (None: the cylindrical plug's own F_b, as `icerubble compare` takes it)."""
    out = dict(row)
    pf = plug_force_of(row) * 1e3 if plug_force is None else plug_force
    t1, t2, t3 = shear_strength.three_strengths(row["F_m_kN_per_m"] * 1e3, row["keel_depth_m"], pf,
                                                row["F_b_Ap_20mm_kN_per_m"] * 1e3)
    out.update(tau1_kPa=t1 / 1e3, tau2_kPa=t2 / 1e3, tau3_kPa=t3 / 1e3)
    return out


def read(path, bond_points):
    """StoredRun per row of the summary.csv at ``path``, with its (F̄, F_d) pairs
    where an fd_pairs.csv lies beside it. Raises ValueError naming the file and
    what is wrong: not a file, a column absent, a cell not a number, rows
    measured through other bond points than ``bond_points``."""
    if not os.path.isfile(path):
        raise ValueError(f"--stored-rows {path!r}: no such file (a summary.csv of `icerubble figures` "
                         "or `icerubble summary`)")
    with open(path, newline="") as fh:
        reader = csv.DictReader(fh)
        absent = [c for c in REQUIRED_COLUMNS if c not in (reader.fieldnames or ())]
        if absent:
            raise ValueError(f"--stored-rows {path!r}: not a summary.csv of this version: "
                             f"column(s) {', '.join(absent)} absent")
        out = []
        for k, raw in enumerate(reader, start=2):
            try:
                row = {c: _value(c, raw.get(c) or "") for c in summary.COLUMNS}
            except ValueError as exc:
                raise ValueError(f"--stored-rows {path!r}, line {k}: {exc}") from None
            if row["bond_points"] != bond_points:
                raise ValueError(f"--stored-rows {path!r}, line {k}: measured through "
                                 f"{row['bond_points']!r} bond points, and this call reads {bond_points!r} "
                                 "(--bond-points): alpha and A_p cannot be measured again without the run file")
            out.append(StoredRun(row=row, source=path))
    pairs_path = fd.beside(path)
    if os.path.isfile(pairs_path):
        pairs = fd.read(pairs_path)
        for s in out:   # a run none are stored for (a row older than the file) stays None
            s.fd_pairs = pairs.get((s.row["file"], s.row["run_id"]))
    return out


def pairs_of(run, file="", run_id=""):
    """A run's (F̄, F_d) pairs (postproc/fd_pairs.py): a stored run's own (None
    where none are stored), else measured from its file under ``file`` and ``run_id``."""
    if isinstance(run, StoredRun):
        return run.fd_pairs
    return fd.of_run(run, file, run_id)


def read_all(paths, bond_points):
    return [s for p in paths or () for s in read(p, bond_points)]


def travel(run):
    """The run's travel [m], from its record or its row."""
    return run.travel if isinstance(run, StoredRun) else (float(run.force_y[-1]) if len(run.force_y) else 0.0)


def add_option(parser):
    """--stored-rows CSV (repeatable), the same on every command that takes it."""
    parser.add_argument("--stored-rows", action="append", metavar="CSV",
                        help="a summary.csv of runs whose files are not at hand (made on another machine): "
                             "their rows join the tables and the figures drawn from per-run values; may be "
                             "given more than once (docs/postproc.md, 'Runs known by their rows')")
