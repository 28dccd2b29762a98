"""The discrete-only model's YADE coupling (icerubble/rigid_dem/yade_coupling.py)
in real YADE scenes (tests/rigid_dem/yade_scenes.py): friction per contact,
flotation and rise under the project's water law, turning at the right rate,
and an energy ledger that closes on YADE's integration."""
import json
import os
import subprocess

import numpy as np
import pytest

from tests.paths import ROOT

RHO_I, RHO_W, G, MU = 920.0, 1010.0, 9.81, 0.35


def run_scene(name, tmp_path):
    out = tmp_path / f"{name}.json"
    env = dict(os.environ, SCENE=name, OUT=str(out), OMP_NUM_THREADS="1")
    r = subprocess.run(["yade", "-n", "-x", os.path.join("tests", "rigid_dem", "yade_scenes.py")],
                       cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    return json.loads(out.read_text())


def test_two_blocks_pushed_opposite_ways_stay_with_the_projects_friction(tmp_path):
    coupled = run_scene("two_blocks_coupled", tmp_path)
    # within the tangential spring's give: 2 P / k_t at the end of its swing
    give = 2 * coupled["push"] / coupled["k_t"]
    assert np.all(np.abs(coupled["travel"]) <= 1.05 * give)
    # the same scene with YADE's own polyhedra friction: both slide (its shear
    # force is shared between contacts), which is why the coupling exists
    yade_law = run_scene("two_blocks_yade_friction", tmp_path)
    assert yade_law["travel"][0] > 1000 * give and yade_law["travel"][1] < -1000 * give


def test_a_block_floats_at_draft_rho_i_over_rho_w_in_yade(tmp_path):
    r = run_scene("floating_block", tmp_path)
    assert r["draft"] / r["h"] == pytest.approx(RHO_I / RHO_W, rel=1e-6)
    assert abs(r["angle"]) < 1e-9   # a flat plank stays flat


def test_a_submerged_block_rises_at_the_quadratic_drag_terminal_speed_in_yade(tmp_path):
    r = run_scene("rising_block", tmp_path)
    assert r["y"] < -0.5    # still deep: no surface effect yet
    net = (RHO_W - RHO_I) * G * r["w"] * r["h"]
    v_t = np.sqrt(2 * net / (RHO_W * 1.0 * r["w"]))   # broadside: L = w, C_d = 1
    assert r["vy"] == pytest.approx(v_t, rel=1e-4)


def test_a_turned_block_spins_at_torque_over_its_moment_about_z(tmp_path):
    # YADE turns a turned block's principal frame so that the prism's axis is
    # body x; its integrator then divided the torque by the wrong moment
    r = run_scene("turned_block_spin", tmp_path)
    assert r["omega"] == pytest.approx(r["torque"] * r["t"] / r["inertia_z"], rel=1e-9)


def test_the_energy_ledger_closes_on_yades_own_integration(tmp_path):
    # impacts, sliding friction, drag, buoyancy and turning: every force's work,
    # paid with the leapfrog's mean velocities, is the change of kinetic energy
    r = run_scene("ledger", tmp_path)
    scale = r["initial"] + abs(r["work_gravity"]) + abs(r["work_buoyancy"])
    assert r["worst_residual"] < 1e-10 * scale
    assert abs(r["residual"]) < 1e-10 * scale
    assert r["friction"] > 0.0 and r["drag"] > 0.0   # both only take energy out
