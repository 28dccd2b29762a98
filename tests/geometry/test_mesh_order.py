"""Locality numbering of a mesh (geometry/mesh_order.py): the same mesh, renumbered."""
import numpy as np

from icerubble.geometry import mesh_order


def grid_mesh(n, rng):
    """An n x n grid of unit squares split into triangles, nodes and triangles shuffled."""
    xs, ys = np.meshgrid(np.arange(n + 1.0), np.arange(n + 1.0))
    nodes = np.column_stack([xs.ravel(), ys.ravel()])
    k = lambda i, j: j * (n + 1) + i
    tris = []
    for j in range(n):
        for i in range(n):
            tris += [(k(i, j), k(i + 1, j), k(i + 1, j + 1)), (k(i, j), k(i + 1, j + 1), k(i, j + 1))]
    tris = np.array(tris)
    perm = rng.permutation(len(nodes))           # new = perm[old]
    shuffled = np.empty_like(nodes)
    shuffled[perm] = nodes
    tris = perm[tris][rng.permutation(len(tris))]
    return shuffled, tris


def test_renumbering_keeps_every_triangle_and_its_orientation():
    rng = np.random.default_rng(1)
    nodes, tris = grid_mesh(30, rng)
    body = rng.integers(0, 5, len(tris))
    new_nodes, new_tris, new_body, node_map = mesh_order.renumber(nodes, tris, body, cell=0.5)
    # node_map carries every node to its place; the triangles are the same point triples
    assert np.array_equal(new_nodes[node_map], nodes)
    as_points = lambda n, t, b: sorted((tuple(n[t[i]].ravel()), b[i]) for i in range(len(t)))
    assert as_points(new_nodes, new_tris, new_body) == as_points(nodes, tris, body)
    # corner order (orientation) kept: signed areas unchanged as a set
    area = lambda n, t: 0.5 * np.cross(n[t[:, 1]] - n[t[:, 0]], n[t[:, 2]] - n[t[:, 0]])
    assert np.allclose(np.sort(area(new_nodes, new_tris)), np.sort(area(nodes, tris)))
    assert (area(new_nodes, new_tris) > 0).all()


def test_renumbering_makes_neighbours_in_space_neighbours_in_memory():
    rng = np.random.default_rng(2)
    nodes, tris = grid_mesh(60, rng)
    spread_before = np.median(tris.max(1) - tris.min(1))
    _, new_tris, _, _ = mesh_order.renumber(nodes, tris, np.zeros(len(tris), int), cell=0.5)
    spread_after = np.median(new_tris.max(1) - new_tris.min(1))
    # shuffled: a triangle's corners lie ~n_nodes/3 apart; in Z order a few apart
    assert spread_before > 500
    assert spread_after <= 10
    # nodes numbered by first use: each triangle brings at most its own new nodes
    first_use = np.maximum.accumulate(new_tris.max(axis=1))
    assert (np.diff(first_use) <= 3).all()


def test_unused_nodes_are_kept_after_the_used_ones():
    nodes = np.array([[0, 0], [5, 5], [1, 0], [0, 1]], float)
    tris = np.array([[0, 2, 3]])
    new_nodes, new_tris, _, node_map = mesh_order.renumber(nodes, tris, np.zeros(1, int), cell=1.0)
    assert node_map[1] == 3 and np.array_equal(new_nodes[3], [5, 5])
    assert sorted(new_tris.ravel()) == [0, 1, 2]
