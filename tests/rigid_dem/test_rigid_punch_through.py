"""The discrete-only punch-through end to end: a yade-batch table line with
model = rigid-dem runs in YADE, writes the FEM-DEM's result format, and the
figures read it unchanged."""
import os
import subprocess

import numpy as np
import pytest

from icerubble.run.table_check import check_table
from postproc import results
from tests.paths import ROOT


@pytest.fixture(scope="module")
def rigid_result(tmp_path_factory):
    d = tmp_path_factory.mktemp("rigid")
    table = d / "t.table"
    table.write_text("scene model mu description\n'tiny' 'rigid-dem' 0.3 tiny_rigid\n")
    env = dict(os.environ, ICERUBBLE_OUT_DIR=str(d / "out"), YADE_BATCH=f"{table}:2", OMP_NUM_THREADS="1")
    r = subprocess.run(["yade", "-n", "-x", os.path.join(ROOT, "yade_scripts", "punch_through.py")],
                       cwd=ROOT, env=env, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    return d / "out" / "tiny_rigid.h5"


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


def test_the_figures_read_a_rigid_run(rigid_result, tmp_path):
    r = subprocess.run(["/usr/bin/python3", "-m", "postproc.run_figures", str(rigid_result)], cwd=ROOT,
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    out = tmp_path / "figs"
    r = subprocess.run(["/usr/bin/python3", "-m", "postproc.make_figures", str(rigid_result.parent), "-o", str(out)],
                       cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr[-2000:]
    assert (out / "fig08_peak_vs_mu.png").exists() and (out / "summary.csv").exists()


def test_a_table_with_an_unknown_model_is_refused_with_the_valid_ones(tmp_path):
    t = tmp_path / "t.table"
    t.write_text("scene model\n'tiny' 'rigid'\n")
    problems = check_table(str(t))
    assert problems == ["line 2, column model: 'rigid' is not a model; valid: fem-dem, rigid-dem"]
