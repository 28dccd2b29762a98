"""A rigid punch-through stopped by a scheduler's signal while loading writes a
checkpoint and resumes from it (icerubble/rigid_dem/checkpoint.py): the state
it takes up is the stopped run's, bit for bit, and it goes on as the
uninterrupted run does; a checkpoint of another run is refused; stopped while
settling, it stops at once.

Two processes of the same rigid run are not always alike on one machine: on
the tiny ridge, about a third of the processes started by this test settled to
another rest state (F at rest -45.60 against -51.07 N/m) or parted from the
others while loading, whatever was resumed (YADE's polyhedra; the cause is not
found, docs/reproducibility.md). So the restored state is compared with the
stopped one always, and the resumed record with the uninterrupted run's where
that run reached the stop in the stopped run's bits; where the resumed record
parts from it, the checkpoint is taken up once more: two resumed runs that agree
with each other and not with the run never stopped fail the test (a resume that
loses a state), a second one that agrees passes it.
"""
import os
import shutil
import subprocess

import h5py
import numpy as np
import pytest

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
    # resumed runs; it and the stopped run keep their state at the stop
    reference = tmp_path / "reference.h5"
    at_stop = dict(STATE_AT="700")
    code, log = run_scene(dict(MESH=str(mesh), OUT=str(reference), RUN_ID="r", STATE_OUT=str(tmp_path / "r.npz"),
                               **at_stop), tmp_path)
    assert code == 0, log[-2000:]
    out = tmp_path / "stopped.h5"
    ckpt = tmp_path / "stopped.checkpoint.h5"
    env = dict(MESH=str(mesh), OUT=str(out), RUN_ID="a")
    code, log = run_scene(dict(env, SIGNAL_AFTER="700", STATE_OUT=str(tmp_path / "a.npz"),
                               SAVED_STATE=str(tmp_path / "stopped.npz"), **at_stop), tmp_path)
    assert code == 75 and "stopped by SIGTERM" in log, log[-2000:]
    assert ckpt.exists() and not out.exists()          # no result that looks complete
    # another run's checkpoint is not taken up
    code, log = run_scene(dict(env, RUN_ID="b"), tmp_path)
    assert code == 1 and "checkpoint of another run (run_id" in log, log[-2000:]
    kept = tmp_path / "kept.checkpoint.h5"            # the resumed run removes its checkpoint
    shutil.copy(ckpt, kept)
    resaved = tmp_path / "resaved.checkpoint.h5"
    code, log = run_scene(dict(env, RESAVE=str(resaved), SAVED_STATE=str(tmp_path / "resaved.npz")), tmp_path)
    assert code == 0 and "resumed from" in log, log[-2000:]
    assert out.exists() and not ckpt.exists()
    # the state taken up is the one the stopped run left, bit for bit: every
    # body's, the histories, the ledger, the driver's and the record so far
    with h5py.File(kept) as a, h5py.File(resaved) as b:
        assert_same_tree(a, b)
    assert_same_state(tmp_path / "stopped.npz", tmp_path / "resaved.npz")
    if not same_state(tmp_path / "r.npz", tmp_path / "a.npz"):
        pytest.skip("the uninterrupted run's process parted from the stopped run's before the stop "
                    "(module docstring): the resumed record has nothing to be compared with")
    if same_record(reference, out):
        return
    # Parted after the stop: the resume, or one of the two processes (module
    # docstring)? A state lost at the resume parts every resumed run the same way;
    # a process that parts does so at random. So the checkpoint is taken up again.
    again = tmp_path / "again.h5"
    shutil.copy(kept, tmp_path / "again.checkpoint.h5")
    code, log = run_scene(dict(env, OUT=str(again)), tmp_path)
    assert code == 0 and "resumed from" in log, log[-2000:]
    if same_record(reference, again):
        return
    assert not same_record(out, again), (
        "two runs resumed from one checkpoint agree with each other and not with the run never stopped: "
        "the resume loses or changes a state")
    pytest.skip("the resumed runs parted from each other as well as from the run never stopped: processes "
                "that differ (module docstring), nothing to tell about the resume")


def same_record(a, b):
    """The records and the snapshots' displacements, bit for bit."""
    with h5py.File(a) as x, h5py.File(b) as y:
        return (all(np.array_equal(x[k][()], y[k][()], equal_nan=True) for k in COMPARED)
                and all(np.array_equal(x["snapshots"][s]["u_node"][()], y["snapshots"][s]["u_node"][()])
                        for s in x["snapshots"]))


def same_state(a, b):
    with np.load(a) as x, np.load(b) as y:
        return x.files == y.files and all(np.array_equal(x[k], y[k]) for k in x.files)


def assert_same_state(a, b):
    with np.load(a) as x, np.load(b) as y:
        assert x.files == y.files
        for k in x.files:
            assert np.array_equal(x[k], y[k]), k


def assert_same_tree(a, b, path=""):
    """Every group, dataset and attribute of `a` in `b`, with the same bits,
    but the time the file was written and YADE's scene string (its shapes'
    colours are drawn at random: the bodies' states are compared apart)."""
    assert sorted(a.attrs) == sorted(b.attrs), path
    assert sorted(a) == sorted(b), path
    for k in set(a.attrs) - {"created"}:
        assert np.array_equal(np.asarray(a.attrs[k]), np.asarray(b.attrs[k])), f"{path}@{k}"
    for k in set(a) - {"yade_scene"}:
        if isinstance(a[k], h5py.Group):
            assert_same_tree(a[k], b[k], f"{path}/{k}")
        else:
            x, y = a[k][()], b[k][()]
            assert (x.tobytes() == y.tobytes()) if isinstance(x, np.void) else np.array_equal(x, y, equal_nan=True), \
                f"{path}/{k}"


def test_a_rigid_run_signalled_while_settling_stops_at_once(tiny_runs, tmp_path):
    tiny_runs.path("rigid-dem")
    mesh = next((tiny_runs.out / "scenes").glob("*_mesh.h5"))
    out = tmp_path / "settling.h5"
    code, log = run_scene(dict(MESH=str(mesh), OUT=str(out), RUN_ID="s", SIGNAL_SETTLING="100"), tmp_path)
    assert code == 75 and "(settle, before loading" in log, log[-2000:]
    assert not out.exists() and not (tmp_path / "settling.checkpoint.h5").exists()
