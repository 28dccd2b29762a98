"""The side-by-side table keeps what must not be mixed apart: one table per
model and force direction (eq 11's two forms are compared, never pooled)."""
from postproc import paper_comparison
from tests.postproc import synthetic


def test_each_force_direction_gets_its_own_table(tmp_path):
    for direction in ("paper", "work_conjugate"):
        for ridge in (1, 2):
            for mu in (0.05, 0.3):
                synthetic.write_run(str(tmp_path / f"r{ridge}_mu{mu}_{direction}.h5"), ridge, mu, 50e3,
                                    travel_end=0.04, force_direction=direction)
    rows, runs = paper_comparison.rows_and_runs(str(tmp_path))
    assert len(rows) == 8
    text = paper_comparison.tables_by_variant(rows, runs)
    heads = [ln for ln in text.splitlines() if ln.startswith("### ")]
    assert heads == ["### fem-dem, force_direction = paper", "### fem-dem, force_direction = work_conjugate"]
    # each table counts its own four runs, not all eight
    assert text.count("Runs: 4 (2 ridges") == 2
    # a folder of one variant: its table alone, no heading
    paper = [i for i, r in enumerate(rows) if r["force_direction"] == "paper"]
    one = paper_comparison.tables_by_variant([rows[i] for i in paper], [runs[i] for i in paper])
    assert one.startswith("Runs: 4 (2 ridges") and "###" not in one


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
