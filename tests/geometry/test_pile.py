"""Phase 1 (paper section 2.4): the YADE pile settles at rest, in equilibrium, with small overlaps."""
import os
import subprocess

import h5py
import numpy as np
import pytest

from icerubble.files import pile_file
from icerubble.geometry import contact_resolution, meshing, pile
from tests.paths import ROOT

SCRIPT = os.path.join(ROOT, "yade_scripts", "make_pile.py")


def run_make_pile(tmp_path, name, **params):
    """One yade-batch table line run headless, as a user would (YADE_BATCH=table:2)."""
    out = tmp_path / f"{name}.h5"
    params = dict(params, out=f"'{out}'")
    table = tmp_path / f"{name}.table"
    table.write_text("description " + " ".join(params) + "\n" +
                     name + " " + " ".join(str(v) for v in params.values()) + "\n")
    env = dict(os.environ, YADE_BATCH=f"{table}:2", OMP_NUM_THREADS="1")
    proc = subprocess.run(["yade", "-n", "-x", SCRIPT], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=300)
    return proc, out


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("pile")
    proc, out = run_make_pile(tmp, "tiny", seed=3, n_blocks=8, domain_width=6.0)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    return pile_file.read_pile(str(out))


def _area(p):
    return abs(pile.polygon_area(p))


def test_pile_settles_at_rest(tiny):
    m, P = tiny["meta"], tiny["params"]
    assert m["settled"] == 1 and m["n_blocks"] == 8
    assert m["ke_per_block"] < P["ke_per_block"]
    assert tiny["corners"].shape == (8, 4, 2)
    # the blocks were generated with the documented sizes
    assert np.all((tiny["thickness"] >= 0.2) & (tiny["thickness"] <= 0.4))
    assert np.all((tiny["length"] >= 0.6) & (tiny["length"] <= 1.8))
    # rigid blocks keep their shape: every settled outline has its nominal area
    areas = np.array([_area(c) for c in tiny["corners"]])
    np.testing.assert_allclose(areas, tiny["thickness"] * tiny["length"], rtol=1e-9)


def _contact_scale(P, corners):
    """Net buoyancy F_b of the pile and k_n = E/2 (force = k_n x overlap volume, 1 m deep)."""
    F_b = (P["rho_w"] - P["rho_i"]) * P["g"] * sum(_area(c) for c in corners)
    return F_b, 0.5 * P["E_settle"]


def test_block_overlaps_within_contact_bound(tiny):
    # No contact can carry more than the whole pile's net buoyancy F_b; a
    # right-angled corner pushed a depth d into a face overlaps an area >= d^2,
    # so any overlap depth satisfies d <= sqrt(F_b / k_n).
    F_b, k_n = _contact_scale(tiny["params"], tiny["corners"])
    depth = contact_resolution.max_overlap_depth(list(tiny["corners"]))
    assert depth <= np.sqrt(F_b / k_n)
    m = tiny["meta"]
    assert tiny["corners"][:, :, 1].max() <= m["layer_bottom_y"] + np.sqrt(F_b / k_n)


def test_pile_in_vertical_equilibrium(tiny):
    # At rest the layer reaction k_n V_layer-overlap balances the net buoyancy
    # (rho_w - rho_i) g A, up to the wall friction (at most mu x wall normal force)
    # and the residual dynamics: the force imbalance of blocks vibrating at the
    # highest contact frequency omega with the final kinetic energy K is at most
    # omega sqrt(2 K M) (Cauchy-Schwarz over the blocks).
    P, m, C = tiny["params"], tiny["meta"], tiny["corners"]
    F_b, k_n = _contact_scale(P, C)
    yb, half = m["layer_bottom_y"], 0.5 * m["domain_width"]
    up = np.array([0.0, 1.0])
    F_layer = k_n * sum(_area(pile.clip_halfplane(c, -up, -yb)) for c in C if c[:, 1].max() > yb)
    V_side = sum(_area(pile.clip_halfplane(c, np.array([1.0, 0.0]), -half)) for c in C
                 if c[:, 0].min() < -half)
    V_side += sum(_area(pile.clip_halfplane(c, np.array([-1.0, 0.0]), -half)) for c in C
                  if c[:, 0].max() > half)
    omega = np.sqrt(4 * k_n / (P["rho_i"] * P["t_min"]))
    M = P["rho_i"] * sum(_area(c) for c in C)
    residual = omega * np.sqrt(2 * m["final_kinetic_energy"] * M)
    assert F_layer > 0.5 * F_b  # the pile really rests against the layer
    assert abs(F_layer - F_b) <= P["mu_settle"] * k_n * V_side + residual


