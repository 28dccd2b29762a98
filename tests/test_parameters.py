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
                                        ("nu", 0.5), ("E", float("nan")), ("keel_depth", -4.0),
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
