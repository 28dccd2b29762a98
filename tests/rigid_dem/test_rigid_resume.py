"""A rigid punch-through stopped by a scheduler's signal while loading writes a
checkpoint and resumes from it (icerubble/rigid_dem/checkpoint.py; on this
ridge's few contacts bit for bit, in general to round-off); a checkpoint of
another run is refused; stopped while settling, it stops at once."""
import os
import subprocess

import h5py
import numpy as np

from tests.paths import ROOT

COMPARED = ("force/t", "force/y_I", "force/F", "force/F_instant", "energy/t", "energy/kinetic", "energy/contact",
            "energy/friction", "energy/cohesive", "energy/residual", "bonds/t_split", "bonds/y_I_fail", "bonds/mode")


def run_scene(env, tmp_path):
    r = subprocess.run(["yade", "-n", "-x", os.path.join("tests", "rigid_dem", "yade_resume_scene.py")],
                       cwd=ROOT, env=dict(os.environ, OMP_NUM_THREADS="1", **env),
                       capture_output=True, text=True, timeout=600)
    return r.returncode, r.stdout + r.stderr


def test_a_rigid_run_stopped_by_sigterm_resumes_bit_for_bit(tiny_runs, tmp_path):
    tiny_runs.path("rigid-dem")                        # makes the ridge's pile and mesh
    mesh = next((tiny_runs.out / "scenes").glob("*_mesh.h5"))
    # the run never stopped, in a process of its own as the stopped and the
    # resumed runs (YADE's polyhedra intersections, CGAL, round off by the
    # process's memory layout: a run that made its pile first can differ)
    reference = tmp_path / "reference.h5"
    code, log = run_scene(dict(MESH=str(mesh), OUT=str(reference), RUN_ID="r"), tmp_path)
    assert code == 0, log[-2000:]
    out = tmp_path / "stopped.h5"
    ckpt = tmp_path / "stopped.checkpoint.h5"
    env = dict(MESH=str(mesh), OUT=str(out), RUN_ID="a")
    code, log = run_scene(dict(env, SIGNAL_AFTER="700"), tmp_path)
    assert code == 75 and "stopped by SIGTERM" in log, log[-2000:]
    assert ckpt.exists() and not out.exists()          # no result that looks complete
    # another run's checkpoint is not taken up
    code, log = run_scene(dict(env, RUN_ID="b"), tmp_path)
    assert code == 1 and "checkpoint of another run (run_id" in log, log[-2000:]
    code, log = run_scene(env, tmp_path)
    assert code == 0 and "resumed from" in log, log[-2000:]
    assert out.exists() and not ckpt.exists()
    with h5py.File(reference) as a, h5py.File(out) as b:
        for k in COMPARED:
            assert np.array_equal(a[k][()], b[k][()], equal_nan=True), k
        for s in a["snapshots"]:
            assert np.array_equal(a["snapshots"][s]["u_node"][()], b["snapshots"][s]["u_node"][()]), s


def test_a_rigid_run_signalled_while_settling_stops_at_once(tiny_runs, tmp_path):
    tiny_runs.path("rigid-dem")
    mesh = next((tiny_runs.out / "scenes").glob("*_mesh.h5"))
    out = tmp_path / "settling.h5"
    code, log = run_scene(dict(MESH=str(mesh), OUT=str(out), RUN_ID="s", SIGNAL_SETTLING="100"), tmp_path)
    assert code == 75 and "(settle, before loading" in log, log[-2000:]
    assert not out.exists() and not (tmp_path / "settling.checkpoint.h5").exists()