def test_yade_pile_meshes_with_bonds(tiny):
    m = meshing.build_mesh(tiny, element_size=0.1)
    # resolved blocks do not overlap: bonded pairs touch on a line, others are apart
    assert contact_resolution.max_overlap_depth(m["resolved_blocks"]) <= 1e-9
    assert m["resolve_info"]["n_slivers"] == 0
    c = m["contacts"]
    assert c["bonded"].any(), "a settled pile must have bonded contacts"
    # every contact bonded by the rule is bonded in the mesh over at least its common
    # face (round-off only; the fuzzy fragment may join faces within `fuzzy` beyond it)
    assert np.all(c["bond_length"][c["bonded"]] >= c["chord"][c["bonded"]] - 1e-9)
    # unbonded contacts are kept apart by eps_sep > fuzzy: no bond edge at all
    assert np.all(c["bond_length"][~c["bonded"]] == 0.0)
    # and there is no bond between blocks that are not a contact of the rule
    nb = len(tiny["corners"])
    pairs = {(int(i), -1 if j >= nb else int(j)) for i, j in m["bond_edge_bodies"]}
    rule = {(min(i, j), max(i, j)) if j >= 0 else (i, -1) for i, j in c["bodies"][c["bonded"]]}
    assert pairs == rule


def test_hold_stage_brings_a_pile_formed_at_high_friction_to_rest_at_low(tmp_path):
    """The hold stage (the paper scene's piles): formed at mu 0.3, then held at
    0.05 with its face contacts stuck (the rigid-block friction law's stick,
    engine rigid/rigid_friction.hpp) until at rest again."""
    proc, out = run_make_pile(tmp_path, "held", seed=3, n_blocks=8, domain_width=6.0,
                              mu_settle=0.3, mu_hold=0.05)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    held = pile_file.read_pile(str(out))
    m, P = held["meta"], held["params"]
    assert m["settled"] == 1 and m["ke_per_block"] < P["ke_per_block"]
    assert m["hold_friction"] == 0.05 and m["friction"] == 0.3
    # 8 blocks under a layer: some meet the layer or each other on a face
    assert 0 < m["hold_frozen_contacts"] and m["hold_time"] > 0.0
    assert "face contacts frozen" in proc.stdout


def test_invalid_parameters_stop_before_work(tmp_path):
    for name, params, word in (("neg", dict(t_min=-0.1), "t_min"),
                               ("narrow", dict(domain_width=1.0), "domain_width"),
                               ("sink", dict(rho_w=900.0), "rho_w")):
        proc, out = run_make_pile(tmp_path, name, **params)
        assert proc.returncode != 0
        text = proc.stdout + proc.stderr
        assert word in text and "make_pile: error" in text and "Traceback" not in text
        assert not out.exists()


def test_compact_start_blocks_do_not_overlap():
    rng = np.random.default_rng(0)
    top = pile.layer_bottom_y()
    c, t, ln, _ = pile.compact_start(60, 10.0, top, rng)
    assert len(c) == 60
    assert c[:, :, 1].max() <= top - 0.03 + 1e-9 and np.abs(c[:, :, 0]).max() <= 5.0
    # the separating-axis depth is negative (a gap) for every pair
    assert contact_resolution.max_overlap_depth(list(c)) < 0
    area = pile.blocks_for_keel(10.0, 1.0, 0.25)
    c2, t2, l2, _ = pile.compact_start(None, 10.0, top, rng, n_area=area)
    assert np.sum(t2 * l2) >= area > np.sum(t2[:-1] * l2[:-1])


def test_porosity_and_keel_bounds_of_known_rectangles():
    top = -0.9
    left = pile.rectangle((-2.0, top - 0.5), 4.0, 1.0, 0.0)   # 4 m x 1 m
    right = pile.rectangle((2.0, top - 1.0), 4.0, 2.0, 0.0)   # 4 m x 2 m
    b = pile.keel_bounds([left, right], top, -4.0, 4.0)
    # half the columns are 1 m deep, half 2 m: mean bottom 1.5 m below the top
    assert b == pytest.approx((-4.0, 4.0, top - 1.5, top), abs=1e-12)
    # region 8 m x 1.5 m holds 4 + 6 m^2 of ice: eta = 1 - 10/12
    assert pile.porosity([left, right], b) == pytest.approx(1 - 10.0 / 12.0, abs=1e-12)


def test_read_pile_rejects_other_files(tmp_path):
    txt = tmp_path / "notes.txt"
    txt.write_text("not a pile")
    with pytest.raises(ValueError, match="not an HDF5"):
        pile_file.read_pile(str(txt))
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as f:
        f.attrs["format"] = "icerubble-run"
    with pytest.raises(ValueError, match="expected 'icerubble-pile'"):
        pile_file.read_pile(str(other))
    with pytest.raises(ValueError, match="does not exist"):
        pile_file.read_pile(str(tmp_path / "missing.h5"))


def test_pile_file_round_trip(tmp_path):
    c = np.array([pile.rectangle((0, -1.5), 1.0, 0.3, 0.2)])
    path = str(tmp_path / "p.h5")
    pile_file.write_pile(path, c, [0.3], [1.0], dict(seed=4), dict(n_blocks=1, porosity=0.5))
    back = pile_file.read_pile(path)
    np.testing.assert_array_equal(back["corners"], c)
    assert back["params"]["seed"] == 4 and back["meta"]["complete"] == 1
    assert not os.path.exists(path + ".part")
