"""The cohesive force kernel both backends run (bonds/cohesive_pair_kernel.hpp):
on the CPU, the engine's cohesive pass is that kernel, so what the GPU is
compared with (gpu.compare_cohesive) is what a CPU run computes. In CI, where
no GPU exists, this checks the kernel's CPU side through the rigid phase,
softening and failure of the opened pairs of a bonded square, for both force
directions."""
import numpy as np
import pytest

from icerubble import _engine
from tests.engine.gpu_scenes import opened_square


@pytest.mark.parametrize("direction", ["paper", "work_conjugate"])
def test_the_engines_cohesive_pass_is_the_kernel(direction):
    states = 0
    for m in opened_square(np.random.default_rng(3), direction=direction):
        m.evaluate()
        own = m.forces("cohesive")
        m._m.evaluate_before_cohesive()   # the forces the pass read
        ref = _engine.cohesive_fields(m._m)
        assert np.array_equal(own[:, 0], ref["f_coh_x"]) and np.array_equal(own[:, 1], ref["f_coh_y"])
        # the + and - nodes of a pair take opposite forces: momentum is kept
        scale = np.abs(ref["fpx"]).max(initial=0.0) + np.abs(ref["fpy"]).max(initial=0.0)
        assert abs(np.sum(ref["f_coh_x"])) <= 1e-12 * scale and abs(np.sum(ref["f_coh_y"])) <= 1e-12 * scale
        states += 1
    assert states == 4 and ref["failed"].any()   # the last state runs the failure branch
    assert len(ref["fpx"]) > 0
