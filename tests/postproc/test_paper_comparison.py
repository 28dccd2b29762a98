"""The side-by-side table keeps what must not be mixed apart: a column per
folder, model and force direction (eq 11's two forms are compared, never
pooled), each column's values those of its runs alone."""
import pytest

from postproc import paper_comparison
from tests.postproc import synthetic


def _cells(text, statistic):
    """The cells of the table row whose statistic is `statistic`."""
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells[0] == statistic:
            return cells[1:]
    raise AssertionError(f"no row {statistic!r} in\n{text}")


def test_each_force_direction_gets_its_own_column(tmp_path):
    for direction in ("paper", "work_conjugate"):
        for ridge in (1, 2):
            for mu in (0.05, 0.3):
                synthetic.write_run(str(tmp_path / f"r{ridge}_mu{mu}_{direction}.h5"), ridge, mu, 50e3,
                                    travel_end=0.04, force_direction=direction)
    cols = paper_comparison.columns([str(tmp_path)], ["deep"])
    names = [name for name, _, _ in cols]
    assert names == ["deep (fem-dem, force_direction = paper)", "deep (fem-dem, force_direction = work_conjugate)"]
    text = paper_comparison.comparison(cols)
    assert text.splitlines()[0] == "| statistic | " + " | ".join(names) + " | paper |"
    # each column counts its own four runs, not all eight
    assert text.count("Runs: 4 (2 ridges") == 2
    # a column's cell is what its runs alone give: the table of that variant
    paper_rows, paper_runs = cols[0][1], cols[0][2]
    alone = paper_comparison.table(paper_rows, paper_runs)
    assert alone.startswith("Runs: 4 (2 ridges") and "###" not in alone
    for what, ours, _ in paper_comparison.statistics(paper_rows, paper_runs):
        assert _cells(text, what)[0] == ours == _cells(alone, what)[0]


def test_folders_side_by_side_with_a_dash_where_a_column_has_no_runs(tmp_path):
    """A deep study at tau_cr 50 and 100 kPa beside a reduced one at 5 and 50 kPa:
    the deep column has no tau_cr 5 kPa row to give, the reduced none at 100,
    and the rows keep the paper's order of tau_cr."""
    deep, reduced = tmp_path / "deep", tmp_path / "reduced"
    deep.mkdir(), reduced.mkdir()
    for ridge in (1, 2):
        for tau in (50e3, 100e3):
            synthetic.write_run(str(deep / f"d{ridge}_{tau:g}.h5"), ridge, 0.05, tau, travel_end=0.04)
        for tau in (5e3, 50e3):
            synthetic.write_run(str(reduced / f"r{ridge}_{tau:g}.h5"), ridge, 0.05, tau, travel_end=0.04)
    text = paper_comparison.comparison(paper_comparison.columns([str(deep), str(reduced)], ["deep", "reduced"]))
    assert text.splitlines()[0] == "| statistic | deep | reduced | paper |"
    five = _cells(text, "Table 3 n_t/n_s (mode at full failure), τ_cr 5 kPa")
    assert five[0] == "—" and five[1] != "—" and five[2] == "0.38 ± 0.14"
    fifty = _cells(text, "Table 3 n_t/n_s (mode at full failure), τ_cr 50 kPa")
    assert "—" not in fifty[:2]
    hundred = _cells(text, "Table 3 n_t/n_s (mode at full failure), τ_cr 100 kPa")
    assert hundred[0] != "—" and hundred[1] == "—"
    table3 = [ln.split("|")[1].strip() for ln in text.splitlines() if ln.startswith("| Table 3")]
    assert table3 == [f"Table 3 n_t/n_s (mode at full failure), τ_cr {t} kPa" for t in (5, 50, 100)]
    assert "- **deep**: Runs: 4 (2 ridges" in text and "- **reduced**: Runs: 4 (2 ridges" in text


def test_scenes_found_in_one_folder_are_two_columns(tmp_path):
    """A folder holding the reduced study and, below it, the paper-depth one: a
    column per scene, each describing its own two ridges."""
    (tmp_path / "deep").mkdir()
    for ridge in (1, 2):
        synthetic.write_run(str(tmp_path / f"s{ridge}.h5"), f"small-{ridge}", 0.05, 50e3, travel_end=0.04,
                            scene="small")
        synthetic.write_run(str(tmp_path / "deep" / f"d{ridge}.h5"), f"deep-{ridge}", 0.05, 50e3, travel_end=0.04,
                            scene="deep")
    cols = paper_comparison.columns([str(tmp_path)], ["runs"])
    assert [name for name, _, _ in cols] == ["runs (deep, fem-dem, force_direction = paper)",
                                             "runs (small, fem-dem, force_direction = paper)"]
    for (_, rows, _), scene in zip(cols, ("deep", "small")):
        assert sorted(r["ridge"] for r in rows) == [f"{scene}-1", f"{scene}-2"]
    assert paper_comparison.comparison(cols).count("Runs: 2 (2 ridges") == 2


