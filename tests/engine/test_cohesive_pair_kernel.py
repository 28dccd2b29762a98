"""The cohesive force kernel both backends run (bonds/cohesive_pair_kernel.hpp):
on the CPU, the engine's cohesive pass is that kernel, so what the GPU is
compared with (gpu.compare_cohesive) is what a CPU run computes. In CI, where
no GPU exists, this checks the kernel's CPU side through the rigid phase,
softening and failure of the bar's pairs, for both force directions."""
import numpy as np
import pytest

from icerubble import _engine
from tests.engine.gpu_scenes import opened_bar


@pytest.mark.parametrize("direction", ["paper", "work_conjugate"])
def test_the_engines_cohesive_pass_is_the_kernel(direction):
    states = 0
    for m in opened_bar(direction=direction):
        m.evaluate()
        own = m.forces("cohesive")
        m._m.evaluate_before_cohesive()   # the forces the pass read
        ref = _engine.cohesive_fields(m._m)
        assert np.array_equal(own[:, 0], ref["f_coh_x"]) and np.array_equal(own[:, 1], ref["f_coh_y"])
        # the + and - nodes of a pair take opposite forces: momentum is kept
        assert np.sum(ref["f_coh_x"]) == pytest.approx(0.0, abs=1e-9 * np.abs(ref["fpx"]).max())
        states += 1
    assert states == 4 and ref["failed"].any()   # the last state runs the failure branch
