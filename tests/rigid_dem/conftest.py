"""Runs the rigid model's tests share: the tiny ridge from one yade-batch table,
by either model, each run once per session when a test first asks for it
(tens of seconds each: every test module that needs one takes it from here)."""
import os
import subprocess

import pytest

from tests.paths import ROOT

TINY_TABLE = ("scene model mu description\n"
              "'tiny' 'rigid-dem' 0.3 tiny_rigid\n"
              "'tiny' 'fem-dem' 0.3 tiny_fem\n")
TINY_LINES = {"rigid-dem": (2, "tiny_rigid.h5"), "fem-dem": (3, "tiny_fem.h5")}


class TinyRuns:
    """The tiny ridge's results in one folder (they share its pile and mesh)."""

    def __init__(self, folder):
        self.folder = folder
        self.table = folder / "t.table"
        self.table.write_text(TINY_TABLE)
        self.out = folder / "out"

    def path(self, model):
        """The result of `model` ("fem-dem" | "rigid-dem"), run on first request."""
        line, name = TINY_LINES[model]
        result = self.out / name
        if not result.exists():
            env = dict(os.environ, ICERUBBLE_OUT_DIR=str(self.out), YADE_BATCH=f"{self.table}:{line}",
                       OMP_NUM_THREADS="1")
            r = subprocess.run(["yade", "-n", "-x", os.path.join(ROOT, "yade_scripts", "punch_through.py")],
                               cwd=ROOT, env=env, capture_output=True, text=True, timeout=600)
            assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
        return result


@pytest.fixture(scope="session")
def tiny_runs(tmp_path_factory):
    return TinyRuns(tmp_path_factory.mktemp("tiny_runs"))


@pytest.fixture(scope="session")
def tiny_fem_result(tiny_runs):
    """The tiny ridge's FEM-DEM result: one snapshot (1 mm), bond points split, none failed by then."""
    return tiny_runs.path("fem-dem")
