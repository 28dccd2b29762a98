"""The YADE punch-through script and the study helpers refuse bad input before any work."""
import os
import subprocess

import pytest

from icerubble.run.presets import SCENES, scene
from icerubble.study.line import run_name, run_one
from tests.paths import ROOT



def test_unknown_scene_is_refused():
    with pytest.raises(ValueError, match="scene"):
        scene("huge")


def test_bad_overrides_are_refused_before_the_pile_is_made(tmp_path):
    with pytest.raises(ValueError, match="tau_cr"):
        run_one("demo", ridge=1, overrides=dict(tau_cr=-5e3), out_dir=str(tmp_path))
    assert not (tmp_path / "scenes").exists()


def test_run_names_tell_the_study_apart():
    from icerubble import parameters as P
    a = run_name("paper", 2, P.validate(dict(mu=0.05, tau_cr=12.5e3, force_direction="paper")))
    b = run_name("paper", 2, P.validate(dict(mu=0.05, tau_cr=12.5e3, force_direction="work_conjugate")))
    assert a == "paper_ridge2_mu0.05_tau12.5k" and b == a + "_wc"
    # the name says the direction, whichever is the default (it changed: docs/model.md §3.3)
    assert run_name("paper", 2, P.validate(dict(mu=0.05, tau_cr=12.5e3))) == b


def test_every_scene_has_valid_parameters():
    from icerubble import parameters as P
    from icerubble.run.presets import NUMERICS
    from icerubble.run.punch_through_run import RunOptions
    for name, sc in SCENES.items():
        P.validate(sc["params"])
        assert set(NUMERICS[name]) == {"paper", "balanced", "fast"}
        for preset, settings in NUMERICS[name].items():
            assert 0 < settings["dt_fraction"] <= 1.0
            RunOptions.from_numerics(settings, name=preset)  # checks the sleep thresholds, reach


def test_yade_script_reports_a_bad_table_value(tmp_path):
    """A yade-batch line with a bad value stops at once with the parameter named."""
    table = tmp_path / "bad.table"
    table.write_text(f"description ridge mu tau_cr scene out_dir\nbad 1 -0.3 50e3 'demo' '{tmp_path}'\n")
    env = dict(os.environ, YADE_BATCH=f"{table}:2")
    r = subprocess.run(["yade", "-n", "-x", os.path.join(ROOT, "yade_scripts", "punch_through.py")],
                       env=env, capture_output=True, text=True, timeout=300)
    assert r.returncode != 0
    assert "mu" in (r.stdout + r.stderr) and "valid range" in (r.stdout + r.stderr)
    assert not (tmp_path / "scenes").exists()


def test_phase1_pile_is_reproducible_from_its_seed(tmp_path):
    """The same seed gives the same settled pile, bit for bit (one YADE thread)."""
    import h5py
    import numpy as np
    from icerubble.run.scene_cache import run_phase1
    piles = []
    for name in ("a.h5", "b.h5"):
        run_phase1(str(tmp_path / name), 3, dict(domain_width=5.0, n_blocks=6))
        with h5py.File(tmp_path / name) as f:
            piles.append(f["blocks/corners"][:])
    np.testing.assert_array_equal(piles[0], piles[1])
