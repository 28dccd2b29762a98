"""Runs known by their summary rows only (postproc/stored_rows.py): a study whose
run files were made on machines not kept gives the same tables and per-run
figures from its stored rows as from the files themselves; what needs records
says so; a row measured otherwise than asked is refused."""
import csv
import os
import re
import shutil

import numpy as np
import pytest

from postproc import failure_plane, make_figures, paper_comparison, shear_strength, stored_rows, summary
from postproc.plotting import plt
from tests.postproc import synthetic

TAUS = (5e3, 50e3, 100e3)


@pytest.fixture(scope="module")
def halves(tmp_path_factory):
    """A study in two folders, ridge 1 in a/ and ridge 2 in b/, and the whole
    study (both, found recursively) in their parent; a_out/ holds what
    make_figures made of a/ alone, its summary.csv the rows that travel."""
    base = tmp_path_factory.mktemp("study")
    synthetic.write_set(str(base / "runs" / "a"), ridges=("1",), tau_crs=TAUS, travel_end=0.04)
    synthetic.write_set(str(base / "runs" / "b"), ridges=("2",), tau_crs=TAUS, travel_end=0.04)
    assert make_figures.main([str(base / "runs" / "a"), "-o", str(base / "a_out")]) == 0
    return base


def _numbers(path):
    """The table's numbers ('a ± b' gives a and b, '–' NaN), by quantity."""
    with open(path) as fh:
        rows = list(csv.reader(fh))
    return {r[0]: [float(x) for c in r[1:] for x in (re.findall(r"-?\d+(?:\.\d+)?", c) or ["nan"])]
            for r in rows[1:]}


def test_tables_from_stored_rows_equal_those_from_the_run_files(halves):
    """Ridge 1's runs made 'elsewhere' (their summary.csv kept), ridge 2's here:
    Tables 2-3, the per-run values of Figs. 8, 10, 11, 13-15 and the summary
    written equal the whole study's from its files, to the CSV's 6 digits (the
    tables print 2 decimals: within one unit of the last)."""
    whole, a_out, b_out = halves / "whole", halves / "a_out", halves / "b_out"
    assert make_figures.main([str(halves / "runs"), "-o", str(whole)]) == 0
    assert make_figures.main([str(halves / "runs" / "b"), "-o", str(b_out),
                              "--stored-rows", str(a_out / "summary.csv")]) == 0
    for stem in ("table2_shear_strength", "table3_ratios"):
        got, want = _numbers(b_out / f"{stem}.csv"), _numbers(whole / f"{stem}.csv")
        assert got.keys() == want.keys()
        for q in want:
            np.testing.assert_allclose(got[q], want[q], atol=0.011, equal_nan=True, err_msg=f"{stem}: {q}")
    # the summary written holds every run, so that the next call can take it again
    with open(b_out / "summary.csv") as fh:
        merged = {os.path.basename(r["file"]): r for r in csv.DictReader(fh)}
    with open(whole / "summary.csv") as fh:
        full = {os.path.basename(r["file"]): r for r in csv.DictReader(fh)}
    assert merged.keys() == full.keys() and len(full) == 12
    for name, r in full.items():
        for k in ("F_m_kN_per_m", "alpha_mean_1_20mm_deg", "A_p_mean_1_20mm_m2", "tau2_kPa", "nt_ns"):
            np.testing.assert_allclose(float(merged[name][k] or "nan"), float(r[k] or "nan"), rtol=1e-5,
                                       equal_nan=True, err_msg=f"{name}: {k}")
    # made from rows: Figs. 8, 10, 11, 13-15; drawn from records only from the files here
    for stem in ("fig08_peak_vs_mu", "fig10_peak_vs_tau", "fig11_peak_ratio_mu", "fig13_alpha_vs_tau",
                 "fig14_plug_area", "fig15_forces_vs_plug", "fig06_force_records"):
        assert (b_out / f"{stem}.png").exists(), stem
    text = (b_out / "MISSING.md").read_text()
    assert "6 stored row(s) from" in text and "6 run(s) known by their stored rows only" in text
    assert "ridge1_mu0.05_tau50kPa.h5" in text and "ERROR" not in text
    # figures not made (records missing) were closed too: a long study's make_figures keeps none open
    assert not plt.get_fignums()


