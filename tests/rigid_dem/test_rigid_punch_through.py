"""The discrete-only punch-through end to end: a yade-batch table line with
model = rigid-dem runs in YADE, writes the FEM-DEM's result format, and the
figures read it unchanged."""
import subprocess

import numpy as np
import pytest

from icerubble import parameters as P
from icerubble.files import results
from icerubble.study.table_check import check_table
from postproc import loads, model_comparison
from tests.paths import ROOT


@pytest.fixture(scope="module")
def rigid_result(tiny_runs):
    tiny_runs.path("fem-dem")          # beside it, for the comparison
    return tiny_runs.path("rigid-dem")


def test_a_rigid_run_writes_the_result_format(rigid_result):
    run = results.load(rigid_result)
    assert run.attrs["model"] == "rigid-dem"
    y, F = run.force_y, run.force_F
    assert y[0] == 0.0 and y[-1] >= run.parameters["target_travel"] * (1 - 1e-9)
    assert np.all(np.diff(y) > 0) and np.all(np.diff(y) <= 1.5e-4)   # samples every ~0.1 mm
    # at rest the held indenter carries next to nothing; loading, the rubble resists
    assert abs(run.attrs["F_at_rest"]) < 0.01 * F.max()
    assert F.max() > 0.0
    assert run.snapshots and abs(run.snapshots[0].y_I - 1e-3) < 2e-4
    # rigid bodies: within a block every triangle moves alike in a pure translation
    # or turns about one point; at least the displacement field is finite and not all zero
    u = run.u_elem(run.snapshots[0])
    assert np.isfinite(u).all() and np.abs(u).max() > 1e-4


def test_a_rigid_run_records_an_energy_ledger_that_closes(rigid_result):
    import h5py
    with h5py.File(rigid_result) as f:
        e = {k: f["energy"][k][()] for k in f["energy"]}
    assert len(e["t"]) >= 2 and np.all(np.diff(e["t"]) > 0)
    w = e["work_boundary"][-1]
    assert w > 0.0                                            # the indenter pushes the rubble
    # every force YADE integrated is paid out: the balance closes to round-off
    assert np.abs(e["residual"]).max() < 1e-9 * w
    assert np.all(e["drag"] >= 0.0) and np.all(e["friction"] >= 0.0) and np.all(e["cohesive"] >= 0.0)
    assert np.all(e["damping"] == 0.0)                         # loading is undamped
    # YADE's contacts do not make energy here (they can in violent impacts)
    assert e["contact"].min() > -0.01 * w


def test_the_figures_read_a_rigid_run(rigid_result, tmp_path):
    r = subprocess.run(["/usr/bin/python3", "-m", "postproc.run_figures", str(rigid_result)], cwd=ROOT,
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    out = tmp_path / "figs"
    r = subprocess.run(["/usr/bin/python3", "-m", "postproc.make_figures", str(rigid_result.parent), "-o", str(out)],
                       cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    # a folder of both models: one set of figures per model (and force direction, the default here)
    direction = P.REGISTRY["force_direction"].default
    assert (out / f"rigid-dem_{direction}" / "fig08_peak_vs_mu.png").exists()
    assert (out / f"fem-dem_{direction}" / "fig08_peak_vs_mu.png").exists()


def test_a_table_with_an_unknown_model_is_refused_with_the_valid_ones(tmp_path):
    t = tmp_path / "t.table"
    t.write_text("scene model\n'tiny' 'rigid'\n")
    problems = check_table(str(t))
    assert problems == ["line 2, column model: 'rigid' is not a model; valid: fem-dem, rigid-dem"]


def test_the_comparison_puts_both_models_of_one_ridge_side_by_side(rigid_result, tmp_path):
    fem = rigid_result.parent / "tiny_fem.h5"
    r = subprocess.run(["/usr/bin/python3", "-m", "postproc.model_comparison", str(fem), str(rigid_result),
                        "-o", str(tmp_path)], cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    rows = {line.split(",")[0]: line.split(",")[2:] for line in (tmp_path / "model_comparison.csv").read_text().splitlines()}
    for key, peak in (("F^m", loads.cohesive_peak), ("record maximum", loads.record_maximum)):
        f_fem, f_rigid = (float(v) for v in rows[key])
        for value, run in ((f_fem, results.load(fem)), (f_rigid, results.load(rigid_result))):
            assert value == pytest.approx(peak(run.force_y, run.force_F)[0] / 1e3, rel=1e-3)
    # the ratio is the one the two files record (no expectation on the timings themselves)
    walls = [model_comparison.wall_time(results.load(f)) for f in (fem, rigid_result)]
    assert float(rows["wall time ratio rigid / FEM-DEM"][1]) == pytest.approx(walls[1] / walls[0], rel=1e-3)
    assert (tmp_path / "model_comparison.png").exists()
    # the same file twice is not a comparison
    r = subprocess.run(["/usr/bin/python3", "-m", "postproc.model_comparison", str(rigid_result), str(rigid_result)],
                       cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert r.returncode == 2 and "expected a fem-dem and a rigid-dem result" in r.stderr
