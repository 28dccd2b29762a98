"""Reading run results: complete files only, missing optional groups reported (docs/results_format.md)."""
import os

import h5py
import numpy as np
import pytest

from icerubble.files import results
from postproc import failure_plane, summary

from tests.postproc import synthetic


def test_part_file_refused(tmp_path):
    p = synthetic.write_run(str(tmp_path / "a.h5"), "1", 0.05, 50e3, travel_end=0.02, leave_part=True)
    assert p.endswith(".h5.part") and os.path.exists(p)
    with pytest.raises(results.ResultFileError, match="part"):
        results.load(p)
    done, partial = results.find_results(str(tmp_path))
    assert done == [] and partial == [p]


def test_incomplete_file_refused(tmp_path):
    p = synthetic.write_run(str(tmp_path / "a.h5"), "1", 0.05, 50e3, travel_end=0.02, complete=False)
    with pytest.raises(results.ResultFileError, match="complete"):
        results.load(p)


def test_wrong_format_refused(tmp_path):
    p = str(tmp_path / "x.h5")
    with h5py.File(p, "w") as f:
        f.attrs["format"] = "something-else"
    with pytest.raises(results.ResultFileError, match="format"):
        results.load(p)


def test_missing_optional_groups_are_reported(tmp_path):
    p = synthetic.write_run(str(tmp_path / "a.h5"), "1", 0.3, 5e3, travel_end=0.02, snapshots=False, energy=False)
    run = results.load(p)
    assert set(run.missing) == {"snapshots", "energy", "fields"}
    assert "Figs. 16-20" in run.missing["snapshots"]
    assert run.nearest_snapshot(5e-3) is None
    # the rest still works; the summary says what is missing
    row = summary.summarize(run)
    assert row["missing"] == "energy; fields; snapshots" and row["n_snapshots"] == 0


def test_end_to_end_alpha_exact_through_the_file(tmp_path):
    """Bond points written exactly on the synthetic planes (jitter 0) come back as the
    planes' angles: the reader, selection and fit lose nothing but round-off."""
    p = synthetic.write_run(str(tmp_path / "a.h5"), "2", 0.05, 25e3, jitter=0.0, travel_end=0.03)
    run = results.load(p)
    aL, aR = synthetic.true_alpha("2", 25e3)
    got = failure_plane.alpha_at(run, 20e-3)
    assert abs(got[0] - aL) < 1e-9 and abs(got[1] - aR) < 1e-9
    # every instant of Fig. 13 (1...20 mm) has >= 3 failed points per side
    samples = failure_plane.alpha_samples(run)
    assert samples.size == 40
    assert np.allclose(np.sort(samples), np.sort([aL] * 20 + [aR] * 20), atol=1e-9)


@pytest.mark.parametrize("change,why", [("delete", "absent"), ("nan", "NaN at split bond points")])
def test_file_without_split_tractions_has_no_initiation_count(tmp_path, change, why):
    """A file from before /bonds/split_tn, split_tt were written, or a rigid-DEM file
    with them NaN: the run still reads; the initiation-side count is NaN and
    `missing` says why, while the full-failure count stands."""
    p = synthetic.write_run(str(tmp_path / "a.h5"), "1", 0.05, 50e3, travel_end=0.03)
    with h5py.File(p, "r+") as f:
        for k in ("split_tn", "split_tt"):
            if change == "delete":
                del f["bonds"][k]
            else:
                f["bonds"][k][...] = np.nan
    run = results.load(p)
    assert why in run.missing["split_traction"] and "n_t_init" in run.missing["split_traction"]
    row = summary.summarize(run)
    assert all(np.isnan(row[k]) for k in ("n_t_init", "n_s_init", "nt_ns_init"))
    assert row["n_t"] + row["n_s"] == row["n_failed"] > 0 and "split_traction" in row["missing"]