def test_of_equal_travels_the_run_file_is_kept_over_its_stored_row(halves, tmp_path):
    a_out = halves / "a_out"
    out = tmp_path / "again"
    assert make_figures.main([str(halves / "runs" / "a"), "-o", str(out),
                              "--stored-rows", str(a_out / "summary.csv")]) == 0
    text = (out / "MISSING.md").read_text()
    assert "known by their stored rows only" not in text
    assert text.count("duplicate run (ridge 1") == 6
    # each line says which of a name's two readings was kept: the file, not its row
    assert text.count(".h5, ignoring ") == 6 and text.count(".h5 (stored row)\n") == 6


def test_the_file_is_kept_where_its_row_rounds_its_travel_up():
    """A row keeps 6 significant digits: a run's travel of 20.008689541 mm is stored
    as 20.0087, longer than the file's own. Of the file (listed first) and its row
    the file must be kept, and a 300 mm run must still win (found at paper depth:
    the record figures had lost the files of runs at hand)."""
    file_travel = 0.020008689541296253
    row_travel = float(summary._fmt(file_travel * 1e3)) * 1e-3
    assert row_travel > file_travel
    items = [("file", file_travel), ("row", row_travel), ("other case", 0.02)]
    kept, dropped = shear_strength.longest_per_case(items, lambda i: i[0] == "other case", lambda i: i[1])
    assert kept == [("file", file_travel), ("other case", 0.02)] and dropped == [(items[1], items[0])]
    kept, _ = shear_strength.longest_per_case(items[:2] + [("300 mm", 0.300005)], lambda i: 0, lambda i: i[1])
    assert kept == [("300 mm", 0.300005)]


def test_alpha_pooled_from_run_means_equals_the_samples_pooled():
    """Fig. 13 pools the alpha samples of many runs; a row keeps a run's count, mean
    and sd only, and those give the pooled mean and sd exactly."""
    rng = np.random.default_rng(3)
    samples = [rng.normal(30, 8, n) for n in (1, 2, 7, 40)]
    parts = [(s.size,) + failure_plane.mean_sd(s) for s in samples] + [(0, np.nan, np.nan)]
    np.testing.assert_allclose(failure_plane.pooled_mean_sd(parts),
                               failure_plane.mean_sd(np.concatenate(samples)), rtol=1e-12)
    assert np.isnan(failure_plane.pooled_mean_sd([(1, 5.0, np.nan)])[1])
    assert np.isnan(failure_plane.pooled_mean_sd([(0, np.nan, np.nan)])[0])


def test_comparison_from_stored_rows_equals_the_files_R_by_their_stored_pairs(halves, tmp_path):
    """Every statistic of `icerubble compare` from ridge 1's stored rows and ridge 2's
    files equals the one from all files, R(F, F_d) too: its (F̄, F_d) pairs travel in
    the fd_pairs.csv beside the summary.csv. A summary.csv without one leaves ridge 1
    out of R, and the column says so."""
    a_out = halves / "a_out"
    stored = stored_rows.read(str(a_out / "summary.csv"), "split")
    assert all(s.fd_pairs for s in stored)   # every run reaches 40 mm: pairs at 20, 30, 40 mm
    (_, rows, runs), = paper_comparison.columns([str(halves / "runs" / "b")], ["b"], stored=stored)
    (_, rows_all, runs_all), = paper_comparison.columns([str(halves / "runs")], ["all"])
    assert len(rows) == len(runs) == 12
    got = {w: v for w, v, _ in paper_comparison.statistics(rows, runs)}
    want = {w: v for w, v, _ in paper_comparison.statistics(rows_all, runs_all)}
    assert got.keys() == want.keys() and any(w.startswith("R(") for w in want)
    for what in want:
        assert got[what] == want[what], what
    assert "6 of them known by stored summary rows only (in R by their stored (F̄, F_d) pairs)" in \
        paper_comparison.table(rows, runs)
    # the rows alone, without their pairs: R from ridge 2's files only
    alone = tmp_path / "alone"
    alone.mkdir()
    shutil.copy(a_out / "summary.csv", alone / "summary.csv")
    (_, rows_1, runs_1), = paper_comparison.columns([str(halves / "runs" / "b")], ["b"],
                                                    stored=stored_rows.read(str(alone / "summary.csv"), "split"))
    (_, rows_b, runs_b), = paper_comparison.columns([str(halves / "runs" / "b")], ["b"])
    R_1 = {w: v for w, v, _ in paper_comparison.statistics(rows_1, runs_1) if w.startswith("R(")}
    R_b = {w: v for w, v, _ in paper_comparison.statistics(rows_b, runs_b) if w.startswith("R(")}
    assert R_1 == R_b and R_1 != {w: v for w, v in want.items() if w.startswith("R(")}
    assert "6 of them known by stored summary rows only (not in R)" in paper_comparison.table(rows_1, runs_1)
    # a summary.csv made before the cylindrical plug's F_b had a column: tau^(2) from
    # F_b(A_p) at 20 mm, eq 13 being linear in the area, gives the same statistics
    old = str(tmp_path / "old.csv")
    _rewrite(str(a_out / "summary.csv"), old,
             lambda rows, f: ([{k: v for k, v in r.items() if k not in stored_rows.OPTIONAL_COLUMNS} for r in rows],
                              [k for k in f if k not in stored_rows.OPTIONAL_COLUMNS]))
    (_, rows_old, runs_old), = paper_comparison.columns([str(halves / "runs" / "b")], ["b"],
                                                        stored=stored_rows.read(old, "split"))
    got_old = {w: v for w, v, _ in paper_comparison.statistics(rows_old, runs_old)}
    assert [v for w, v in got_old.items() if "τ^(2)" in w] == [v for w, v in want.items() if "τ^(2)" in w]


