"""Topology editing for freeze-bond node splitting: nodes can be appended and
triangle corners re-pointed; masses, gather list and surface follow."""
import numpy as np
import pytest

from icerubble import engine


def bonded_pair():
    """Two 0.5 x 0.5 m blocks sharing their common edge x = 0.5 (a continuous
    mesh across the freeze-bond edge, docs/model.md §3.3)."""
    nodes, tri = engine.rectangle_mesh(4, 2, 0.25)
    body = (nodes[tri].mean(axis=1)[:, 0] > 0.5).astype(int)
    m = engine.Model(nodes, tri, body, dict(E=1e8, nu=0.3, rho=900.0))
    return m, nodes, tri, body


def test_shared_edge_nodes_are_surface_nodes_of_both_bodies():
    m, nodes, tri, body = bonded_pair()
    # Every triangle touches its body's boundary in a 2-cell-deep block.
    assert len(m.surface_triangles) == len(tri)
    s = m.stable_time_step()
    assert np.isfinite(s["dt_contact"])  # two bodies: contact is possible


def test_splitting_the_bond_edge_conserves_mass_and_frees_the_blocks():
    m, nodes, tri, body = bonded_pair()
    m.set(gravity=False)
    total = m.mass.sum()
    mass_before = m.mass.copy()
    shared = np.flatnonzero(np.isclose(nodes[:, 0], 0.5))
    core = m._m
    new_ids = {}
    for i in shared:  # x- stays with body 0, x+ (the new node) takes body 1
        new_ids[i] = core.add_node(nodes[i, 0], nodes[i, 1], nodes[i, 0], nodes[i, 1], 0.0, 0.0)
    for t in np.flatnonzero(body == 1):
        for c in range(3):
            if tri[t, c] in new_ids:
                core.set_triangle_node(int(t), c, new_ids[tri[t, c]])
    m.set(dt=0.9 * m.stable_time_step()["dt"])  # rebuilds topology
    mass = m.mass
    # m+ + m- = m at every split node, total unchanged (exact sums of rho A/3).
    for i, j in new_ids.items():
        assert mass[i] + mass[j] == pytest.approx(mass_before[i], rel=1e-15)
    assert mass.sum() == pytest.approx(total, rel=1e-15)
    # Pulled apart, the split blocks separate rigidly: no stress anywhere.
    n = m.n_nodes
    all_nodes = np.vstack((nodes, nodes[shared]))
    v = np.zeros((n, 2))
    v[:, 0] = np.where(np.isin(np.arange(n), list(new_ids.values())) |
                       ((all_nodes[:, 0] > 0.5) & (np.arange(n) < len(nodes))), 1.0, -1.0)
    m.set_velocities(v)
    m.step(200)
    # Round-off only: 200 position updates of O(1 m) coordinates leave
    # strains ~ 200 x 2e-16 m / 0.25 m = 2e-13, so stress < 1e-12 E. Still
    # bonded, the pull would strain the blocks ~ 2 m/s x t / 0.5 m ~ 1e-2.
    assert np.abs(m.stress).max() < 1e-12 * 1e8
    gap = m.x[list(new_ids.values())] - m.x[list(new_ids.keys())]
    # The gap opens at 2 m/s; round-off of 200 updates of 0.5 m coordinates.
    np.testing.assert_allclose(gap, 2.0 * m.time, rtol=0, atol=1e-13)



def test_a_corner_cannot_be_re_pointed_to_another_place():
    """A triangle's reference shape (Dm^-1, area, its stable-step limit) is
    the constructor's: a corner re-pointed to a node elsewhere in the
    reference configuration would leave them stale, so it is refused with
    what is wrong; a node at the corner's own place (a split) is taken."""
    m, nodes, tri, body = bonded_pair()
    core = m._m
    p = 0.5 * (nodes[tri[0, 0]] + nodes[tri[0]].mean(axis=0))
    elsewhere = core.add_node(p[0], p[1], p[0], p[1], 0.0, 0.0)
    with pytest.raises(ValueError, match=r"corner 0 of triangle 0 .* own reference place"):
        core.set_triangle_node(0, 0, elsewhere)
    x, y = nodes[tri[0, 0]]
    core.set_triangle_node(0, 0, core.add_node(x, y, x, y, 0.0, 0.0))
