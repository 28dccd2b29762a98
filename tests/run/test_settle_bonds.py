"""Bonds checked while settling (settle_bonds='checked', issue 26): the loading
starts from a balance the bonds can carry. On the two-row brick scene.

- with bonds too weak for the blocks' own weight, points split while
  settling, the settle still ends at rest, no intact point is past eq 5 when
  the loading starts, and the result books those splits to the initial state
  (t_split < 0, y_I_split NaN: no analysis counts them as the punch-through's);
- where no point reaches eq 5, checking is only reading: the rest state is
  the held settle's, bit for bit;
- the settle then reads the bond strengths: they are in its key.
"""
import os

import h5py
import numpy as np
import pytest

from icerubble import _engine
from icerubble import parameters as P
from icerubble.files.h5io import open_complete
from icerubble.run import rest_states as RS
from icerubble.run import run_identity as RI
from icerubble.run.punch_through_run import PunchThrough, RunOptions
from tests.run.punch_through_scenes import brick_mesh
from tests.run.test_punch_through import PARAMS
from tests.run.test_rest_states import OPTS, REST_HOW_MADE, _same, _tree

CHECKED = dict(PARAMS, settle_bonds="checked")
# a quarter of Table 1's strengths: a settle checking them splits points under
# the blocks' weight (6 of the scene's 113; at Table 1's, 2)
WEAK = dict(tau_cr=12.5e3, sigma_cr=2.5e3)


@pytest.fixture(scope="module")
def mesh_path(tmp_path_factory):
    return brick_mesh(tmp_path_factory.mktemp("scene"))


def _max_ratio(run):
    """The largest eq 5 ratio over the intact bond points at the run's state."""
    run.model.evaluate()
    ratio = np.asarray(_engine.bond_check_fields(run.model._m)["ratio"], float)
    return float(np.nanmax(ratio)), int(np.count_nonzero(np.isfinite(ratio)))


def test_points_past_eq5_split_while_settling_and_belong_to_the_initial_state(mesh_path, tmp_path):
    params = dict(CHECKED, **WEAK, target_travel=0.0005, ramp_time=0.01)
    run = PunchThrough(mesh_path, tmp_path / "weak.h5", params=params, options=RunOptions(**OPTS))
    run.settle_only(tmp_path / "rest.checkpoint.h5")
    assert run.state.settle_splits > 0
    ratio, intact = _max_ratio(run)
    assert intact > 0 and ratio < 1.0, (ratio, intact)   # the rest is carried by the bonds that are left
    run = PunchThrough(mesh_path, tmp_path / "weak.h5", params=params, options=RunOptions(**OPTS))
    run.run()
    with open_complete(tmp_path / "weak.h5") as f:
        t, y = f["bonds/t_split"][...], f["bonds/y_I_split"][...]
        n_settle = int(f.attrs["settle_splits"])
    assert n_settle > 0
    before = t < 0.0
    assert np.count_nonzero(before) == n_settle and np.isnan(y[before]).all()
    after = np.isfinite(t) & ~before
    assert np.isfinite(y[after]).all() and (y[after] >= 0.0).all()
    # the summary counts them apart from the punch-through's splits
    from icerubble.files.results import load
    from postproc.summary import summarize
    row = summarize(load(tmp_path / "weak.h5"))
    assert row["n_split_settle"] == n_settle and row["n_split"] == np.count_nonzero(after)


def test_checking_bonds_that_hold_changes_nothing(mesh_path, tmp_path):
    """Bonds ten times Table 1's strength: no point reaches eq 5 while the
    brick scene settles (at Table 1's, 2 of its 113 do), so the checked
    settle's rest state is the held one's bit for bit (the check only reads
    the model: its split plan is empty)."""
    strong = dict(tau_cr=500e3, sigma_cr=100e3)
    rests = []
    for name, params in (("held", dict(PARAMS, **strong)), ("checked", dict(CHECKED, **strong))):
        run = PunchThrough(mesh_path, tmp_path / f"{name}.h5", params=params, options=RunOptions(**OPTS))
        rests.append(run.settle_only(tmp_path / f"rest_{name}.checkpoint.h5"))
        assert run.state.settle_splits == 0
    with h5py.File(rests[0]) as fa, h5py.File(rests[1]) as fb:
        a, b = _tree(fa), _tree(fb)
    assert set(a) == set(b)
    differ = sorted(k for k in a if not _same(a[k], b[k]) and k not in REST_HOW_MADE)
    # beside the parameters, only the check's own record: how often it ran and
    # which points its screen keeps near eq 5 (docs/freeze_bonds.md)
    assert differ == ["/driver@params", "/engine/bond_state/near", "/engine/bond_state@checks"], differ


def test_a_checked_settle_reads_the_bond_strengths(mesh_path):
    assert set(P.settle_free(CHECKED)) == set(P.SETTLE_FREE) - set(P.BOND_STRENGTH)
    assert P.settle_free(PARAMS) == P.SETTLE_FREE
    run = PunchThrough(mesh_path, os.devnull + ".h5", params=PARAMS, options=RunOptions(**OPTS))
    key = lambda params: RI.run_id(RS.settle_identity(dict(run.params, **params), run.mesh,  # noqa: E731
                                                      RunOptions(**OPTS), 1))
    assert key(CHECKED) != key(PARAMS)
    for k, v in (("tau_cr", 1.0), ("G", 0.01), ("force_direction", P.OTHER_FORCE_DIRECTION)):
        assert key(dict(CHECKED, **{k: v})) != key(CHECKED), k
        assert key(dict(PARAMS, **{k: v})) == key(PARAMS), k
    assert key(dict(CHECKED, v_final=0.05)) == key(CHECKED)
