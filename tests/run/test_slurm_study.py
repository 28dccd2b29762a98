"""A study on a real SLURM: `icerubble study submit --slurm`, `status`,
`resubmit`, against a one-node SLURM started on this machine (tests/local_slurm.py).
If SLURM cannot start here the tests fail saying why; they do not skip.

The table is the tiny scene (8 blocks) with 60 mm of travel: its loading
takes ~8 s, several times the ~1.5 s it takes the test to see loading begin
and stop the run (at 15 mm the loading took 2 s, and once ended before the
stop reached it).
"""
import os
import subprocess
import time

import h5py
import numpy as np
import pytest

from icerubble.files.h5io import open_complete
from tests.local_slurm import LocalSlurm

TRAVEL = 0.060
WAIT_S = 400


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    with LocalSlurm(tmp_path_factory.mktemp("slurm")) as c:
        yield c


@pytest.fixture(scope="module")
def out(tmp_path_factory):
    return tmp_path_factory.mktemp("study")


def _study(cluster, *args, cwd):
    r = subprocess.run(["icerubble", "study", *args], env=cluster.env, cwd=cwd, capture_output=True,
                       text=True, timeout=120)
    assert "Traceback" not in r.stdout + r.stderr, r.stdout + r.stderr
    return r


def _states(text):
    """{label: (state, rest)} from `study status`."""
    got = {}
    for ln in text.splitlines():
        parts = ln.split(None, 3)
        if len(parts) == 4 and parts[0] == "line":
            label, _, rest = parts[3].partition(": ")
            got[label] = (parts[2], rest)
    return got


def _wait(cluster, out, until, what, wrong=lambda states: None):
    """Polls `study status` until `until(states)`; fails at once when
    `wrong(states)` says why the wait cannot end well."""
    deadline = time.time() + WAIT_S
    while time.time() < deadline:
        text = _study(cluster, "status", str(out), cwd=out).stdout
        states = _states(text)
        if until(states):
            return states, text
        why = wrong(states)
        if why:
            raise AssertionError(f"{what}: {why}:\n{text}")
        time.sleep(1)
    raise AssertionError(f"{what}: not within {WAIT_S} s:\n{text}")


def _settled(states):
    return states and not any(s in ("running", "pending", "not run") for s, _ in states.values())


def _submit(cluster, out, name, text):
    table = out / name
    table.write_text(text)
    r = _study(cluster, "submit", str(table), "--slurm", "--out", str(out), "--cpus-per-task", "1", cwd=out)
    assert r.returncode == 0, r.stdout + r.stderr
    return r.stdout.split()[-1]


def _force(path):
    with open_complete(path) as f:
        return f["force/y_I"][()], f["force/F"][()], f["energy/residual"][()]


def test_a_table_runs_as_a_job_array_and_one_bad_line_fails_alone(cluster, out):
    job = _submit(cluster, out, "three.table",
                  "description scene mu tau_cr dt target_travel\n"
                  f"strong 'tiny' 0.3 50e3 None {TRAVEL}\n"
                  f"weak 'tiny' 0.3 5e3 None {TRAVEL}\n"
                  # a step far above the stable step: only the mesh can tell, so it fails at run time
                  f"toolarge 'tiny' 0.3 50e3 1e-3 {TRAVEL}\n")
    assert job.isdigit()
    states, text = _wait(cluster, out, _settled, "the three lines to end")
    assert states["strong"][0] == "done" and states["weak"][0] == "done", text
    assert states["toolarge"][0] == "failed" and "exceeds the stable step" in states["toolarge"][1], text
    for name in ("strong", "weak"):
        y, _, _ = _force(out / f"{name}.h5")
        assert y[-1] >= TRAVEL
    assert not (out / "toolarge.h5").exists()
    # the ridge's pile and mesh were made once, by one task, while the other
    # waited; strong and weak differ only in tau_cr, which the settle never
    # reads: one shared rest state (both settled, at once, to the same bits)
    scenes = sorted(os.listdir(out / "scenes"))
    assert scenes[:2] == ["tiny_ridge1_pilemu0.05_mesh.h5", "tiny_ridge1_pilemu0.05_pile.h5"], scenes
    assert scenes[3:] == ["tiny_ridge1_pilemu0.05_scene.lock"], scenes
    assert scenes[2].startswith("tiny_ridge1_pilemu0.05_rest_") and scenes[2].endswith(".checkpoint.h5")
    # nothing to resubmit but the failed line
    r = _study(cluster, "resubmit", str(out), cwd=out)
    assert "three.table: resubmitted lines 4 " in r.stdout, r.stdout
    _wait(cluster, out, lambda s: _settled(s) and s["toolarge"][0] == "failed", "the resubmitted line")