def test_labels_must_match_the_folders(tmp_path, capsys):
    with pytest.raises(SystemExit):
        paper_comparison.main([str(tmp_path), str(tmp_path), "--label", "one"])
    assert "--label given 1 times for 2 folders" in capsys.readouterr().err
    with pytest.raises(ValueError, match="no such folder"):
        paper_comparison.main([str(tmp_path / "absent")])


def test_a_case_run_to_two_travels_counts_once_by_the_longer(tmp_path):
    """The same case (ridge, mu, tau_cr, direction) to 30 and to 60 mm: one row, the
    60 mm run's; the same case in the other direction is another case."""
    synthetic.write_run(str(tmp_path / "a.h5"), 1, 0.05, 50e3, travel_end=0.03)
    synthetic.write_run(str(tmp_path / "a_long.h5"), 1, 0.05, 50e3, travel_end=0.06)
    synthetic.write_run(str(tmp_path / "a_wc.h5"), 1, 0.05, 50e3, travel_end=0.03, force_direction="work_conjugate")
    rows, runs = paper_comparison.rows_and_runs(str(tmp_path))
    assert len(rows) == len(runs) == 2
    paper = next(r for r in rows if r["force_direction"] == "paper")
    assert paper["file"].endswith("a_long.h5") and abs(paper["y_I_end_mm"] - 60.0) < 1.0


def test_every_statistic_of_model_md_section_5_is_given(tmp_path):
    """Table 3's tau ratios per ridge, F^m over the mean load of 150-300 mm (runs that
    reach 300 mm only), alpha and A_p by tau_cr and R at K 0.9, each the value its
    rows give by hand."""
    for ridge in (1, 2):
        for mu in (0.05, 0.3):
            synthetic.write_run(str(tmp_path / f"r{ridge}_mu{mu}.h5"), ridge, mu, 50e3, travel_end=0.3)
    synthetic.write_run(str(tmp_path / "short.h5"), 3, 0.3, 5e3, travel_end=0.04)
    rows, runs = paper_comparison.rows_and_runs(str(tmp_path))
    S = {what: ours for what, ours, _ in paper_comparison.statistics(rows, runs)}
    by = {(r["ridge"], r["mu"], r["tau_cr_kPa"]): r for r in rows}
    for key, label in (("tau1", "τ^(1)"), ("tau2", "τ^(2)"), ("tau3", "τ^(3)")):
        q = [by[(k, 0.3, 50.0)][key + "_kPa"] / by[(k, 0.05, 50.0)][key + "_kPa"] for k in ("1", "2")]
        assert S[f"Table 3 {label}(μ 0.3)/{label}(μ 0.05), τ_cr 50 kPa (per ridge)"] == paper_comparison._pm(q)
    # the 40 mm run has no 150-300 mm mean: only the four 300 mm runs count
    late = [by[(k, 0.05, 50.0)]["F_m_kN_per_m"] / by[(k, 0.05, 50.0)]["F_mean_150_300mm_kN_per_m"] for k in ("1", "2")]
    assert S["F^m / mean F over y_I 150-300 mm, μ 0.05"].startswith(paper_comparison._pm(late))
    late = [by[(k, 0.3, 50.0)]["F_m_kN_per_m"] / by[(k, 0.3, 50.0)]["F_mean_150_300mm_kN_per_m"] for k in ("1", "2")]
    assert S["F^m / mean F over y_I 150-300 mm, μ 0.3"].startswith(paper_comparison._pm(late) + ";")
    a5 = [by[("3", 0.3, 5.0)]["alpha_mean_1_20mm_deg"]]
    assert S["α over y_I 1-20 mm, τ_cr 5 kPa [°] (run means)"] == paper_comparison._pm(a5, 0)
    assert S["A_p over y_I 1-20 mm, τ_cr 50 kPa [m²] (run means)"] == paper_comparison._pm(
        [r["A_p_mean_1_20mm_m2"] for r in rows if r["tau_cr_kPa"] == 50.0], 0)
    assert any(w.startswith("R(F̄, F_d(K 0.9))") for w in S)
    assert not any("(μ 0.3)/" in w and "τ_cr 5 kPa" in w for w in S)   # ridge 3 has no μ 0.05 run
