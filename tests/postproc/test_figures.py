"""postproc.make_figures on synthetic result folders: every promised file from a full
set; a partial set reports what is missing and why."""
import csv
import os

import pytest

from postproc import make_figures

from tests.postproc import synthetic


@pytest.fixture(scope="module")
def full_set(tmp_path_factory):
    d = tmp_path_factory.mktemp("full")
    synthetic.write_set(str(d), ridges=("1", "2"), mus=(0.05, 0.3), tau_crs=(5e3, 12.5e3, 25e3, 50e3, 100e3))
    return str(d)


def test_full_set_makes_every_promised_file(full_set, tmp_path, capsys):
    out = str(tmp_path / "out")
    assert make_figures.main([full_set, "-o", out]) == 0
    for path in make_figures.promised_files(out):
        assert os.path.getsize(path) > 0, path
    missing = open(os.path.join(out, "MISSING.md")).read()
    assert "nothing missing" in missing and "ERROR" not in missing
    with open(os.path.join(out, "summary.csv")) as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 20
    # n_t/n_s recovered from the file: the synthetic modes are drawn to a known ratio
    # up to rounding of the tensile count (one bond point out of ~70: < 0.1 in the ratio)
    for r in rows:
        assert abs(float(r["nt_ns"]) - synthetic.nt_ns_target(float(r["tau_cr_kPa"]) * 1e3)) < 0.1
        # and the initiation side from /bonds/split_tn, ~105 split points: < 0.07 in the ratio
        assert abs(float(r["nt_ns_init"]) - synthetic.nt_ns_init_target(float(r["tau_cr_kPa"]) * 1e3)) < 0.1
        assert r["bond_points"] == "split"
    table3 = open(os.path.join(out, "table3_ratios.md")).read()
    assert "at initiation" in table3 and "fully failed / split" in table3


def test_partial_set_reports_what_is_missing(tmp_path, capsys):
    d = tmp_path / "runs"
    d.mkdir()
    synthetic.write_run(str(d / "r1_a.h5"), "1", 0.05, 50e3, snapshots=False, travel_end=0.1)
    synthetic.write_run(str(d / "r1_b.h5"), "1", 0.05, 5e3, travel_end=0.1)
    synthetic.write_run(str(d / "busy.h5"), "2", 0.05, 50e3, travel_end=0.02, leave_part=True)
    synthetic.write_run(str(d / "broken.h5"), "3", 0.05, 50e3, travel_end=0.02, complete=False)
    out = tmp_path / "out"
    assert make_figures.main([str(d), "-o", str(out)]) == 0
    text = (out / "MISSING.md").read_text()
    assert "busy.h5.part: still being written" in text
    assert "broken.h5' is incomplete (root attribute complete != 1)" in text
    assert "Fig. 11: not made" in text and "mu = 0.3" in text            # one mu only
    for n in (16, 17, 19):
        assert f"Fig. {n}: not made" in text and "/snapshots absent" in text
    assert "Fig. 18: not made" in text
    # Fig. 20 (b) uses the 5 kPa run's snapshots; only panel (a) (50 kPa) is empty
    assert "Fig. 20: not made" not in text and "fig20 (a)" in text
    assert "fig09: tau_cr = 12.5, 25 kPa missing" in text
    assert "ERROR" not in text
    # what can be made is made
    for stem in ("fig06_force_records", "fig08_peak_vs_mu", "fig10_peak_vs_tau", "fig12_failure_planes",
                 "table2_shear_strength"):
        assert (out / f"{stem}.png").exists() or (out / f"{stem}.csv").exists()
    assert not (out / "fig16_uy_5mm.png").exists() and (out / "fig20_F_vs_Ad.png").exists()


def test_empty_folder_exit_status(tmp_path):
    assert make_figures.main([str(tmp_path), "-o", str(tmp_path / "o")]) == 2


