"""The order of friction's Gauss-Seidel sweeps (contact/friction_order.hpp):
colour by colour, no two pairs of a colour sharing a node, fixed by the
touching pairs alone. So the pairs of a colour can be updated at once (the GPU
backend, docs/gpu.md) with the bits of a serial sweep, and a run whose
candidate list was built at another time (a resumed run) gets the same
friction bit for bit."""
import numpy as np

from icerubble import _engine

S = 2e11
DT = 1e-6
MU = 0.3


def wall_of_squares(rng, rows=3, cols=6, h=0.2, overlap=2e-5, gap=0.01):
    """rows x cols squares of side h, two triangles each (a body per square),
    each pressed `overlap` into its right and upper neighbours, with slightly
    jittered corners: many touching pairs that share nodes; and a column of
    squares `gap` to the right of the wall (near, not touching)."""
    pts, tri, body = [], [], []
    for r in range(rows):
        for c in range(cols + 1):
            x0, y0 = c * (h - overlap) + (gap if c == cols else 0.0), r * (h - overlap)
            k = len(pts)
            corners = np.array([[x0, y0], [x0 + h, y0], [x0 + h, y0 + h], [x0, y0 + h]])
            pts.extend(corners + rng.uniform(-0.2, 0.2, (4, 2)) * overlap)
            tri += [[k, k + 1, k + 2], [k, k + 2, k + 3]]
            body += [len(body) // 2] * 2
    return np.array(pts), np.array(tri, dtype=np.int32), np.array(body, dtype=np.int32)


def friction_step(pts, tri, body, v, load, skin_fraction):
    n = len(pts)
    solver = _engine.ContactSolver(skin_fraction)
    mass = np.full(n, 0.5)
    fx, fy = np.zeros(n), np.zeros(n)
    args = (pts[:, 0].copy(), pts[:, 1].copy(), v[:, 0].copy(), v[:, 1].copy(), mass, tri, body,
            np.arange(len(tri), dtype=np.int32))
    touching = solver.compute_normal(*args, fx, fy, penalty=S, mu=MU, dt=DT)
    fx += load[:, 0]
    fy += load[:, 1]
    power = solver.apply_friction(*args, fx, fy, penalty=S, mu=MU, dt=DT)
    return solver, touching, np.c_[fx, fy], power


def test_each_colour_is_a_set_of_pairs_that_share_no_node():
    rng = np.random.default_rng(7)
    pts, tri, body = wall_of_squares(rng)
    v = rng.normal(0.0, 1e-3, pts.shape)
    solver, touching, _, _ = friction_step(pts, tri, body, v, rng.normal(0.0, 1e3, pts.shape), 0.1)
    order = solver.sweep_order
    pair, start = order["pair"], order["colour_start"]
    assert touching > 20
    assert sorted(pair) == list(range(touching))  # every pair once
    assert len(start) - 1 >= 2  # coupled pairs: more than one colour
    nodes = np.concatenate([tri[solver.pairs["tris"][:, 0]], tri[solver.pairs["tris"][:, 1]]], axis=1)
    for c in range(len(start) - 1):
        members = pair[start[c]:start[c + 1]]
        assert list(members) == sorted(members)  # pair order within a colour
        used = np.concatenate([np.unique(nodes[p]) for p in members])
        assert len(used) == len(np.unique(used)), f"colour {c} has pairs that share a node"


def test_friction_does_not_depend_on_when_the_candidate_list_was_built():
    # Another skin gives another candidate list (in another order); the
    # touching pairs, their colours and so the friction forces are the same bits.
    rng = np.random.default_rng(11)
    pts, tri, body = wall_of_squares(rng)
    v = rng.normal(0.0, 1e-3, pts.shape)
    load = rng.normal(0.0, 1e3, pts.shape)
    a, na, fa, pa = friction_step(pts, tri, body, v, load, 0.1)
    b, nb, fb, pb = friction_step(pts, tri, body, v, load, 0.0)
    assert len(a.candidates) != len(b.candidates)
    assert na == nb
    assert np.array_equal(a.sweep_order["pair"], b.sweep_order["pair"])
    assert np.array_equal(fa, fb)
    assert pa == pb
    assert np.any(a.friction_forces != 0.0)


def priority(key):
    """friction_priority (contact/friction_kernel.hpp): splitmix64's finaliser."""
    m = 0xFFFFFFFFFFFFFFFF
    key ^= key >> 30
    key = (key * 0xBF58476D1CE4E5B9) & m
    key ^= key >> 27
    key = (key * 0x94D049BB133111EB) & m
    return key ^ (key >> 31)


def test_parallel_rounds_give_the_greedy_colours():
    # The GPU colours the pairs in rounds (cuda/friction.cu): a pair takes the
    # smallest colour its neighbours before it (by priority) do not have, once
    # they all have one. Emulated here round by round, it must give the CPU's
    # greedy colouring (friction_order.cpp) exactly, in few rounds.
    rng = np.random.default_rng(5)
    pts, tri, body = wall_of_squares(rng, rows=6, cols=10)
    v = rng.normal(0.0, 1e-3, pts.shape)
    solver, touching, _, _ = friction_step(pts, tri, body, v, rng.normal(0.0, 1e3, pts.shape), 0.1)
    order = solver.sweep_order
    greedy = np.empty(touching, int)
    for c in range(len(order["colour_start"]) - 1):
        greedy[order["pair"][order["colour_start"][c]:order["colour_start"][c + 1]]] = c
    pairs = solver.pairs["tris"]
    nodes = np.concatenate([tri[pairs[:, 0]], tri[pairs[:, 1]]], axis=1)
    prio = [(priority((int(a) << 32) | int(b)), p) for p, (a, b) in enumerate(pairs)]
    neighbours = [[q for q in range(touching) if q != p and set(nodes[p]) & set(nodes[q])] for p in range(touching)]
    colour = np.full(touching, -1)
    rounds = 0
    while (colour < 0).any():
        rounds += 1
        start = colour.copy()
        for p in np.flatnonzero(start < 0):
            before = [q for q in neighbours[p] if prio[q] < prio[p]]
            if all(start[q] >= 0 for q in before):
                taken = {start[q] for q in before}
                colour[p] = min(set(range(len(taken) + 1)) - taken)
    assert np.array_equal(colour, greedy)
    assert rounds < touching / 4, f"{rounds} rounds for {touching} pairs"
