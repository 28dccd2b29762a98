"""A checkpoint is checked as a whole before a run resumes from it (issue 11):
a damaged or foreign one is refused with the file and the dataset named, and
nothing is run or written."""
import shutil

import h5py
import numpy as np
import pytest

from icerubble.run.punch_through_run import PunchThrough, RunOptions
from tests.run.punch_through_scenes import brick_mesh

PARAMS = dict(dt=5e-6, penalty=2e10, target_travel=0.003, ramp_time=0.2, damping=0.1)


def options(**kw):
    return RunOptions(threads=1, progress_every_s=1e9, vtu=False, **kw)


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    """A mesh and the checkpoint of a run stopped while loading."""
    d = tmp_path_factory.mktemp("ckpt")
    mesh = brick_mesh(d)
    run = PunchThrough(mesh, d / "run.h5", params=PARAMS, options=options(stop_after_steps=30000))
    with pytest.raises(KeyboardInterrupt):
        run.run()
    assert run.state.phase == "load"
    return mesh, d / "run.checkpoint.h5"


def _replace(f, name, data):
    del f[name]
    f.create_dataset(name, data=data)


def damage_missing_positions(f):
    del f["engine/positions"]


def damage_positions_shape(f):
    _replace(f, "engine/positions", f["engine/positions"][:-1])


def damage_nan_velocities(f):
    v = f["engine/velocities"][...]
    v[3, 0] = np.nan
    _replace(f, "engine/velocities", v)


def damage_triangle_ids(f):
    t = f["engine/triangles"][...]
    t[0, 0] = 10 ** 6
    _replace(f, "engine/triangles", t)


def damage_float_triangles(f):
    _replace(f, "engine/triangles", f["engine/triangles"][...].astype(float))


def damage_phase(f):
    f["driver"].attrs["phase"] = "unloading"


def damage_params(f):
    f["driver"].attrs["params"] = "{not json"


def damage_clock(f):
    g = f["engine/clock"]
    g.attrs["step_count"] = -5


def damage_recorder(f):
    del f["recorder"]


def damage_node_set(f):
    name = next(iter(f["engine/node_sets"]))
    _replace(f, f"engine/node_sets/{name}", np.array([-1, 2]))


def damage_energy_rows(f):
    _replace(f, "recorder/energy_rows", np.zeros((3, 2)))


CASES = [
    (damage_missing_positions, "dataset 'engine/positions': missing"),
    (damage_positions_shape, "dataset 'engine/positions': shape"),
    (damage_nan_velocities, "dataset 'engine/velocities': 1 non-finite values"),
    (damage_triangle_ids, "dataset 'engine/triangles': node ids"),
    (damage_float_triangles, "dataset 'engine/triangles': dtype float64, expected integers"),
    (damage_phase, "driver/phase is 'unloading'"),
    (damage_params, "driver/params is not JSON"),
    (damage_clock, "step_count=-5"),
    (damage_recorder, "group 'recorder' missing"),
    (damage_node_set, "node ids outside"),
    (damage_energy_rows, "dataset 'recorder/energy_rows': shape (3, 2)"),
]


@pytest.mark.parametrize("damage, message", CASES, ids=[c[0].__name__ for c in CASES])
def test_a_damaged_checkpoint_is_refused_before_any_work(saved, tmp_path, damage, message):
    mesh, ckpt = saved
    out = tmp_path / "run.h5"
    mine = tmp_path / "run.checkpoint.h5"
    shutil.copy(ckpt, mine)
    with h5py.File(mine, "a") as f:
        damage(f)
    before = mine.read_bytes()
    run = PunchThrough(mesh, out, params=PARAMS, options=options())
    with pytest.raises(ValueError) as e:
        run.run(resume=True)
    assert str(mine) in str(e.value) and message in str(e.value)
    assert run.model.step_count == 0       # nothing was run
    assert not out.exists()                # nothing written
    assert mine.read_bytes() == before     # the checkpoint is left as it was


def test_the_intact_checkpoint_passes_and_resumes(saved, tmp_path):
    mesh, ckpt = saved
    shutil.copy(ckpt, tmp_path / "run.checkpoint.h5")
    run = PunchThrough(mesh, tmp_path / "run.h5", params=PARAMS, options=options())
    run.run(resume=True)
    assert (tmp_path / "run.h5").exists()