def test_models_kept_apart_and_duplicates_listed(tmp_path):
    d = tmp_path / "runs"
    d.mkdir()
    synthetic.write_run(str(d / "a.h5"), "1", 0.05, 50e3, travel_end=0.03)
    synthetic.write_run(str(d / "a_again.h5"), "1", 0.05, 50e3, travel_end=0.03)
    synthetic.write_run(str(d / "b.h5"), "1", 0.05, 50e3, travel_end=0.03, model="rigid-dem")
    out = tmp_path / "out"
    assert make_figures.main([str(d), "-o", str(out)]) == 0
    for sub in ("fem-dem_paper", "rigid-dem_paper"):
        with open(out / sub / "summary.csv") as fh:
            assert len(list(csv.DictReader(fh))) == 1
    text = (out / "MISSING.md").read_text()
    assert "duplicate run (ridge 1, mu 0.05, tau_cr 50 kPa): using a.h5, ignoring a_again.h5" in text


def test_scenes_kept_apart(tmp_path):
    """runs/ (the reduced study's small scene) holding runs/deep/ (the paper-depth
    scene), found recursively: each scene gets its folder with its own runs, not
    one study of twice the ridges."""
    d = tmp_path / "runs"
    (d / "deep").mkdir(parents=True)
    for ridge in ("1", "2"):
        synthetic.write_run(str(d / f"small_{ridge}.h5"), f"small-{ridge}", 0.05, 50e3, travel_end=0.03,
                            scene="small")
        synthetic.write_run(str(d / "deep" / f"deep_{ridge}.h5"), f"deep-{ridge}", 0.05, 50e3, travel_end=0.03,
                            scene="deep")
    out = tmp_path / "out"
    assert make_figures.main([str(d), "-o", str(out)]) == 0
    for scene in ("small", "deep"):
        with open(out / f"{scene}_fem-dem_paper" / "summary.csv") as fh:
            rows = list(csv.DictReader(fh))
        assert sorted(r["ridge"] for r in rows) == [f"{scene}-1", f"{scene}-2"]
        assert {r["scene"] for r in rows} == {scene}


def test_of_a_case_run_twice_the_longer_run_is_used(tmp_path):
    """A case run to 20 mm and to 300 mm from one rest state: the figures and tables
    read the 300 mm run, whichever file comes first."""
    d = tmp_path / "runs"
    d.mkdir()
    synthetic.write_run(str(d / "a_long.h5"), "1", 0.05, 50e3, travel_end=0.06)
    synthetic.write_run(str(d / "a.h5"), "1", 0.05, 50e3, travel_end=0.03)
    out = tmp_path / "out"
    assert make_figures.main([str(d), "-o", str(out)]) == 0
    with open(out / "summary.csv") as fh:      # one variant: its folder is out itself
        rows = list(csv.DictReader(fh))
    assert len(rows) == 1 and rows[0]["file"].endswith("a_long.h5")
    text = (out / "MISSING.md").read_text()
    assert "using a_long.h5, ignoring a.h5 (the longer travel, 60 mm)" in text


def test_bond_points_option(tmp_path, capsys):
    d = tmp_path / "runs"
    d.mkdir()
    synthetic.write_run(str(d / "a.h5"), "1", 0.05, 50e3, travel_end=0.03)
    with pytest.raises(SystemExit) as exc:
        make_figures.main([str(d), "-o", str(tmp_path / "x"), "--bond-points", "broken"])
    assert exc.value.code == 2
    assert "--bond-points: invalid choice: 'broken' (choose from 'split', 'failed')" in capsys.readouterr().err
    out = tmp_path / "out"
    assert make_figures.main([str(d), "-o", str(out), "--bond-points", "failed"]) == 0
    assert "fully failed bond points (--bond-points failed)" in (out / "MISSING.md").read_text()
    with open(out / "summary.csv") as fh:
        assert next(csv.DictReader(fh))["bond_points"] == "failed"
