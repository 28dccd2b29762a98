"""The step's bond check reads the model and returns a split plan; the
topology stage splits exactly the planned points (docs/freeze_bonds.md "What
happens each step"). The plan is computed here by the same kernel outside a
step (what the GPU backend hands the host) and compared with what the next
committed step splits."""
import numpy as np
import pytest

from icerubble import _engine
from tests.engine.gpu_scenes import bonded_square


@pytest.mark.parametrize("seed", [1, 2, 3, 4])
def test_the_step_splits_the_points_of_the_plan(seed):
    m = bonded_square(np.random.default_rng(seed))
    m.set_bond_params(screen_interval=1)  # every point checked every step
    m.evaluate()
    record = [np.array(t) for t in m.bonds.tractions()]
    plan = _engine.bond_check_fields(m._m)["plan"]
    # the check outside the step left the bonds' own record as it was
    assert all(np.array_equal(a, np.array(b), equal_nan=True) for a, b in zip(record, m.bonds.tractions()))
    assert m.bonds.counts["split"] == 0
    m.step(1)
    split_now = np.flatnonzero(m.bonds.state()["point_state"] != 0)
    assert np.array_equal(split_now, plan)


def test_seeds_give_both_outcomes():
    """The scene is strong enough that some points stay intact and weak
    enough that some split: the comparison above is not vacuous."""
    counts = []
    for seed in (1, 2, 3, 4):
        m = bonded_square(np.random.default_rng(seed))
        m.evaluate()
        counts.append(len(_engine.bond_check_fields(m._m)["plan"]))
    assert max(counts) > 0 and min(counts) < m.bonds.counts["points"]
