"""Run parameters: Table 1 defaults, range checks and the indenter ramp."""
import pytest

from icerubble import parameters as P
from icerubble.files.h5io import AtomicH5, open_complete


def test_defaults_are_table_1():
    d = P.validate({})
    assert d["tau_cr"] == 50e3 and d["sigma_cr"] == 10e3 and d["G"] == 15.0
    assert d["E"] == 2e9 and d["rho_i"] == 920.0 and d["rho_w"] == 1010.0
    assert d["c_w"] == 2.5e4 and d["penalty"] == 2e11 and d["v_final"] == 0.1


@pytest.mark.parametrize("name,value", [("tau_cr", 0.0), ("sigma_cr", -1.0), ("mu", -0.1),
                                        ("nu", 0.5), ("E", float("nan")), ("ramp_time", -1.0),
                                        ("force_direction", "sideways"), ("strength_bottom_fraction", 0.0)])
def test_bad_values_name_parameter_and_range(name, value):
    with pytest.raises(ValueError) as e:
        P.validate({name: value})
    assert name in str(e.value)
    assert "valid" in str(e.value)


def test_unknown_parameter_is_an_error():
    with pytest.raises(ValueError, match="tua_cr"):
        P.validate({"tua_cr": 5e3})


def test_ice_must_float():
    with pytest.raises(ValueError, match="rho_i"):
        P.validate({"rho_i": 1100.0})


def test_draft_is_density_ratio():
    d = P.validate({})
    assert P.water_line_draft(d) == pytest.approx(920.0 / 1010.0)


@pytest.mark.parametrize("name", sorted(P.MESH))
def test_geometry_is_refused_naming_the_scenes(name):
    """The geometry is the scene's mesh's: a geometry parameter asked of a run
    would be ignored, so it is refused, saying to pick a scene (and which)."""
    from icerubble.run.presets import SCENES
    with pytest.raises(ValueError, match=f"{name} is the scene's geometry.*pick a scene") as e:
        P.validate({name: 4.0}, scenes=SCENES)
    assert all(s in str(e.value) for s in SCENES)


def test_every_parameter_is_declared_once_with_unit_range_doc_and_group():
    for k, p in P.REGISTRY.items():
        assert p.group in P.GROUPS and p.unit and p.doc, k
        if p.default is not None:   # the default is valid
            assert P.check_value(k, p.default) == p.default or p.kind == "flag", k


def test_what_derives_from_the_registry():
    """Table columns, identity, settle key and the engine's keys are the registry's flags."""
    assert set(P.defaults()) == {k for k, p in P.REGISTRY.items() if p.table}
    assert not set(P.MESH) & set(P.defaults())
    assert set(P.SETTLE_FREE) == {"tau_cr", "sigma_cr", "G", "strength_bottom_fraction", "force_direction",
                                  "v_final", "ramp_time", "target_travel"}
    from icerubble.engine import model
    from icerubble.run import rest_states as RS
    from icerubble.run.punch_through_run import RunOptions
    assert RS.SETTLE_FREE == P.SETTLE_FREE and RS.SETTLE_OPTIONS == P.SETTLE_OPTIONS
    assert set(model.PARAMETERS) == set(P.ENGINE)
    # the engine's defaults are Table 1's where both name a value (drag_model included)
    for k in set(P.ENGINE) & set(P.TABLE_1) - set(model.START_UNSET):
        assert model.PARAMETERS[k][0] == P.REGISTRY[k].default, k
    options = RunOptions()
    for k in P.SETTLE_OPTIONS:
        assert getattr(options, k) == P.REGISTRY[k].default, k


def test_docs_parameter_table_is_the_registrys():
    """docs/parameters.md holds the table the registry makes (regenerate it with
    /usr/bin/python3 -m icerubble.parameters > docs/parameters.md)."""
    from tests.paths import ROOT
    import os
    with open(os.path.join(ROOT, "docs", "parameters.md")) as f:
        text = f.read()
    assert P.docs_table() in text, ("docs/parameters.md is not the registry's table: regenerate it "
                                    "(/usr/bin/python3 -m icerubble.parameters > docs/parameters.md)")


def test_atomic_file_only_appears_complete(tmp_path):
    path = tmp_path / "run.h5"
    with pytest.raises(RuntimeError):
        with AtomicH5(path, "icerubble-run") as f:
            f.create_dataset("x", data=[1.0])
            raise RuntimeError("interrupted")
    assert not path.exists() and (tmp_path / "run.h5.part").exists()
    with pytest.raises(ValueError, match="partially"):
        open_complete(str(tmp_path / "run.h5.part"))
    with AtomicH5(path, "icerubble-run") as f:
        f.create_dataset("x", data=[1.0])
    with open_complete(path, "icerubble-run") as f:
        assert f.attrs["complete"] == 1 and f["x"][0] == 1.0
    with pytest.raises(ValueError, match="format"):
        open_complete(path, "icerubble-pile")
    junk = tmp_path / "junk.h5"
    junk.write_text("not hdf5")
    with pytest.raises(ValueError, match="not an HDF5"):
        open_complete(junk)
