"""The candidate list as the GPU's contact stages read it
(contact/candidate_layout.hpp): one layout for the normal pass and friction,
whose per-node sums give the CPU's bits only if the candidates come in the
CPU's pair order and each node's entries in that order. Checked here on the
CPU, where CI runs, against the CPU's contact solver."""
import numpy as np
import pytest

from icerubble import _engine
from tests.engine.test_friction_order import friction_step, wall_of_squares


def layout_of(solver, tri, n_nodes):
    return _engine.candidate_layout(solver.candidates, tri, n_nodes)


def test_candidates_come_in_the_cpus_pair_order():
    rng = np.random.default_rng(3)
    pts, tri, body = wall_of_squares(rng)
    v = rng.normal(0.0, 1e-3, pts.shape)
    solver, touching, _, _ = friction_step(pts, tri, body, v, rng.normal(0.0, 1e3, pts.shape), 0.1)
    L = layout_of(solver, tri, len(pts))
    pairs = np.c_[L["contactor"], L["target"]]
    # every candidate once, (contactor, target) ascending
    assert sorted(map(tuple, pairs)) == sorted(map(tuple, solver.candidates))
    assert [tuple(p) for p in pairs] == sorted(map(tuple, pairs))
    # the touching pairs, in layout order, are the CPU's pairs in its order
    touched = {tuple(p) for p in solver.pairs["tris"]}
    assert touching > 20
    in_layout = [tuple(p) for p in pairs if tuple(p) in touched]
    assert in_layout == [tuple(p) for p in solver.pairs["tris"]]
    # six nodes each: the contactor's, then the target's
    assert np.array_equal(L["node"].reshape(-1, 6), np.c_[tri[L["contactor"]], tri[L["target"]]])
    assert len(np.unique(L["key"])) == len(pairs)


def test_each_node_lists_its_entries_in_candidate_order():
    rng = np.random.default_rng(5)
    pts, tri, body = wall_of_squares(rng)
    solver, _, _, _ = friction_step(pts, tri, body, np.zeros(pts.shape), np.zeros(pts.shape), 0.1)
    L = layout_of(solver, tri, len(pts))
    node, start, entry = L["node"], L["start"], L["entry"]
    assert start[0] == 0 and start[-1] == len(node) == len(entry)
    for i in range(len(pts)):
        mine = entry[start[i]:start[i + 1]]
        assert np.array_equal(mine, np.flatnonzero(node == i))  # all of them, ascending
        assert len(np.unique(mine // 6)) == len(mine)  # a node is one corner of a candidate


def test_triangles_that_share_a_node_are_refused():
    tri = np.array([[0, 1, 2], [2, 3, 4]], dtype=np.int32)
    with pytest.raises(ValueError, match="triangles 0 and 1 share node 2"):
        _engine.candidate_layout(np.array([[0, 1]], dtype=np.int32), tri, 5)
    with pytest.raises(ValueError, match="outside 0..1"):
        _engine.candidate_layout(np.array([[0, 7]], dtype=np.int32), tri, 5)
