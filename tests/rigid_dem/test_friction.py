"""Coulomb friction with stick between rigid blocks (engine rigid/rigid_friction.hpp):
per-contact history, so blocks pushed opposite ways on one floor both stay (the
case YADE's polyhedra law gets wrong), sliding at the right acceleration above the
limit, action and reaction, order independence."""
import numpy as np
import pytest

from icerubble import _engine

G, MU, K_T, DT = 9.81, 0.35, 1e6, 1e-4
M = 331.2  # a 1.2 m x 0.3 m ice block per metre of width [kg/m]


def run_on_floor(pushes, steps, mu=MU, stuck=()):
    """Blocks 1..n resting on a fixed floor (body 0) at x = 2k, each pushed
    sideways with pushes[k-1] [N/m]; normal force m g at a point under each
    block's centroid; the blocks numbered in `stuck` stick to the floor.
    Returns displacements and velocities of the blocks, and the last step's
    tangential forces."""
    n = len(pushes)
    fr = _engine.RigidFriction()
    fr.stick(np.zeros(len(stuck), np.int32), np.asarray(stuck, np.int32))
    x = np.array([0.0] + [2.0 * k for k in range(1, n + 1)])
    y = np.array([-1.0] + [0.15] * n)
    vx = np.zeros(n + 1)
    zeros = np.zeros(n + 1)
    a = np.zeros(n, np.int32)
    b = np.arange(1, n + 1, dtype=np.int32)
    for _ in range(steps):
        px, py = x[1:].copy(), np.zeros(n)
        ft, fx, fy, tz = fr.step(a, b, px, py, np.zeros(n), np.ones(n), np.full(n, M * G),
                                 x, y, vx, zeros, zeros, DT, K_T, mu)
        vx[1:] += DT * (np.asarray(pushes) + fx[1:]) / M
        x[1:] += DT * vx[1:]
    return x[1:] - 2.0 * np.arange(1, n + 1), vx[1:], ft


def test_one_block_below_the_friction_limit_stays_put():
    P = 0.5 * MU * M * G
    dx, v, ft = run_on_floor([P], 20000)
    # it sticks within the tangential spring's give (2 P / k_t at the swing's end)
    assert abs(dx[0]) <= 2 * P / K_T * (1 + 1e-9)
    assert abs(ft[0]) <= MU * M * G


def test_two_blocks_pushed_opposite_ways_on_one_floor_both_stay():
    """YADE's polyhedra law shares one shear force among all contacts: there
    both blocks slide at 0.18 m/s (docs/yade_notes.md)."""
    P = 0.5 * MU * M * G
    dx, v, ft = run_on_floor([P, -P], 20000)
    assert np.all(np.abs(dx) <= 2 * P / K_T * (1 + 1e-9))
    assert ft[0] == pytest.approx(-ft[1], rel=1e-12)


def test_above_the_limit_a_block_slides_at_the_coulomb_acceleration():
    P = 1.5 * MU * M * G
    _, v1, _ = run_on_floor([P, -P], 10000)
    _, v2, ft = run_on_floor([P, -P], 20000)
    a_expected = (P - MU * M * G) / M
    # once the tangential spring has given (a quarter swing, ~30 ms) it slides
    # with the friction at its cap: the Coulomb acceleration, step by step
    assert (v2[0] - v1[0]) / (10000 * DT) == pytest.approx(a_expected, rel=1e-9)
    assert (v2[1] - v1[1]) / (10000 * DT) == pytest.approx(-a_expected, rel=1e-9)
    # along t = z x n = -x on block 1 (it slides to +x): against the slip, at mu f_n
    assert ft[0] == pytest.approx(MU * M * G, rel=1e-12)


def test_a_stuck_pair_holds_at_any_force_and_the_others_still_slide():
    """Phase 1's hold stage (make_pile.py mu_hold): a face contact the mesher will
    bond sticks beyond mu f_n; its neighbour on the same floor still slides."""
    P = 1.5 * MU * M * G
    _, v1, _ = run_on_floor([P, P], 10000, stuck=[1])
    dx, v2, ft = run_on_floor([P, P], 20000, stuck=[1])
    # the stuck block swings on its tangential spring about P / k_t, never further than 2 P / k_t
    assert abs(dx[0]) <= 2 * P / K_T * (1 + 1e-9)
    assert (v2[1] - v1[1]) / (10000 * DT) == pytest.approx((P - MU * M * G) / M, rel=1e-9)
    assert abs(ft[1]) == pytest.approx(MU * M * G, rel=1e-12)


def test_stick_refuses_what_is_not_a_body_pair():
    fr = _engine.RigidFriction()
    for a, b in (([1], [1]), ([2], [1]), ([-1], [0])):
        with pytest.raises(ValueError, match="0 <= a < b"):
            fr.stick(np.array(a, np.int32), np.array(b, np.int32))
    fr.stick(np.array([0, 0], np.int32), np.array([3, 3], np.int32))
    assert list(fr.stuck) == [3]


