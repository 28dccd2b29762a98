"""postproc.measured on constructed CSVs with hand-computed answers (eq 13, eq 15)."""
import math
import os

import pytest

from postproc import measured
from tests.paths import ROOT

EXAMPLE = os.path.join(ROOT, "data", "measured_example", "constructed_punch_through.csv")

# hand values for the example (data/measured_example/README.md), H = W = 4 m, eta = 0.25
FB_CYL = 0.75 * 90.0 * 9.81 * 16.0                                   # 10594.8 N/m
AP_43 = 4.0 * (4.0 + 4.0 * math.tan(math.radians(43.0)))             # 30.920 m^2
FB_43 = 0.75 * 90.0 * 9.81 * AP_43


def test_example_csv_hand_numbers():
    y, F = measured.read_csv(EXAMPLE)
    r = measured.analyse(y, F, 4.0, 4.0, 0.25)
    # the record is piecewise linear with its knots sampled: trapezoid means are exact
    assert r["F_m"] == pytest.approx(40e3, abs=1e-9) and r["y_I_peak"] == pytest.approx(2e-3, abs=1e-15)
    (a1, b1, m1), (a2, b2, m2) = r["means"]
    assert (a1, b1, a2, b2) == (20.0, 150.0, 150.0, 300.0)
    assert m1 == pytest.approx(18e3, abs=1e-6) and m2 == pytest.approx(14.5e3, abs=1e-6)
    assert r["tau1"] == pytest.approx(5000.0, abs=1e-9)
    assert r["tau2"] == pytest.approx((40e3 - FB_CYL) / 8.0, abs=1e-9)
    assert r["tau3"] == pytest.approx((40e3 - FB_43) / 8.0, abs=1e-9)
    assert r["A_p"] == pytest.approx(AP_43, abs=1e-12)


def test_units_total_force_and_plug_force_option(tmp_path):
    p = tmp_path / "m.csv"
    # displacement in m, total force in kN over a 2 m long plane-strain test
    p.write_text("displacement,load\n0,0\n0.001,60\n0.01,30\n0.2,24\n")
    y, F = measured.read_csv(str(p), disp_unit="m", force_unit="kN", out_of_plane_length=2.0)
    r = measured.analyse(y, F, 2.0, 1.0, 0.3, intervals=((10.0, 200.0),), alpha=0.0, plug_force=1000.0)
    assert r["F_m"] == pytest.approx(30e3) and r["y_I_peak"] == pytest.approx(1e-3)
    assert r["means"][0][2] == pytest.approx(13.5e3)           # linear 15 -> 12 kN/m
    assert r["tau2"] == pytest.approx((30e3 - 1000.0) / 4.0)
    # alpha = 0: the "assumed" plug is the cylindrical one, W H = 2 m^2
    assert r["F_b3"] == pytest.approx(0.7 * 90.0 * 9.81 * 2.0)


def test_measured_F_m_is_the_record_maximum_with_the_early_maximum_beside(tmp_path):
    """A field test peaks later than a simulation (Heinonen: 8.8-18.1 mm): F^m and tau
    come from the record maximum, 40 kN/m at 12 mm; the maximum over the first 5 mm
    (30 kN/m at 2 mm) is reported for comparison only."""
    p = tmp_path / "m.csv"
    p.write_text("y_I [mm],F [kN/m]\n0,0\n2,30\n5,25\n12,40\n30,20\n")
    y, F = measured.read_csv(str(p))
    r = measured.analyse(y, F, 4.0, 4.0, 0.25, intervals=())
    assert (r["F_m"], r["y_I_peak"]) == (pytest.approx(40e3), pytest.approx(12e-3))
    assert (r["F_early"], r["y_I_early"]) == (pytest.approx(30e3), pytest.approx(2e-3))
    assert r["tau1"] == pytest.approx(40e3 / 8.0)
    assert "for comparison only" in measured.report_text(r, str(p))


@pytest.mark.parametrize("text,kwargs,match", [
    ("a,b\n0,0\n1,1\n", {}, "no disp column"),
    ("y_I [mm],F [kN/m]\n0,0\n2,1\n1,3\n", {}, "decreases at data row 3"),
    ("y_I [mm],F [kN/m]\n0,0\n1,x\n", {}, "row 2"),
    ("y_I [mm],F [kN/m]\n0,0\n1,1\n", {"disp_unit": "m"}, "contradicts"),
    ("y_I [mm],F [kN]\n0,0\n1,1\n", {}, "out-of-plane-length"),
    ("y_I [mm],F [kN/m]\n0,0\n", {}, "at least 2"),
    ("y_I [mm],F [kN/m]\n-5,9\n0,0\n1,1\n", {}, "data row 1: negative displacement -5"),
])
def test_bad_csv_clear_errors(tmp_path, text, kwargs, match):
    p = tmp_path / "bad.csv"
    p.write_text(text)
    with pytest.raises(ValueError, match=match):
        measured.read_csv(str(p), **kwargs)


@pytest.mark.parametrize("args,match", [
    (["--porosity", "1.2"], "--porosity"),
    (["--porosity", "0.25", "--alpha", "95"], "--alpha"),
    (["--porosity", "0.25", "--rho-w", "900"], "--rho-w"),
])
def test_cli_rejects_bad_parameters(capsys, args, match):
    rc = measured.main([EXAMPLE, "--keel-depth", "4", "--indenter-width", "4"] + args)
    assert rc == 2 and match in capsys.readouterr().err


def test_cli_writes_report_and_figure(tmp_path, capsys):
    out = tmp_path / "o"
    rc = measured.main([EXAMPLE, "--keel-depth", "4", "--indenter-width", "4", "--porosity", "0.25",
                        "--interval", "20:150", "--interval", "250:400", "-o", str(out)])
    text = capsys.readouterr().out
    assert rc == 0
    assert "ASSUMED plug" in text and "not computed" in text  # 250-400 mm is beyond the record
    for name in ("report.md", "result.csv", "measured_F_y.png", "measured_F_y.pdf"):
        assert (out / name).stat().st_size > 0
