"""The (F̄, F_d) pairs of R(F, F_d) as rows that travel (postproc/fd_pairs.py):
R from stored pairs is Pearson's R of the numbers stored at Fig. 20's travels
(20-150 mm), the pairs written and
read back are the numbers measured, and a file that cannot serve is refused."""
import csv

import numpy as np
import pytest

from postproc import displaced_area as dA
from postproc import fd_pairs, loads, paper_comparison, stored_rows
from icerubble.files import results
from tests.postproc import synthetic


def _stored(tau_kPa, F_d, F, name="x.h5"):
    """A run known by its row only, with pairs (F_d at K 0.45 and 0.9 alike, F̄ = F(y_I))."""
    P = [{"file": name, "run_id": "", "y_I_mm": 20.0 + 10 * k, "F_mean_kN_per_m": f, "F_sample_kN_per_m": f,
          "F_d_K0.45_kN_per_m": d, "F_d_K0.9_kN_per_m": d} for k, (d, f) in enumerate(zip(F_d, F))]
    return stored_rows.StoredRun(row={"file": name, "tau_cr_kPa": tau_kPa}, source="s.csv", fd_pairs=P)


def test_R_from_stored_pairs_is_pearsons_R_of_the_numbers_stored():
    # x = 1, 2, 3 and y = 1, 3, 2: covariance 1, variances 2 and 2, so R = 1/2 by hand
    half = _stored(50.0, [1.0, 2.0, 3.0], [1.0, 3.0, 2.0])
    R, n, ratio = paper_comparison.r_fd([half], K=0.45)
    assert n == 3 and R == pytest.approx(0.5, abs=1e-12)
    assert np.allclose(ratio, [1.0, 1.5, 2.0 / 3.0])
    # pairs on a line y = 2x + 1 are R = 1; the τ_cr filter picks the run at 5 kPa alone
    line = _stored(5.0, [1.0, 2.0, 4.0], [3.0, 5.0, 9.0], "y.h5")
    assert paper_comparison.r_fd([half, line], tau=5.0, K=0.9)[:2] == (pytest.approx(1.0, abs=1e-12), 3)
    # R reads Fig. 20's travels, 20-150 mm: pairs at 160 and 170 mm off the line do not count
    x = np.arange(1.0, 17.0)
    y = 2 * x + 1
    y[14:] = [-50.0, 80.0]
    assert paper_comparison.r_fd([_stored(5.0, x, y)], K=0.45)[:2] == (pytest.approx(1.0, abs=1e-12), 14)
    # a stored run without pairs adds none
    none = stored_rows.StoredRun(row={"file": "z.h5", "tau_cr_kPa": 5.0}, source="s.csv")
    assert paper_comparison.r_fd([line, none], K=0.9)[1] == 3


def test_pairs_written_and_read_back_are_the_numbers_measured(tmp_path):
    path = str(tmp_path / "r.h5")
    synthetic.write_run(path, 1, 0.05, 50e3, travel_end=0.05)
    run = results.load(path)
    P = fd_pairs.of_run(run, "runs/r.h5", "abc")
    want = [s.y_I for s in run.snapshots if s.y_I >= 19.5e-3]
    assert len(want) >= 3 and [p["y_I_mm"] for p in P] == [y * 1e3 for y in want]
    for p, y in zip(P, want):
        assert p["F_mean_kN_per_m"] == dA.paired_load(run, y) / 1e3
        assert p["F_sample_kN_per_m"] == loads.load_at(run.force_y, run.force_F, y) / 1e3
        assert p["F_d_K0.9_kN_per_m"] == dA.displaced_load(run, 0.9, y) / 1e3
    out = str(tmp_path / fd_pairs.FILE_NAME)
    fd_pairs.write_csv(P, out)
    assert fd_pairs.read(out) == {("runs/r.h5", "abc"): P}   # 17 digits: bit for bit


def test_pairs_that_cannot_serve_are_refused_with_the_reason(tmp_path):
    with pytest.raises(ValueError, match="K 0.1: stored pairs hold F_d at K in"):
        fd_pairs.f_d_column(0.1)
    short = tmp_path / "short.csv"
    short.write_text("file,run_id,y_I_mm\nx.h5,,20\n")
    with pytest.raises(ValueError, match="not an fd_pairs.csv of this version: column"):
        fd_pairs.read(str(short))
    text = tmp_path / "text.csv"
    with open(text, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(fd_pairs.COLUMNS)
        w.writerow(["x.h5", "", "20", "low", "1", "1", "1"])
    with pytest.raises(ValueError, match="line 2: column 'F_mean_kN_per_m' holds 'low', not a number"):
        fd_pairs.read(str(text))
