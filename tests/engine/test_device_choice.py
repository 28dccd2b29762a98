"""Where a model's steps run (Model(device=...), RunOptions, a study's
--device and device column; docs/gpu.md): the CPU by default, the GPU only
where its backend can run, refused before any work elsewhere with the
reason. A model on device 'cuda' steps as on the CPU, on a GPU or on the
backend's CPU emulation (tests/engine/test_gpu_backend.py compares the steps
themselves)."""
import os
import re

import numpy as np
import pytest

from icerubble import engine
from icerubble.engine import gpu
from icerubble.run import run_identity as RI
from icerubble.run.punch_through_run import RunOptions
from tests.commands import icerubble
from tests.engine.gpu_scenes import landing_block_and_a_flyer, on_gpu_or_emulation, pulled_bar
from tests.paths import ROOT

no_gpu = pytest.mark.skipif(gpu.available(), reason="a GPU is visible here: 'cuda' is not refused")


def square():
    nodes, tri = engine.rectangle_mesh(2, 2, 0.1)
    return nodes, tri, np.zeros(len(tri), dtype=np.int32), dict(E=2e9, nu=0.3, rho=920.0)


def test_the_cpu_is_the_default_and_the_choice_is_kept():
    m = engine.Model(*square())
    assert m.device == "cpu" and RunOptions().device == "cpu"
    with pytest.raises(ValueError, match="device='tpu' is unknown: valid values are cpu, cuda"):
        m.device = "tpu"
    assert m.device == "cpu"


@no_gpu
def test_the_gpu_is_refused_with_the_reason_where_it_cannot_run():
    why = gpu.why_unavailable()
    with pytest.raises(ValueError, match=re.escape(f"device='cuda': the GPU backend cannot run here: {why}")):
        engine.Model(*square(), device="cuda")
    with pytest.raises(ValueError, match="GPU backend cannot run here"):
        RunOptions(device="cuda")


@no_gpu
def test_a_study_on_the_gpu_is_refused_before_any_line_runs(tmp_path):
    r = icerubble("study", "run", os.path.join(ROOT, "data", "study_tiny.table"), "--local",
                  "--out", tmp_path / "runs", "--device", "cuda", cwd=tmp_path)
    assert r.returncode == 2, r.stdout + r.stderr
    assert "GPU backend cannot run here" in r.stderr and "Traceback" not in r.stderr
    assert not (tmp_path / "runs" / "logs").exists()   # no line was started


def test_a_run_on_the_gpu_is_another_run():
    # the GPU sums the ledger's terms (and quadratic drag's) in another order: its results are its own
    class Options:
        device = "cuda"
    mesh = dict(nodes=np.zeros((3, 2)), triangles=np.array([[0, 1, 2]]), attrs={})
    cpu, on_gpu = RI.identity({}, mesh, RunOptions()), RI.identity({}, mesh, Options())
    assert "device" not in cpu and on_gpu["device"] == "cuda"


@on_gpu_or_emulation
def test_a_model_on_the_gpu_steps_as_on_the_cpu():
    # the state read back between calls, as a run's chunks do, the GPU
    # keeping its own between them; the pulled end's reaction the CPU's bits
    cmp = gpu.compare_device(pulled_bar, 7, 2000, nodes="right")
    assert cmp["same"] and cmp["gpu_steps"] > 0 and cmp["remade"] == 1, cmp
    assert cmp["host_steps"] == cmp["host_makes"] > 0, cmp  # the splits' steps, the model's own


@on_gpu_or_emulation
def test_a_model_on_the_gpu_rebuilds_its_lists_in_place():
    # a flyer past a block at rest: the candidate lists are rebuilt on the
    # GPU's turn (counted in the model's timings), no step is the model's
    cmp = gpu.compare_device(lambda: landing_block_and_a_flyer(np.random.default_rng(4)), 4, 1000,
                             nodes="slab_bottom")
    assert cmp["same"] and cmp["list_rebuilds"] >= 5 and cmp["host_makes"] == 0, cmp


@on_gpu_or_emulation
def test_a_model_changed_between_calls_on_the_gpu_steps_as_on_the_cpu():
    # each change between two calls reaches the GPU's next steps: the steps
    # are made again from the model (a settle's end: drag on, damping off,
    # the ledger restarted; a resumed state)
    changes = [lambda m: m.set(local_damping=0.3), lambda m: m.reset_energy(),
               lambda m: m.set_velocities(0.5 * m.velocities)]
    cmp = gpu.compare_device(pulled_bar, 4, 1500, nodes="right", between=lambda m, k: changes[k](m))
    assert cmp["same"] and cmp["remade"] == 4, cmp
    # the copies to the GPU: the four makings and the stages made again within the steps
    assert cmp["makes"] >= 4 + cmp["host_makes"], cmp
