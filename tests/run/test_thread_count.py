"""The thread count a run asks for is the one it computes with, also after
meshing its scene in the same process: gmsh.initialize() sets OpenMP's
thread count of the whole process to 1 (icerubble/openmp_threads.py).

Each case runs in a fresh interpreter: OpenMP reads OMP_NUM_THREADS once,
when the process starts, and the count must differ from gmsh's 1 to show
anything (3 threads: more than this machine may have, which OpenMP allows).
"""
import json
import os
import subprocess
import sys

from tests.paths import ROOT

MESH_THEN_RUN = r"""
import json, pathlib, sys, tempfile
from icerubble.openmp_threads import openmp_max_threads
from icerubble.run.punch_through_run import PunchThrough, RunOptions
from tests.run.punch_through_scenes import brick_mesh

tmp = pathlib.Path(tempfile.mkdtemp())
before = openmp_max_threads()
mesh = brick_mesh(tmp)          # gmsh, in this process
after = openmp_max_threads()
asked = int(sys.argv[1])
run = PunchThrough(mesh, tmp / "run.h5", params=dict(dt=5e-6, penalty=2e10),
                   options=RunOptions(threads=asked), rest_dir=tmp)
key = json.loads(run.shared_rest[1])
print(json.dumps(dict(before=before, after=after, computes=run.model.thread_count, key=key["threads"])))
"""


def _mesh_then_run(asked, omp_num_threads):
    env = dict(os.environ, OMP_NUM_THREADS=str(omp_num_threads), PYTHONPATH=ROOT)
    r = subprocess.run([sys.executable, "-c", MESH_THEN_RUN, str(asked)], cwd=ROOT, env=env,
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stdout + r.stderr
    return json.loads(r.stdout.strip().splitlines()[-1])


def test_a_run_that_meshed_its_scene_computes_on_the_threads_of_its_process():
    """threads = 0 (every study run): OMP_NUM_THREADS, which `yade -jN` sets,
    is what the model computes with and what the rest state is keyed by, and
    meshing leaves OpenMP's own setting (YADE's loops read it) as it was."""
    got = _mesh_then_run(asked=0, omp_num_threads=3)
    assert got["before"] == got["after"] == 3, got
    assert got["computes"] == got["key"] == 3, got


def test_a_run_asking_for_threads_computes_on_them_after_meshing():
    got = _mesh_then_run(asked=2, omp_num_threads=3)
    assert got["computes"] == got["key"] == 2, got
