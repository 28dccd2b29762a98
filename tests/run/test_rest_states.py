"""Shared rest states (icerubble/run/rest_states.py): runs that differ only in
what the settle never reads settle once, and a run from another's rest state
is the run that settles itself, bit for bit. On the two-row brick scene."""
import os
import shutil

import h5py
import numpy as np
import pytest

from icerubble import parameters as P
from icerubble.files.h5io import open_complete
from icerubble.run import rest_states as RS
from icerubble.run import run_identity as RI
from icerubble.run.punch_through_run import PunchThrough, RunOptions
from tests.run.punch_through_scenes import brick_mesh
from tests.run.test_punch_through import PARAMS

OPTS = dict(threads=1, progress_every_s=1e9, vtu=False)
# Every parameter the settle is said not to read, changed. The strengths are
# so low that a settle that checked them would split bond points under the
# blocks' own weight.
OTHER = dict(tau_cr=1.0, sigma_cr=1.0, G=0.01, strength_bottom_fraction=0.5, force_direction=P.OTHER_FORCE_DIRECTION,
             v_final=0.05, ramp_time=0.1, target_travel=0.006)


@pytest.fixture(scope="module")
def mesh_path(tmp_path_factory):
    return brick_mesh(tmp_path_factory.mktemp("scene"))


def test_settle_free_is_the_whole_difference_between_the_shared_keys():
    assert set(OTHER) == set(RS.SETTLE_FREE)


def _tree(g, prefix=""):
    """{path: value} of every dataset and attribute under h5 group g."""
    out = {f"{prefix}@{a}": g.attrs[a] for a in g.attrs}
    for k, v in g.items():
        if isinstance(v, h5py.Group):
            out.update(_tree(v, f"{prefix}/{k}"))
        else:
            out[f"{prefix}/{k}"] = v[()]
    return out


# entries of a rest state that say when and how long it took to make, not what it is
REST_HOW_MADE = {"@created", "/driver@wall_settle_s", "/driver@wall_load_s"}


def _same(x, y):
    x, y = np.asarray(x), np.asarray(y)
    nan_ok = x.dtype.kind == "f" and y.dtype.kind == "f"   # a NaN is "not yet" (bond events)
    return np.array_equal(x, y, equal_nan=nan_ok)


def preset_like(mesh_path, tmp_path):
    """The options of the study's presets on this scene: a fraction of the
    stable step, selective mass scaling, a local contact reach and a settle
    at a larger step (as `balanced`)."""
    dt0 = PunchThrough(mesh_path, tmp_path / "x.h5", params=PARAMS,
                       options=RunOptions(**OPTS)).model.stable_time_step()["dt"]
    return dict(dt_fraction=0.8, mass_scaling_dt=1.5 * dt0, contact_reach=0.05, settle_mass_scaling_dt=3 * dt0)


@pytest.mark.parametrize("numerics", ["plain", "preset"])
def test_the_settle_reads_none_of_the_settle_free_parameters(mesh_path, tmp_path, numerics):
    """Two settles, of runs that differ in every SETTLE_FREE parameter, end
    in the same rest state bit for bit: positions, velocities, masses, bond
    states, friction, clock, energy ledger, settle record. Only the bond
    strengths, the force direction and the parameters themselves differ.
    With the scene's own step, and with the presets' numerics."""
    opts = dict(OPTS, **(preset_like(mesh_path, tmp_path) if numerics == "preset" else {}))
    rests = []
    for name, params in (("a", PARAMS), ("b", dict(PARAMS, **OTHER))):
        run = PunchThrough(mesh_path, tmp_path / f"{name}.h5", params=params, options=RunOptions(**opts))
        rests.append(run.settle_only(tmp_path / f"rest_{name}.checkpoint.h5"))
    with h5py.File(rests[0]) as fa, h5py.File(rests[1]) as fb:
        a, b = _tree(fa), _tree(fb)
    assert set(a) == set(b)
    differ = sorted(k for k in a if not _same(a[k], b[k]) and k not in REST_HOW_MADE)
    own = ["/driver@params", "/engine/bond_input/G", "/engine/bond_input/sigma_cr",
           "/engine/bond_input/tau_cr", "/engine/bond_params@direction", "/recorder/pending_snaps"]
    assert differ == [k for k in own if k in a], "\n".join(differ)
    assert len(a["/engine/bond_input/node"]) > 20 and a["/driver@phase"] in ("load", b"load")


def test_the_key_holds_what_the_settle_reads(mesh_path):
    run = PunchThrough(mesh_path, os.devnull + ".h5", params=PARAMS, options=RunOptions(**OPTS))
    key = lambda params=PARAMS, options=RunOptions(**OPTS), threads=1: RI.run_id(  # noqa: E731
        RS.settle_identity(dict(run.params, **params), run.mesh, options, threads))
    assert key(dict(PARAMS, **OTHER)) == key()
    for changed in (dict(mu=0.1), dict(E=3e9), dict(penalty=3e10), dict(dt=4e-6), dict(rho_w=1020.0)):
        assert key(dict(PARAMS, **changed)) != key(), changed
    assert key(threads=2) != key()
    assert key(options=RunOptions(settle_velocity=2e-4, **OPTS)) != key()
    assert key(options=RunOptions(mass_scaling_dt=1e-5, **OPTS)) != key()


