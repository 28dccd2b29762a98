"""The normal contact pass of a pile-like state with many touching pairs at
any thread count: each thread lists its chunk's touching candidates, the
pairs are made in parallel, and the forces are added onto the nodes in pair
order, so the contact forces, the touching pairs and friction's forces are
the same bits on one thread and on two (a loaded pile has ~1,000 touching
pairs among tens of thousands of candidates, above the sizes from which
these parts run threaded)."""
import numpy as np

from icerubble import engine
from tests.engine.test_friction_order import wall_of_squares


def pressed_wall(threads):
    rng = np.random.default_rng(11)
    pts, tri, body = wall_of_squares(rng, rows=14, cols=24)
    m = engine.Model(pts, tri, body, dict(E=1e9, nu=0.3, rho=920.0))
    m.set(threads=threads, penalty=2e11, mu=0.3)
    m.set_velocities(rng.normal(0.0, 1e-3, pts.shape))
    m.set(dt=0.5 * m.stable_time_step()["dt"])
    m.step(2)
    return m


def test_the_contact_pass_of_many_touching_pairs_is_the_same_on_one_and_two_threads():
    one, two = pressed_wall(1), pressed_wall(2)
    assert one.touching_pairs >= 1000, one.touching_pairs  # the threaded making of the pairs runs
    assert one.touching_pairs == two.touching_pairs
    for kind in ("contact", "total"):
        assert np.array_equal(one.forces(kind), two.forces(kind)), kind
    assert np.array_equal(one.positions, two.positions) and np.array_equal(one.velocities, two.velocities)
