"""The engine's parameters cross the binding as one struct, checked once, in
C++, against the registry's ranges (issue 27, item 1): the build writes the
ranges of icerubble/parameters.py into the engine, so the engine refuses
exactly what the registry's own check refuses."""
import math

import numpy as np
import pytest

from icerubble import _engine, engine
from icerubble import parameters as P
from icerubble.engine.model import START_UNSET, STRUCT


def square():
    nodes = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    return engine.Model(nodes, [[0, 1, 2], [0, 2, 3]], [0, 0], materials=dict(E=2e9, rho=920.0))


def probes(spec):
    """Values on, inside and just outside each bound of a registry range."""
    values = [math.nan, math.inf, -math.inf, 0.0, 1.0, -1.0, 1e300]
    for b in (spec.lo, spec.hi):
        if b is not None:
            step = max(abs(b), 1.0) * 1e-12
            values += [b, b - step, b + step]
    if spec.kind == "whole":
        values = [v for v in values if not math.isfinite(v) or v == math.floor(v)] + [0.5]
    return values


def engine_accepts(m, name, value):
    try:
        m.set(**{name: int(value) if P.REGISTRY[name].kind == "whole" and math.isfinite(value) else value})
        return True
    except ValueError:
        return False


def registry_accepts(name, value):
    try:
        P.check_value(name, int(value) if P.REGISTRY[name].kind == "whole" and math.isfinite(value) else value)
        return True
    except ValueError:
        return False


def test_the_struct_has_the_registrys_engine_parameters():
    assert set(_engine.engine_parameter_names()) == set(STRUCT)
    assert set(STRUCT) | set(START_UNSET) == set(P.ENGINE)


@pytest.mark.parametrize("name", [k for k, p in P.ENGINE.items() if p.kind in ("number", "whole")])
def test_the_engine_refuses_what_the_registry_refuses(name):
    m = square()
    spec = P.REGISTRY[name]
    for v in probes(spec):
        if name == "threads" and v > 64:
            continue    # a valid count, but not one to run this test with
        assert engine_accepts(m, name, v) == registry_accepts(name, v), (name, v)


def test_a_refusal_names_the_parameter_and_the_registrys_range():
    m = square()
    spec = P.REGISTRY["C_d"]
    with pytest.raises(ValueError) as err:
        m.set(C_d=spec.hi * 2)
    assert "C_d" in str(err.value) and spec.range_text() in str(err.value)
    # nothing changed: the struct is checked whole before any of it is taken
    assert m._m.parameters()["C_d"] == spec.default


def test_a_bad_value_leaves_every_parameter_as_it_was():
    m = square()
    before = m._m.parameters()
    with pytest.raises(ValueError, match="mu"):
        m.set(penalty=1e9, mu=-0.1)
    assert m._m.parameters() == before


def test_types_are_checked_before_ranges():
    m = square()
    with pytest.raises(ValueError, match="not a number"):
        m.set(mu=True)      # True would be 1.0 to a double
    with pytest.raises(ValueError, match="True or False"):
        m.set(gravity=1)
    with pytest.raises(ValueError, match="whole number"):
        m.set(threads=1.5)
    with pytest.raises(ValueError, match="drag_model"):
        m.set(drag_model="cubic")


def test_the_struct_is_whole_or_refused():
    m = square()
    full = m._m.parameters()
    with pytest.raises(ValueError, match="missing parameter.*mu"):
        m._m.set_parameters({k: v for k, v in full.items() if k != "mu"})
    with pytest.raises(ValueError, match="unknown parameter.*keel_depth"):
        m._m.set_parameters(dict(full, keel_depth=4.0))


def test_a_model_without_parameters_refuses_to_run():
    raw = _engine.Model(np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]), np.array([[0, 1, 2]], np.int32),
                        np.array([0], np.int32))
    raw.set_material(0, 2e9, 0.3, 920.0, 0.0)
    with pytest.raises(ValueError, match="parameters are not set"):
        raw.stable_step()


def test_the_engine_holds_what_was_set():
    m = square()
    m.set(mu=0.05, penalty=1e10, drag_model="linear", sleeping=True, sleep_quiet_steps=7)
    p = m._m.parameters()
    assert (p["mu"], p["penalty"], p["drag_model"], p["sleeping"], p["sleep_quiet_steps"]) == \
        (0.05, 1e10, "linear", True, 7)
