"""A stored result is handed back only for the run that made it (issue 11).

Result files are named by scene, ridge, mu and tau_cr; before run identities a
request for G = 1 J/m² (or 30 mm of travel) in a folder holding the default
run got the default run back. Now the result records a hash of every input,
and a request that differs in anything is refused with the difference named.
"""
import os

import h5py
import numpy as np
import pytest

from icerubble.run import run_identity as RI
from icerubble.study import line as study
from icerubble.run.punch_through_run import RunOptions
from icerubble import parameters as P


def fake_mesh(shift=0.0):
    return {"nodes": np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0 + shift]]),
            "triangles": np.array([[0, 1, 2]], dtype=np.int32),
            "body": np.array([0], dtype=np.int32),
            # ragged per-block data, as a real mesh file holds
            "polygons": [np.zeros((4, 2)), np.ones((5, 2))],
            "attrs": {"element_size": 0.15, "pile_friction": 0.05, "created": "today"}}


OPTIONS = RunOptions(dt_fraction=0.8, mass_scaling_dt=3e-6)


def ident(**over):
    return RI.identity(P.validate(dict(over)), fake_mesh(), OPTIONS)


def test_same_request_same_id_and_any_difference_changes_it():
    base = RI.run_id(ident())
    assert RI.run_id(ident()) == base
    for over in (dict(G=1.0), dict(sigma_cr=1e3), dict(target_travel=0.03), dict(viscosity=0.0)):
        assert RI.run_id(ident(**over)) != base, over
    assert RI.run_id(RI.identity(P.validate({}), fake_mesh(shift=1e-9), OPTIONS)) != base
    assert RI.run_id(RI.identity(P.validate({}), fake_mesh(), RunOptions(dt_fraction=0.5))) != base


def test_the_mesh_files_date_is_not_part_of_it():
    m = fake_mesh()
    m["attrs"]["created"] = "another day"
    assert RI.mesh_digest(m) == RI.mesh_digest(fake_mesh())


def test_differences_name_the_parameter_and_both_values():
    d = RI.differences(ident(), ident(G=1.0))
    assert len(d) == 1 and d[0].startswith("G: stored 15") and "asked 1.0" in d[0]


@pytest.fixture
def folder(tmp_path, monkeypatch):
    """run_one with the scene files and the engine stubbed out: only the
    bookkeeping around an existing result is exercised."""
    monkeypatch.setattr(study, "scene_files", lambda *a, **k: (None, "mesh.h5"))
    monkeypatch.setattr(study, "read_mesh", lambda path: fake_mesh())

    class NoRun:
        def __init__(self, *a, **k):
            raise AssertionError("the run was computed, not looked up")
    monkeypatch.setattr(study, "PunchThrough", NoRun)
    return tmp_path


def store(folder, identity_attr):
    name = study.run_name("small", 1, P.validate({}))
    path = folder / (name + ".h5")
    with h5py.File(path, "w") as f:
        f.attrs["complete"] = 1
        if identity_attr is not None:
            f.attrs["run_identity"] = RI.to_json(identity_attr)
    return str(path)


def test_a_stored_result_of_the_same_request_is_handed_back(folder):
    sc_params = study.scene("small")["params"]
    stored = RI.identity(P.validate(dict(sc_params)), fake_mesh(),
                         RunOptions(dt_fraction=0.8, mass_scaling_dt=3e-6))
    path = store(folder, stored)
    assert study.run_one("small", 1, out_dir=str(folder)) == path


@pytest.mark.parametrize("over, named", [(dict(G=1.0), "G: stored 1.0, asked 15"),
                                         (dict(sigma_cr=1e3), "sigma_cr: stored 1000.0, asked 10000"),
                                         (dict(target_travel=0.01), "target_travel: stored 0.01, asked 0.03")])
def test_a_stored_result_of_another_request_is_refused_with_the_difference_named(folder, over, named):
    sc_params = study.scene("small")["params"]
    stored = RI.identity(P.validate(dict(sc_params, **over)), fake_mesh(),
                         RunOptions(dt_fraction=0.8, mass_scaling_dt=3e-6))
    store(folder, stored)
    with pytest.raises(ValueError, match=named):
        study.run_one("small", 1, out_dir=str(folder))


def test_a_stored_result_without_identity_is_refused(folder):
    store(folder, None)
    with pytest.raises(ValueError, match="records no run identity"):
        study.run_one("small", 1, out_dir=str(folder))


def test_a_run_in_progress_elsewhere_is_reported_at_once(tmp_path):
    out = str(tmp_path / "r.h5")
    with RI.RunLock(out):
        assert os.path.exists(out + ".lock")
        with pytest.raises(RuntimeError, match="being computed by process"):
            with RI.RunLock(out):
                pass
    assert not os.path.exists(out + ".lock")


def test_a_lock_left_by_a_dead_process_is_taken_over(tmp_path):
    out = str(tmp_path / "r.h5")
    import socket
    with open(out + ".lock", "w") as f:
        f.write(f"{socket.gethostname()} 999999999")
    with RI.RunLock(out) as lock:
        assert lock.held


@pytest.mark.parametrize("over, dt, fraction", [({}, 1e-6, "scene"), (dict(dt=5e-7), 5e-7, None)])
def test_a_dt_column_is_the_step_used_not_replaced(folder, monkeypatch, over, dt, fraction):
    """A table's dt is the run's step; without one the scene's fraction of the
    stable step sets it (before, a dt column was validated, then replaced)."""
    seen = {}

    class Capture:
        def __init__(self, mesh_path, out, params, options, meta, rest_dir=None):
            seen.update(dt=params["dt"], fraction=options.dt_fraction)
            raise RuntimeError("captured")
    monkeypatch.setattr(study, "PunchThrough", Capture)
    with pytest.raises(RuntimeError, match="captured"):
        study.run_one("small", 1, overrides=over, out_dir=str(folder))
    if fraction == "scene":
        fraction = study.numerics("small")["dt_fraction"]
    assert seen == dict(dt=dt, fraction=fraction)


def test_each_numerical_preset_is_its_own_run():
    """The presets change the result (sleeping, contact reach, step): they are
    part of the identity, and the faithful one is the identity of before."""
    params, mesh = P.validate({}), fake_mesh()
    ids = {name: RI.run_id(RI.identity(params, mesh, RunOptions.from_numerics(study.numerics("small", name),
                                                                               name=name)))
           for name in ("paper", "balanced", "fast")}
    assert len(set(ids.values())) == 3
    assert ids["paper"] == RI.run_id(RI.identity(params, mesh, OPTIONS))


def test_an_unknown_preset_is_refused_before_any_work(tmp_path):
    with pytest.raises(ValueError, match="numerics='quick' is unknown: valid values are balanced, fast, paper"):
        study.run_one("small", 1, out_dir=str(tmp_path), numerics_name="quick")
    assert os.listdir(tmp_path) == []
