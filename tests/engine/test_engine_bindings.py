"""The engine's own time step (set_dt_fraction), load ramp and bond-state codes."""
import numpy as np
import pytest

from icerubble import _engine
from tests.engine.freeze_bonds_scenes import pull_bar


def test_dt_fraction_is_the_fraction_of_the_stable_step_now():
    m = pull_bar()[0]
    m.set(mass_scaling_dt=2e-6)
    expected = 0.8 * m.stable_time_step()["dt"]   # what the driver computes today
    m._m.set_dt_fraction(0.8)
    assert m._m.dt == expected
    assert m._m.dt_control() == {"dt": expected, "source": "fraction", "fraction": 0.8}
    m.set(dt=1e-7)
    assert m._m.dt_control()["source"] == "explicit" and m._m.dt_control()["fraction"] is None
    for bad in (0.0, 1.5, float("nan")):
        with pytest.raises(ValueError, match=r"dt_fraction=.* is out of range: valid range \(0.0, 1.0\]"):
            m._m.set_dt_fraction(bad)


def test_ramp_velocity_is_the_prescribed_ramp():
    T, v = 2.0, 0.1
    t = np.array([-1.0, 0.0, 0.5, 1.0, 2.0, 3.0])
    s = t / T
    want = np.where(t <= 0, 0.0, np.where(t >= T, v, v * (s - np.sin(2 * np.pi * s) / (2 * np.pi))))
    assert np.array_equal(_engine.ramp_velocity(t, v, T), want)
    with pytest.raises(ValueError, match="ramp_time"):
        _engine.ramp_velocity(t, v, -1.0)


def test_bond_state_codes_are_the_exported_enums():
    assert [int(_engine.PairState.intact), int(_engine.PairState.cohesive),
            int(_engine.PairState.failed)] == [0, 1, 2]
    assert [int(_engine.PointState.intact), int(_engine.PointState.split)] == [0, 1]
    assert [int(_engine.FailureMode.tensile), int(_engine.FailureMode.shear)] == [1, 2]


def test_result_files_and_the_engine_name_failure_modes_alike():
    """/bonds/mode is written from the engine's codes and read by postproc
    with its own enum (postproc needs no compiled engine): the two agree."""
    from icerubble.files.results import FailureMode
    assert {m.name: int(m) for m in FailureMode} == \
        {k: int(v) for k, v in _engine.FailureMode.__members__.items()}