def test_friction_is_action_and_reaction_and_independent_of_contact_order():
    rng = np.random.default_rng(4)
    nb, nc = 6, 9
    pairs = set()
    while len(pairs) < nc:
        i, j = sorted(rng.choice(nb, 2, replace=False))
        pairs.add((i, j))
    pairs = np.array(sorted(pairs), np.int32)
    ang = rng.uniform(0, 2 * np.pi, nc)
    args = dict(px=rng.normal(size=nc), py=rng.normal(size=nc), nx=np.cos(ang), ny=np.sin(ang),
                fn=rng.uniform(0, 100, nc))
    body = dict(x=rng.normal(size=nb), y=rng.normal(size=nb), vx=rng.normal(size=nb),
                vy=rng.normal(size=nb), omega=rng.normal(size=nb))
    out = []
    for perm in (np.arange(nc), rng.permutation(nc)):
        fr = _engine.RigidFriction()
        res = fr.step(pairs[perm, 0], pairs[perm, 1], *(args[k][perm] for k in ("px", "py", "nx", "ny", "fn")),
                      *(body[k] for k in ("x", "y", "vx", "vy", "omega")), DT, K_T, 0.5)
        ft, fx, fy, tz = res
        assert np.all(np.abs(ft) <= 0.5 * args["fn"][perm] * (1 + 1e-15))
        # forces sum to zero; so do the moments about the origin
        assert abs(fx.sum()) < 1e-12 * np.abs(fx).max() and abs(fy.sum()) < 1e-12 * np.abs(fy).max()
        moment = tz + body["x"] * fy - body["y"] * fx
        assert abs(moment.sum()) < 1e-12 * np.abs(moment).max()
        out.append((fx, fy, tz, np.array(fr.keys), np.array(fr.forces)))
    for u, w in zip(out[0], out[1]):
        assert np.array_equal(u, w)   # bit for bit: per-body sums in key order


def test_a_contact_that_ends_forgets_its_history_and_a_restored_one_continues():
    fr = _engine.RigidFriction()
    one = dict(a=np.array([0], np.int32), b=np.array([1], np.int32), px=np.zeros(1), py=np.zeros(1),
               nx=np.zeros(1), ny=np.ones(1), fn=np.array([100.0]), x=np.zeros(2), y=np.zeros(2),
               vx=np.array([0.0, 1e-3]), vy=np.zeros(2), omega=np.zeros(2), dt=DT, k_t=K_T, mu=1.0)
    ft1 = fr.step(**one)[0][0]
    ft2 = fr.step(**one)[0][0]
    assert ft2 == pytest.approx(2 * ft1, rel=1e-12)   # the spring keeps loading
    keys, forces = np.array(fr.keys), np.array(fr.forces)
    none = dict(one, a=np.zeros(0, np.int32), b=np.zeros(0, np.int32), px=np.zeros(0), py=np.zeros(0),
                nx=np.zeros(0), ny=np.zeros(0), fn=np.zeros(0))
    fr.step(**none)
    assert fr.step(**one)[0][0] == pytest.approx(ft1, rel=1e-12)   # started afresh
    again = _engine.RigidFriction()
    again.restore(keys, forces)
    assert again.step(**one)[0][0] == pytest.approx(3 * ft1, rel=1e-12)


def test_bad_contacts_are_refused_with_the_reason():
    fr = _engine.RigidFriction()
    base = dict(a=np.array([0], np.int32), b=np.array([1], np.int32), px=np.zeros(1), py=np.zeros(1),
                nx=np.zeros(1), ny=np.ones(1), fn=np.array([1.0]), x=np.zeros(2), y=np.zeros(2),
                vx=np.zeros(2), vy=np.zeros(2), omega=np.zeros(2), dt=DT, k_t=K_T, mu=0.3)
    for change, msg in ((dict(a=np.array([1], np.int32), b=np.array([0], np.int32)), "must be <"),
                        (dict(ny=np.array([2.0])), "unit vector"),
                        (dict(fn=np.array([-1.0])), "fn must be >= 0"),
                        (dict(b=np.array([5], np.int32)), "not a body id"),
                        (dict(k_t=0.0), "k_t must be > 0"),
                        (dict(mu=-0.1), "mu must be >= 0")):
        with pytest.raises(ValueError, match=msg):
            fr.step(**dict(base, **change))
    two = dict(base, a=np.array([0, 0], np.int32), b=np.array([1, 1], np.int32), px=np.zeros(2),
               py=np.zeros(2), nx=np.zeros(2), ny=np.ones(2), fn=np.ones(2))
    with pytest.raises(ValueError, match="same body pair"):
        fr.step(**two)
