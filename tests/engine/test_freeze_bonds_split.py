"""Node splitting at bond points (paper section 2.3.2, Fig. 3): mass and
momentum conservation, no jump of the node accelerations (eq 8), the junction
and free-edge rules, and the crack faces joining the contact candidates."""
import numpy as np
import pytest

from icerubble import engine
from tests.engine.freeze_bonds_scenes import ICE, bonded, pull_bar, two_block_bar

SIGMA, TAU, G = 1e4, 5e4, 1.0


def momentum(m):
    return (m.mass[:, None] * m.velocities).sum(axis=0)


def test_split_keeps_mass_and_node_accelerations():
    """Twin bars, one with failure checking off (never splits): identical up to
    the splitting step. In that step the two new nodes must move with the
    unsplit node's acceleration (eq 8 makes the pair force exactly the one
    that does this) and carry its mass (m+ + m- = m, each the third of its
    side's triangles). Without the eq-8 force the nodes would accelerate by
    f+/m+ and f-/m-, 870-980 m/s² apart here; the comparison is at round-off of
    that (1e-9)."""
    a, bp, nodes, H = pull_bar(sigma_cr=SIGMA, tau_cr=TAU, G=G)
    b, _, _, _ = pull_bar(sigma_cr=SIGMA, tau_cr=TAU, G=G)
    b.set_bond_params(check_failure=False)
    dt = a.stable_time_step()["dt"] * 0.9
    mass_total = a.mass.sum()
    while True:
        va, vb = a.velocities, b.velocities
        n0 = a.n_nodes
        a.step(1)
        b.step(1)
        if a.bonds.counts["split"]:
            break
        np.testing.assert_array_equal(a.positions, b.positions)
    assert a.bonds.counts["split"] == len(bp)  # uniform stress: all in one step
    s = a.bonds.state()
    acc_b = (b.velocities - vb) / dt
    new = np.arange(n0, a.n_nodes)
    parent = s["parent"]
    va_full = np.vstack([va, va[parent]])  # the new nodes had the parent's velocity
    acc_a = (a.velocities - va_full) / dt
    f_int = a.forces("internal")
    jump = np.abs(f_int[s["node_plus"], 0] / a.mass[s["node_plus"]]
                  - f_int[s["node_minus"], 0] / a.mass[s["node_minus"]])
    assert jump.min() > 100.0  # what eq 8 has to cancel
    scale = jump.max()
    for k in range(len(bp)):
        node = bp.node[k]
        for copy in (s["node_plus"][k], s["node_minus"][k]):
            np.testing.assert_allclose(acc_a[copy], acc_b[node], rtol=0, atol=1e-9 * scale)
    # mass: total unchanged, split shares add up, each from its own side
    assert a.mass.sum() == pytest.approx(mass_total, rel=1e-14)
    tri, body, area = np.asarray(a.triangles), np.asarray(a.body), np.asarray(a.area0)
    for k in range(len(bp)):
        mp, mm = a.mass[s["node_plus"][k]], a.mass[s["node_minus"][k]]
        assert mp + mm == pytest.approx(b.mass[bp.node[k]], rel=1e-14)
        side = np.any(tri == s["node_minus"][k], axis=1)
        assert np.all(body[side] == 0)
        assert mm == pytest.approx(ICE["rho"] * area[side].sum() / 3, rel=1e-14)
    assert len(new) == len(bp) and np.all(np.isin(parent, bp.node))