def test_stored_rows_join_the_first_of_several_folders(halves):
    """`compare b a --stored-rows a_out/summary.csv`: the rows (ridge 1's) join b's
    column, which then equals the whole study's, and a's column is a's files alone,
    as in a call on a alone (the reduced study beside the paper-depth study's rows)."""
    stored = stored_rows.read(str(halves / "a_out" / "summary.csv"), "split")
    (nb, rows_b, runs_b), (na, rows_a, runs_a) = paper_comparison.columns(
        [str(halves / "runs" / "b"), str(halves / "runs" / "a")], ["b", "a"], stored=stored)
    assert (nb, na) == ("b", "a") and len(rows_b) == 12 and len(rows_a) == 6
    (_, rows_all, runs_all), = paper_comparison.columns([str(halves / "runs")], ["all"])
    (_, rows_1, runs_1), = paper_comparison.columns([str(halves / "runs" / "a")], ["a"])
    stats = lambda rows, runs: {w: v for w, v, _ in paper_comparison.statistics(rows, runs)}
    assert stats(rows_b, runs_b) == stats(rows_all, runs_all)
    assert stats(rows_a, runs_a) == stats(rows_1, runs_1)
    assert not any(isinstance(r, stored_rows.StoredRun) for r in runs_a)


def _rewrite(src, dst, edit):
    with open(src) as fh:
        rows = list(csv.DictReader(fh))
    fields = list(rows[0].keys())
    rows, fields = edit(rows, fields)
    with open(dst, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=fields)
        w.writeheader()
        w.writerows(rows)


def test_rows_that_cannot_serve_are_refused_with_the_reason(halves, tmp_path):
    a_out = halves / "a_out"
    good = str(a_out / "summary.csv")
    bad_points, no_column, not_number = (str(tmp_path / n) for n in ("failed.csv", "short.csv", "text.csv"))
    _rewrite(good, bad_points, lambda rows, f: ([{**r, "bond_points": "failed"} for r in rows], f))
    _rewrite(good, no_column, lambda rows, f: ([{k: v for k, v in r.items() if k != "F_m_kN_per_m"} for r in rows],
                                               [k for k in f if k != "F_m_kN_per_m"]))
    _rewrite(good, not_number, lambda rows, f: ([{**r, "mu": "low"} for r in rows], f))
    for path, why in ((bad_points, "measured through 'failed' bond points, and this call reads 'split'"),
                      (no_column, "column(s) F_m_kN_per_m absent"),
                      (not_number, "line 2: column 'mu' holds 'low', not a number"),
                      (str(tmp_path / "none.csv"), "no such file")):
        with pytest.raises(ValueError, match=why.replace("(", r"\(").replace(")", r"\)")):
            stored_rows.read(path, "split")
    out = tmp_path / "never"
    with pytest.raises(ValueError, match="no such file"):
        make_figures.main([str(halves / "runs" / "b"), "-o", str(out), "--stored-rows", str(tmp_path / "x.csv")])
    assert not out.exists()   # refused before anything was written


def test_a_stored_run_has_no_records():
    row = {c: np.nan for c in stored_rows.REQUIRED_COLUMNS}
    row.update(file="runs/x.h5", ridge="1")
    s = stored_rows.StoredRun(row=row, source="s.csv")
    with pytest.raises(make_figures.Missing, match=r"x.h5: known here by its summary row only \(s.csv\); "
                                                   "its force_y is in the run file"):
        s.force_y