def test_stopped_tasks_resume_from_their_checkpoint_to_the_same_record(cluster, out):
    """Two tasks stopped in the middle of loading, each as a scheduler stops
    one: scancel (SIGTERM; resumed by `study resubmit`) and the signal before
    the time limit (SIGUSR1 to the batch script, which requeues the task). Both
    end with the F record of the uninterrupted runs of the first test, bit for
    bit (same parameters, one thread each)."""
    if not (out / "strong.h5").exists():
        pytest.fail("needs the first test's uninterrupted runs")
    job = _submit(cluster, out, "stopped.table",
                  "description scene mu tau_cr target_travel\n"
                  f"cancelled 'tiny' 0.3 50e3 {TRAVEL}\n"
                  f"timelimit 'tiny' 0.3 5e3 {TRAVEL}\n")
    logs = out / "logs" / "stopped"
    stops = {2: ["scancel", f"{job}_2"], 3: ["scancel", "--signal=USR1", "--batch", f"{job}_3"]}
    deadline = time.time() + WAIT_S
    while stops and time.time() < deadline:
        for line in list(stops):
            log = logs / f"line{line}.log"
            if log.exists() and "[punch-through] step" in log.read_text():   # loading has begun
                time.sleep(1.0)
                subprocess.run(stops.pop(line), env=cluster.env, check=True)
        time.sleep(0.2)
    assert not stops, "the runs did not start loading"
    # the time-limit stop requeues the task; SLURM holds a requeued task back
    # for a while (its begin time), released here so the test does not wait.
    # Not at once: slurmd refuses a credential made in the same second as the
    # last attempt's was revoked ("Job credential revoked", and the task ends
    # failed), which is what SLURM's own hold avoids; 2 s after the requeue is past it.
    deadline = time.time() + WAIT_S
    requeued_at = released = None
    while time.time() < deadline and "restart 1" not in (logs / "line3.log").read_text():
        assert "[study] wrote" not in (logs / "line3.log").read_text(), "line 3 ended before SIGUSR1 reached it"
        q = subprocess.run(["squeue", "-h", "-j", f"{job}_3", "-o", "%T"], env=cluster.env,
                           capture_output=True, text=True).stdout.split()
        if q[:1] == ["PENDING"]:
            requeued_at = requeued_at or time.time()
            if not released and time.time() - requeued_at > 2.0:
                subprocess.run(["scontrol", "update", f"JobId={job}_3", "StartTime=now"], env=cluster.env,
                               capture_output=True)
                released = True
        time.sleep(0.5)
    states, text = _wait(cluster, out, lambda s: s["cancelled"][0] == "interrupted" and s["timelimit"][0] == "done",
                         "the cancelled line interrupted and the requeued one done",
                         wrong=lambda s: s.get("cancelled", ("",))[0] == "done" and "line 2 ended before scancel reached it")
    assert "stopped by SIGTERM" in states["cancelled"][1] and "phase load" in states["cancelled"][1], text
    assert (out / "cancelled.checkpoint.h5").exists()
    assert "stopped by SIGUSR1" in (logs / "line3.log").read_text()
    r = _study(cluster, "resubmit", str(out), cwd=out)
    assert "stopped.table: resubmitted lines 2 " in r.stdout, r.stdout
    states, text = _wait(cluster, out, lambda s: _settled(s), "the resubmitted line")
    assert states["cancelled"][0] == "done", text
    for stopped, whole in (("cancelled", "strong"), ("timelimit", "weak")):
        log = (logs / f"line{2 if stopped == 'cancelled' else 3}.log").read_text()
        assert "[punch-through] resumed from" in log and "phase load" in log
        # they started after strong and weak had left their rest state: no settle of their own
        assert "loads from the shared rest state" in log and "[settle]" not in log, log
        for a, b in zip(_force(out / f"{stopped}.h5"), _force(out / f"{whole}.h5")):
            np.testing.assert_array_equal(a, b)
    assert not (out / "cancelled.checkpoint.h5").exists()
    with h5py.File(out / "cancelled.h5", "r") as f:
        assert int(f.attrs["complete"]) == 1