def fly_apart(m, velocity_of_body, steps, every=10):
    """Free flight (no supports, no gravity) from body velocities; returns the
    momentum at every ``every`` steps and the largest |m v| sum for scale."""
    body = np.asarray(m.body)
    tri = np.asarray(m.triangles)
    v = np.zeros((m.n_nodes, 2))
    for b, vel in velocity_of_body.items():
        v[np.unique(tri[body == b])] = vel
    m.set_velocities(v)
    m.set(dt=0.9 * m.stable_time_step()["dt"])
    p0 = momentum(m)
    scale = (m.mass[:, None] * np.abs(m.velocities)).sum()
    out = []
    for _ in range(steps // every):
        m.step(every)
        out.append(momentum(m) - p0)
    return np.array(out), scale


def test_free_edge_bond_points_conserve_momentum():
    """Free-edge rule: the interface of the two-block bar ends on the free top
    and bottom surfaces; its end points are ordinary two-body bond points with
    l = half an edge. Blocks flung apart and sheared (tension wave rho c v ~ 7
    sigma_cr): every point splits, softens and fails; the cohesive pairs are
    equal and opposite, so momentum stays at its initial value to round-off
    (1e-12 of sum m|v|)."""
    m, bp, nodes = two_block_bar(sigma_cr=SIGMA, tau_cr=TAU, G=0.2)
    assert sorted(bp.length)[:2] == pytest.approx([0.025, 0.025])  # the free-edge points
    dp, scale = fly_apart(m, {0: (-0.05, 0.02), 1: (0.05, -0.01)}, steps=1500)
    assert m.bonds.counts["split"] == len(bp) and m.bonds.counts["failed"] == len(bp)
    assert np.abs(dp).max() < 1e-12 * scale


def quadrants(n=8, h=0.05, three=False):
    """A square of four blocks (or three: the top two joined) meeting at the
    centre node: a junction of 4 (3) bodies."""
    nodes, tri = engine.rectangle_mesh(n, n, h)
    c = nodes[tri].mean(axis=1)
    half = n * h / 2
    body = (c[:, 0] > half).astype(np.int32) + 2 * (c[:, 1] > half).astype(np.int32)
    if three:
        body[body == 3] = 2
    return nodes, tri, body


@pytest.mark.parametrize("three", [False, True])
def test_junction_splits_into_one_node_per_body_and_conserves_momentum(three):
    """Junction rule: the centre node, where 4 (3) bodies meet, is one bond
    point with a cohesive pair per two bodies that share a bond edge there
    (4 pairs; 3 for the T), each with that edge's normal and l = half of it.
    When any pair meets the criterion the node splits into one node per body;
    blocks flung apart radially (with a spin) fail everything while momentum
    stays at its initial value to round-off (1e-12 of sum m|v|)."""
    nodes, tri, body = quadrants(three=three)
    m, bp = bonded(nodes, tri, body, sigma_cr=SIGMA, tau_cr=TAU, G=0.2)
    centre = np.flatnonzero(np.all(np.isclose(bp.position, [0.2, 0.2]), axis=1))[0]
    pairs = m.bonds.pairs()
    mine = pairs["point"] == centre
    nb = 3 if three else 4
    assert bp.n_bodies[centre] == nb
    assert mine.sum() == (3 if three else 4)
    np.testing.assert_allclose(pairs["length"][mine], 0.025)
    # each pair's normal is its edge's: horizontal or vertical
    assert np.all(np.isclose(np.abs(pairs["normal"][mine]).max(axis=1), 1.0))
    vel = {0: (-0.05, -0.04), 1: (0.05, -0.05), 2: (-0.04, 0.05), 3: (0.06, 0.04)}
    if three:
        vel.pop(3)
    dp, scale = fly_apart(m, vel, steps=1500)
    ev = m.bonds.events()
    assert np.isfinite(ev["t_split"][centre]) and np.isfinite(ev["t_fail"][centre])
    # one node per body at the centre
    at_centre = np.flatnonzero(np.all(np.isclose(m.reference_positions, [0.2, 0.2]), axis=1))
    assert len(at_centre) == nb
    owners = [set(np.asarray(m.body)[np.any(np.asarray(m.triangles) == i, axis=1)]) for i in at_centre]
    assert all(len(o) == 1 for o in owners) and set.union(*owners) == set(range(nb))
    # every pair of the junction failed; a pair elsewhere may still hold if
    # the spin closes its crack (the crack-closure penalty then keeps x+ and
    # x- from crossing: its opening is not negative beyond round-off)
    st = m.bonds.state()
    assert np.all(st["pair_state"][mine] == 2)
    holding = np.flatnonzero(st["pair_state"] != 2)
    x = m.positions
    d = x[st["node_plus"][holding]] - x[st["node_minus"][holding]]
    assert np.all(np.einsum("ij,ij->i", d, pairs["normal"][holding]) > -1e-9)
    assert np.abs(dp).max() < 1e-12 * scale


def test_crack_faces_are_contact_candidates_after_splitting():
    """After all bond points split the two blocks share no node, and every
    triangle at an interface node is a surface (contact candidate) triangle,
    so a closed crack is handled by the contact of docs/model.md §3.2."""
    m, bp, nodes = two_block_bar(sigma_cr=SIGMA, tau_cr=TAU, G=0.2)
    fly_apart(m, {0: (-0.05, 0.0), 1: (0.05, 0.0)}, steps=200)
    assert m.bonds.counts["split"] == len(bp)
    tri, body = np.asarray(m.triangles), np.asarray(m.body)
    n0, n1 = set(tri[body == 0].ravel()), set(tri[body == 1].ravel())
    assert not n0 & n1
    s = m.bonds.state()
    at_bond = np.flatnonzero(np.any(np.isin(tri, np.r_[s["node_plus"], s["node_minus"]]), axis=1))
    assert set(at_bond) <= set(np.asarray(m.surface_triangles))


def test_a_split_under_mass_scaling_keeps_momentum_and_closes_the_energy_books():
    """With selective mass scaling the pieces of a split node need not add up
    to its inertial mass: each side keeps the contact mass the node needed
    (here two points' pieces carry 1.48 kg/m less than the node did). The split
    then keeps the node's momentum (the pieces' shared velocity scaled by
    m_before / sum of the pieces) and books the kinetic energy this changes,
    with the shift of the ledger's half-step point, as damping. Blocks flung
    apart as above, at a penalty whose contact masses are scaled to a 2 us
    step: momentum stays at its initial value to round-off (1e-12 of sum m|v|)
    and the energy residual within 1e-8 of the ledger's scale (it was 1 % of
    the momentum and 7e-3 of the scale when the split kept velocities and
    booked nothing)."""
    m, bp, nodes = two_block_bar(sigma_cr=SIGMA, tau_cr=TAU, G=0.2)
    m.set(penalty=1e11, contact_reach=0.01, mass_scaling_dt=2e-6)
    assert m.stable_time_step()["added_mass_fraction"] > 0.01
    mass0 = m.mass.sum()
    dp, scale = fly_apart(m, {0: (-0.05, 0.02), 1: (0.05, -0.01)}, steps=1500)
    assert m.bonds.counts["split"] == len(bp) and m.bonds.counts["failed"] == len(bp)
    assert abs(m.mass.sum() - mass0) > 0.01 * mass0   # the case at issue: the pieces' mass differs
    assert np.abs(dp).max() < 1e-12 * scale
    e = m.energies()
    assert abs(e["residual"]) < 1e-8 * e["scale"]


def test_the_step_and_masses_kept_through_splits_are_those_of_the_split_mesh_taken_anew():
    """A split does not take the contact stiffness of the whole mesh again
    (Model::reference_contact_stiffness renames the split node's entry of its
    body, contact.hpp rename_contact_shares) nor the elements' limits
    (compute_element_limits): the stable step and the scaled masses must be
    those of a model made from the split mesh itself, bit for bit, after some
    of the points split and after all of them. Blocks flung apart as above,
    contact masses scaled to a 2 us step, a finite contact reach (its local
    walk of the boundaries)."""
    params = dict(gravity=False, penalty=1e11, contact_reach=0.01, mass_scaling_dt=2e-6)
    m, bp, nodes = two_block_bar(sigma_cr=SIGMA, tau_cr=TAU, G=0.2)
    m.set(**params)
    m.stable_time_step()   # taken before the splits: those after follow them
    tri, body = np.asarray(m.triangles), np.asarray(m.body)
    v = np.zeros((m.n_nodes, 2))
    v[np.unique(tri[body == 0])], v[np.unique(tri[body == 1])] = (-0.05, 0.02), (0.05, -0.01)
    m.set_velocities(v)
    m.set(dt=0.9 * m.stable_time_step()["dt"])
    keys = ("dt", "dt_element", "element", "dt_contact", "contact_node", "contact_mass", "added_mass",
            "scaled_nodes")
    seen = set()
    for _ in range(300):
        m.step(5)
        split = m.bonds.counts["split"]
        if split in seen or split == 0:
            continue
        seen.add(split)
        kept = m.stable_time_step()
        anew = engine.Model(m.reference_positions, np.asarray(m.triangles), np.asarray(m.body), dict(ICE))
        anew.set(**params)
        anew._m.set_mass_floor(np.asarray(m._m.mass_floor()))
        made = anew.stable_time_step()
        assert {k: kept[k] for k in keys} == {k: made[k] for k in keys}
        assert np.array_equal(m.mass, anew.mass)
    assert len(seen) >= 2 and max(seen) == len(bp)   # some of the points, then all


def test_a_crack_closed_again_is_met_by_contact_at_once():
    """The contact module reuses its candidate pairs while no node has moved
    farther than its skin (millimetres here), but a split changes which
    triangles can touch: the crack faces shared nodes before it, so no pair
    of them was a candidate. Blocks flung apart by 0.1 mm and sent back
    across the crack must meet there in contact (the node-to-node crack
    closure alone would keep the faces apart without one touching pair).
    A split adds nodes, which alone makes the list be built again; a change
    of topology without new nodes: test_contact_integrated.py."""
    m, bp, nodes = two_block_bar(sigma_cr=SIGMA, tau_cr=TAU, G=0.2)
    fly_apart(m, {0: (-0.05, 0.0), 1: (0.05, 0.0)}, steps=200)
    assert m.bonds.counts["split"] == len(bp)
    assert m.touching_pairs == 0
    # the pieces split off a node start where it is: the original nodes show every move
    moved = np.abs(m.positions[:len(nodes)] - nodes).max()
    m.set_velocities(-m.velocities)
    touching = 0
    for _ in range(60):
        m.step(10)
        touching = max(touching, m.touching_pairs)
        moved = max(moved, np.abs(m.positions[:len(nodes)] - nodes).max())
    # within half the skin (0.1 x an element) of the first positions, so within
    # the skin of those the list was last built at: not rebuilt for motion
    assert moved < 0.5 * 0.1 * 0.05
    assert touching > 0
