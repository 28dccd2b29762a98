"""Friction on the CPU's threads, island by island (contact/friction_islands.hpp):
the touching pairs coupled through shared nodes form islands; the threads
colour and sweep different islands at once, each island's pairs in their
sweep order, and apply each island's forces in pair order (the normal pass
adds its forces onto the nodes island by island too). So the colours, the
contact and friction forces and the run are the bits of one thread's."""
import numpy as np
import pytest

from icerubble import _engine, engine
from icerubble.engine import gpu
from tests.engine.gpu_scenes import on_gpu_or_emulation
from tests.engine.test_friction_order import priority, wall_of_squares

MIN_PAIRS = 256  # contact/friction_islands.hpp, kMinIslandPairs: fewer are swept on one thread


def components(nodes):
    """Each pair's island by a plain search: pairs sharing a node are joined;
    islands numbered in the order of their first pair."""
    label = np.full(len(nodes), -1)
    by_node = {}
    for p, row in enumerate(nodes):
        for v in row:
            by_node.setdefault(int(v), []).append(p)
    n = 0
    for p in range(len(nodes)):
        if label[p] >= 0:
            continue
        stack, label[p] = [p], n
        while stack:
            q = stack.pop()
            for v in nodes[q]:
                for r in by_node[int(v)]:
                    if label[r] < 0:
                        label[r] = n
                        stack.append(r)
        n += 1
    return label


@pytest.mark.parametrize("threads", [1, 2, 4])
def test_islands_are_the_pairs_joined_through_shared_nodes(threads):
    # on threads, the pairs claim nodes and join islands at once (in any
    # interleaving: the islands, and their numbers, the same)
    rng = np.random.default_rng(3)
    # chains that meet only late (pair 2 joins the islands of pairs 0 and 1;
    # pair 5 joins two islands whose first pairs are 3 and 4), and random
    # pairs over few nodes, which merge islands in every order
    chains = np.array([[0, 1, 2, 3, 4, 5], [10, 11, 12, 13, 14, 15], [5, 20, 21, 22, 23, 10],
                       [30, 31, 32, 33, 34, 35], [40, 41, 42, 43, 44, 45], [45, 50, 51, 52, 53, 35],
                       [60, 61, 62, 63, 64, 65]], dtype=np.int32)
    random = [np.array([rng.choice(n, 6, replace=False) for _ in range(m)], dtype=np.int32)
              for n, m in ((400, 150), (3000, 2000), (20000, 3000))]
    for nodes in [chains] + random:
        got = _engine.friction_islands(nodes, 20000, threads)
        want = components(nodes)
        assert np.array_equal(got["of_pair"], want)
        sizes = np.bincount(want)
        assert list(got["by_size"]) == sorted(range(len(sizes)), key=lambda i: (-sizes[i], i))
    assert list(_engine.friction_islands(chains, 400, threads)["of_pair"]) == [0, 0, 0, 1, 1, 1, 2]


def walls_apart(rng, count, rows, cols, apart=5.0):
    """`count` walls of pressed squares (wall_of_squares), `apart` m from each
    other: each wall's touching pairs an island or a few, none shared."""
    pts, tri, body = [], [], []
    for w in range(count):
        p, t, b = wall_of_squares(rng, rows=rows, cols=cols)
        tri.append(t + sum(len(q) for q in pts))
        body.append(b + sum(len(np.unique(q)) for q in body))
        pts.append(p + [w * apart, 0.0])
    return np.concatenate(pts), np.concatenate(tri).astype(np.int32), np.concatenate(body).astype(np.int32)


def stepped(threads, steps):
    rng = np.random.default_rng(17)
    pts, tri, body = walls_apart(rng, count=12, rows=3, cols=4)
    m = engine.Model(pts, tri, body, dict(E=1e9, nu=0.3, rho=920.0))
    m.set(threads=threads, penalty=2e11, mu=0.3)
    m.set_velocities(rng.normal(0.0, 1e-3, pts.shape))
    m.set(dt=0.5 * m.stable_time_step()["dt"])
    m.step(steps)  # its last step's pairs: those of the warm start (an evaluation would put back the step's before)
    return m, tri


def test_friction_by_islands_on_two_threads_gives_the_bits_of_one():
    # two steps: the walls' overlaps push them apart by the third
    one, tri = stepped(1, 2)
    two, _ = stepped(2, 2)
    f1, f2 = _engine.friction_fields(one._m), _engine.friction_fields(two._m)
    n = one.touching_pairs
    keys = np.asarray(one._m.contact_warm_start()[0], dtype=np.uint64)
    pairs = np.c_[(keys >> np.uint64(32)).astype(np.int64), (keys & np.uint64(0xFFFFFFFF)).astype(np.int64)]
    nodes = np.concatenate([tri[pairs[:, 0]], tri[pairs[:, 1]]], axis=1)
    islands = components(nodes)
    # the threads share islands: enough pairs, several islands, none holding
    # more than a thread's share, colours too small to share (friction.cpp)
    assert n >= MIN_PAIRS and n == two.touching_pairs, n
    assert islands.max() + 1 >= 12 and np.bincount(islands).max() * 2 <= n
    assert n < MIN_PAIRS * f1["colours"]
    assert np.any(f1["lambda"] != 0.0)
    for k in ("lambda", "colour", "f_x", "f_y"):
        assert np.array_equal(f1[k], f2[k]), k
    assert f1["power"] == f2["power"]
    assert np.array_equal(one.positions, two.positions) and np.array_equal(one.velocities, two.velocities)
    # the colours island by island are the greedy colouring of all the pairs
    # in priority order (contact/friction_order.hpp)
    order = sorted(range(n), key=lambda p: (priority((int(pairs[p, 0]) << 32) | int(pairs[p, 1])), p))
    colour, taken = np.full(n, -1), {}
    for p in order:
        used = set().union(*(taken.get(int(v), set()) for v in nodes[p]))
        colour[p] = min(set(range(len(used) + 1)) - used)
        for v in nodes[p]:
            taken.setdefault(int(v), set()).add(colour[p])
    assert np.array_equal(f2["colour"], colour)


@on_gpu_or_emulation
def test_friction_by_islands_is_the_gpus():
    # the GPU's colour-by-colour sweeps (or their emulation), another order of
    # the same updates: the CPU's island by island sweeps must give its bits
    two, _ = stepped(2, 2)
    cmp = gpu.compare_friction(two)
    assert cmp["pairs"][0] >= MIN_PAIRS and cmp["pairs"][0] == cmp["pairs"][1], cmp["pairs"]
    assert cmp["colours"][0] == cmp["colours"][1] and cmp["colour"] == 0
    assert (cmp["lambda"][0], cmp["f_x"][0], cmp["f_y"][0]) == (0, 0, 0)
    assert cmp["power_rel"] <= gpu.ROUND_OFF