# root attributes of a result that name how it was made, not what it is
HOW_MADE = {"created", "wall_settle_s", "wall_load_s", "step_timings", "rest_state_from", "rest_state_shared",
            "rest_state_code_version"}


def _records(path):
    """Every dataset and attribute of a result (force, energy ledger, bond
    events, snapshots, parameters ...), and its root attributes apart."""
    with open_complete(path) as f:
        out = {k: v for k, v in _tree(f).items() if not (k.startswith("@") and k[1:] in HOW_MADE)}
        return out, dict(f.attrs)


def test_a_run_from_a_shared_rest_state_is_the_run_that_settles_itself(mesh_path, tmp_path, capsys):
    """Run a settles and shares its rest state; run b, other bond strengths,
    force direction, ramp and travel, loads from it; b's result is that of the
    same run settling itself, bit for bit, every dataset and attribute but the
    wall times and the rest state's name (with a's strengths it would not be:
    its bond points fail otherwise than a's). With the presets' numerics."""
    shared = tmp_path / "scene"
    shared.mkdir()
    opts = dict(OPTS, **preset_like(mesh_path, tmp_path))   # the study's numerics
    weaker = dict(PARAMS, tau_cr=20e3, sigma_cr=4e3, G=5.0, force_direction="work_conjugate",
                  ramp_time=0.15, target_travel=0.0025)
    a = PunchThrough(mesh_path, tmp_path / "a.h5", params=PARAMS, options=RunOptions(**opts), rest_dir=shared)
    a.run()
    assert "rest state shared as" in capsys.readouterr().out
    assert len(os.listdir(shared)) == 1
    # b is stopped in the middle of its loading and resumed from its own checkpoint
    b = PunchThrough(mesh_path, tmp_path / "b.h5", params=weaker, rest_dir=shared,
                     options=RunOptions(stop_after_steps=a.model.step_count // 2, **opts))
    with pytest.raises(KeyboardInterrupt):
        b.run()
    assert "loads from the shared rest state" in capsys.readouterr().out and b.state.phase == "load"
    b = PunchThrough(mesh_path, tmp_path / "b.h5", params=weaker, options=RunOptions(**opts), rest_dir=shared)
    b.run(resume=True)
    assert "resumed from" in capsys.readouterr().out
    # and again in one go
    PunchThrough(mesh_path, tmp_path / "b1.h5", params=weaker, options=RunOptions(**opts), rest_dir=shared).run()
    own = PunchThrough(mesh_path, tmp_path / "own.h5", params=weaker, options=RunOptions(**opts))
    own.run()
    (ro, _), (ra, _) = _records(tmp_path / "own.h5"), _records(tmp_path / "a.h5")
    assert {"/force/F", "/energy/residual", "/bonds/t_fail", "/parameters@tau_cr", "@settle_mass_scaling_dt"} <= set(ro)
    for name in ("b1", "b"):
        rb, attrs = _records(tmp_path / f"{name}.h5")
        assert set(rb) == set(ro), name
        assert [k for k in ro if not _same(rb[k], ro[k])] == [], name
    assert attrs["rest_state_shared"] == 1 and attrs["rest_state_from"] == os.path.join(shared, os.listdir(shared)[0])
    assert attrs["rest_state_code_version"]
    assert np.isfinite(ro["/bonds/t_fail"]).sum() > 0
    assert not _same(ra["/bonds/t_split"], ro["/bonds/t_split"])
    # another friction coefficient is another settle: it settles itself
    c = PunchThrough(mesh_path, tmp_path / "c.h5", params=dict(PARAMS, mu=0.5), options=RunOptions(**opts),
                     rest_dir=shared)
    assert c.shared_rest[0] != a.shared_rest[0]
    # and a rest state at its name that another settle made is refused, naming the difference
    shutil.copy(a.shared_rest[0], c.shared_rest[0])
    with pytest.raises(ValueError, match=r"not made by this run.s settle \(mu: stored 0.3, asked 0.5"):
        c.run()


def test_a_damaged_shared_rest_state_is_settled_again_and_replaced(mesh_path, tmp_path, capsys):
    """A file at the rest state's name that cannot be read (damaged outside:
    the runs write whole files and rename them) does not stop the runs of
    its key: the next settles itself, says so, and writes it again."""
    shared = tmp_path / "scene"
    shared.mkdir()
    run = PunchThrough(mesh_path, tmp_path / "a.h5", params=PARAMS, options=RunOptions(**OPTS), rest_dir=shared)
    path = run.shared_rest[0]
    with open(path, "wb") as f:
        f.write(b"not an HDF5 file")
    run.run()
    out = capsys.readouterr().out
    assert "shared rest state cannot be read" in out and "rest state shared as" in out
    with open_complete(path) as f:
        assert f["driver"].attrs["settle_identity"] == run.shared_rest[1]
    own = PunchThrough(mesh_path, tmp_path / "own.h5", params=PARAMS, options=RunOptions(**OPTS))
    own.run()
    ra, ro = _records(tmp_path / "a.h5")[0], _records(tmp_path / "own.h5")[0]
    assert [k for k in ro if not _same(ra[k], ro[k])] == []
