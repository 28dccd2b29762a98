"""The normal contact pass and friction of a wall of pressed blocks with many
touching pairs at any thread count: each thread lists its chunk's touching
candidates, the pairs are made in parallel and their forces added onto the
nodes in pair order; friction's phases run colour by colour, threaded where
the colours are large (no two pairs of a colour share a node). So the contact
forces, the touching pairs and friction's forces are the same bits on one
thread and on two. (A loaded pile has ~1,000 touching pairs among tens of
thousands of candidates, above the sizes from which the contact pass runs
threaded; its friction, ~50 pairs a colour, runs island by island:
test_friction_islands.py. The wall here is nearly one island: colour by colour.)"""
import numpy as np

from icerubble import engine
from tests.engine.test_friction_order import friction_step, wall_of_squares

ROWS, COLS = 30, 40


def pressed_wall(threads):
    rng = np.random.default_rng(11)
    pts, tri, body = wall_of_squares(rng, rows=ROWS, cols=COLS)
    m = engine.Model(pts, tri, body, dict(E=1e9, nu=0.3, rho=920.0))
    m.set(threads=threads, penalty=2e11, mu=0.3)
    m.set_velocities(rng.normal(0.0, 1e-3, pts.shape))
    m.set(dt=0.5 * m.stable_time_step()["dt"])
    m.step(2)
    return m


def test_contact_and_friction_of_many_touching_pairs_are_the_same_on_one_and_two_threads():
    # the colours hold 256 pairs or more on average: friction runs threaded
    # (engine/src/contact/friction.cpp, kMinPairsPerColour)
    rng = np.random.default_rng(11)
    pts, tri, body = wall_of_squares(rng, rows=ROWS, cols=COLS)
    solver, touching, _, _ = friction_step(pts, tri, body, np.zeros_like(pts), np.zeros_like(pts), 0.1)
    assert touching >= 256 * (len(solver.sweep_order["colour_start"]) - 1), touching
    one, two = pressed_wall(1), pressed_wall(2)
    assert one.touching_pairs >= 10000 and one.touching_pairs == two.touching_pairs, one.touching_pairs
    for kind in ("contact", "total"):
        assert np.array_equal(one.forces(kind), two.forces(kind)), kind
    assert np.array_equal(one.positions, two.positions) and np.array_equal(one.velocities, two.velocities)
    # friction's power as its solver sums it (the ledger's other sums are per thread)
    assert one._m.energy()["friction_solver"] == two._m.energy()["friction_solver"] != 0.0
