"""Bond points found from a continuous mesh: count, tributary length, normal, depth scaling."""
import numpy as np
import pytest

from icerubble.geometry.bond_points import bond_edges, find_bond_points


def grid(nx, ny, w, h):
    """Structured mesh of nx*ny squares, each cut into 2 CCW triangles."""
    xs, ys = np.linspace(0, w, nx + 1), np.linspace(0, h, ny + 1)
    X, Y = np.meshgrid(xs, ys)
    nodes = np.column_stack([X.ravel(), Y.ravel()])
    tris = []
    for j in range(ny):
        for i in range(nx):
            a = j * (nx + 1) + i
            b, c, d = a + 1, a + nx + 2, a + nx + 1
            tris += [[a, b, c], [a, c, d]]
    tris = np.array(tris)
    return nodes, tris, nodes[tris].mean(axis=1)


STRENGTH = dict(sigma_cr=10e3, tau_cr=50e3, G=15.0, bottom_fraction=0.1)


def test_two_blocks_vertical_interface():
    nodes, tri, c = grid(8, 4, 2.0, 1.0)
    body = (c[:, 0] > 1.0).astype(int)
    bp = find_bond_points(nodes, tri, body, keel_top_y=1.0, keel_depth=1.0, **STRENGTH)
    # the interface x = 1 has ny+1 = 5 nodes and 4 edges
    assert len(bp) == 5 and len(bp.edges) == 4
    assert np.allclose(bp.position[:, 0], 1.0)
    # tributary lengths add up to the interface length; end nodes get half an edge
    assert bp.length.sum() == pytest.approx(1.0, rel=1e-14)
    assert sorted(bp.length)[:2] == pytest.approx([0.125, 0.125])
    # normal points from body 0 (left) to body 1 (right)
    assert np.allclose(bp.normal, [1.0, 0.0])
    assert np.all(bp.bodies == [0, 1]) and np.all(bp.n_bodies == 2)


def test_junction_of_three_bodies_and_excluded_pair():
    nodes, tri, c = grid(8, 8, 2.0, 2.0)
    body = np.where(c[:, 1] > 1.0, 2, (c[:, 0] > 1.0).astype(int))
    bp = find_bond_points(nodes, tri, body, keel_top_y=2.0, keel_depth=2.0, **STRENGTH)
    j = np.nonzero(np.all(np.isclose(bp.position, [1.0, 1.0]), axis=1))[0]
    assert len(j) == 1 and bp.n_bodies[j[0]] == 3
    # total tributary length = total bond length: 1 (vertical) + 2 (horizontal)
    assert bp.length.sum() == pytest.approx(3.0, rel=1e-14)
    # excluding the pairs with body 2 leaves the vertical interface alone
    e, eb, _ = bond_edges(tri, body, exclude_pairs=[(0, 2), (2, 1)])
    assert len(e) == 4 and np.all(eb == [0, 1])


def test_bond_strengths_follow_depth():
    nodes, tri, c = grid(4, 8, 1.0, 4.0)
    body = (c[:, 0] > 0.5).astype(int)
    bp = find_bond_points(nodes, tri, body, keel_top_y=4.0, keel_depth=4.0, **STRENGTH)
    expect = 10e3 * (1 - 0.9 * (4.0 - bp.position[:, 1]) / 4.0)
    assert np.allclose(bp.sigma_cr, expect, rtol=1e-14)
    assert np.allclose(bp.tau_cr / bp.sigma_cr, 5.0)
