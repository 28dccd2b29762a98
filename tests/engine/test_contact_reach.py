"""The contact step bound with a finite reach (contact_time_step.cpp,
Model::set_parameters, contact_reach): an edge counts only the other bodies' boundaries it
can meet, and the run re-checks the bound when nodes have moved half the reach.
The scenes are those of test_contact_time_step.py: block A facing block B,
which may carry a 3 mm bump (the tiny elements of a pile's junction)."""
import numpy as np
import pytest

from icerubble import _engine, engine
from tests.engine.test_contact_time_step import ICE, S, two_blocks

REACH = 0.1


def a_limit(nodes, tri, body, na, reach):
    """Contact limit of A's nodes alone (B's nodes infinitely heavy)."""
    m = engine.Model(nodes, tri, body, materials=ICE)
    mass = np.array(m.mass)
    mass[na:] = np.inf
    return _engine.contact_critical_dt(nodes[:, 0].copy(), nodes[:, 1].copy(), mass, tri, S, body,
                                       reach=reach)["dt"]


@pytest.fixture(scope="module")
def far():
    """B (with and without bump) 0.3 m from A: out of reach."""
    return {b: two_blocks(b, gap=0.3) for b in (False, True)}


@pytest.fixture(scope="module")
def near():
    return {b: two_blocks(b) for b in (False, True)}


def test_out_of_reach_the_tiny_element_does_not_count(far):
    """With the whole mesh as reach the bump 0.3 m away lowers A's limit; with
    a 0.1 m reach A's nodes get exactly the limit of a scene without it."""
    lim = {(b, r): a_limit(*far[b], r) for b in (False, True) for r in (np.inf, REACH)}
    assert lim[(True, np.inf)] < 0.9 * lim[(False, np.inf)]
    assert lim[(True, REACH)] == lim[(False, REACH)]
    assert lim[(True, REACH)] > lim[(True, np.inf)]


def test_within_reach_the_tiny_element_counts(near):
    """2 mm from the bump, A's nodes facing it still get the bump's stiffness:
    the local limit lies below the clean mesh's and not below the global one."""
    with_bump = a_limit(*near[True], REACH)
    assert with_bump < 0.9 * a_limit(*near[False], REACH)
    assert with_bump >= a_limit(*near[True], np.inf)


def run_towards(gap, dt_factor, v=5.0, t_end=0.03):
    """A moves at v towards B (bump) from `gap` away; dt = dt_factor x the
    stable step with the 0.1 m reach at the start."""
    nodes, tri, body, na = two_blocks(True, gap=gap)
    m = engine.Model(nodes, tri, body, materials=ICE)
    m.set(gravity=False, water=False, mu=0.0, penalty=S, contact_reach=REACH)
    m.set(dt=dt_factor * m.stable_time_step()["dt"])
    vel = np.zeros((len(nodes), 2))
    vel[:na, 0] = v
    m.set_velocities(vel)
    return m, na


def test_a_run_whose_step_no_longer_holds_stops_with_the_reason():
    """A starts 0.12 m from B, out of reach: its step is the larger one of an
    edge with nothing to meet. Once A has moved 5 cm (half the reach) the
    bound is taken again with B in reach, dt is above it, and the run stops
    saying why, long before A touches B."""
    m, na = run_towards(gap=0.12, dt_factor=0.99)
    with pytest.raises(_engine.InstabilityError, match="contact reach") as err:
        m.step(int(0.03 / m.dt))
    assert "exceeds the contact stable step" in str(err.value)
    assert m.touching_pairs == 0
    moved = m.positions[:na, 0] - m.reference_positions[:na, 0]
    assert 0.05 <= moved.max() < 0.07


def test_a_run_at_the_step_of_the_nearby_bump_goes_through_the_impact():
    """The same approach from 2 mm, where the bound already counts the bump:
    A hits it at 1 m/s and rebounds with its energy."""
    m, na = run_towards(gap=2e-3, dt_factor=0.9, v=1.0)
    E0 = 0.5 * np.asarray(m.mass)[:na].sum()
    touched = 0
    for _ in range(400):
        m.step(max(1, int(5e-5 / m.dt)))
        touched = max(touched, m.touching_pairs)
        if touched and m.touching_pairs == 0:
            break
    assert touched > 0 and m.touching_pairs == 0
    e = m.energies()
    assert e["kinetic"] + e["elastic"] == pytest.approx(E0, rel=5e-3)


def test_contact_reach_is_checked():
    nodes, tri, body, na = two_blocks(False)
    m = engine.Model(nodes, tri, body, materials=ICE)
    for bad in (0.0, -1.0, float("nan")):
        with pytest.raises(ValueError, match="contact_reach"):
            m.set(contact_reach=bad)


def test_a_resumed_run_gets_the_masses_of_the_run_it_continues():
    """Mass scaling is taken in the reference configuration: after A has
    moved 2 cm towards the bump (now within reach of its edges), a model
    rebuilt from a checkpoint gets the same masses, and steps on bit for bit."""
    nodes, tri, body, na = two_blocks(True, gap=0.21)  # the bump comes within reach + edge

    def configured(m):
        m.set(gravity=False, water=False, mu=0.0, penalty=S, contact_reach=REACH)
        m.set(mass_scaling_dt=2e-7)
        return m

    m = configured(engine.Model(nodes, tri, body, materials=ICE))
    assert np.any(np.asarray(m.mass) > np.asarray(m.mass_phys))
    m.set(dt=0.9 * m.stable_time_step()["dt"])
    vel = np.zeros((len(nodes), 2))
    vel[:na, 0] = 1.0
    m.set_velocities(vel)
    m.step(int(0.02 / m.dt))
    assert_resumes_bit_for_bit(m, configured)


def assert_resumes_bit_for_bit(m, configure):
    """m rebuilt from its checkpoint (configure: sets what a checkpoint does not
    carry) has m's masses and steps on bit for bit."""
    cp = m.checkpoint()
    r = engine.Model.from_checkpoint(cp, ICE)
    configure(r)
    r.set(dt=m.dt)
    r.restore_checkpoint(cp)
    assert np.array_equal(np.asarray(r.mass), np.asarray(m.mass))
    m.step(500)
    r.step(500)
    assert np.array_equal(r.positions, m.positions)


def towards_with_mass_scaling():
    """The approach of the first test (A at 5 m/s towards B's bump from 0.12 m,
    dt at 0.99 of the start's bound), B moving towards A at 0.5 m/s, and mass
    scaling allowed (a target below every limit: nothing is scaled at the start)."""
    nodes, tri, body, na = two_blocks(True, gap=0.12)
    m = engine.Model(nodes, tri, body, materials=ICE)
    m.set(gravity=False, water=False, mu=0.0, penalty=S, contact_reach=REACH, mass_scaling_dt=1e-12)
    m.set(dt=0.99 * m.stable_time_step()["dt"])
    vel = np.zeros((len(nodes), 2))
    vel[:na, 0] = 5.0
    vel[na:, 0] = -0.5
    m.set_velocities(vel)
    return m, na


def test_with_mass_scaling_on_the_guard_scales_the_nodes_that_need_it_instead_of_stopping():
    """Where the first test stops (the bound taken again with the bump in
    reach is below dt), the nodes that need it get the mass the step needs and
    the run goes on, the gap closing to 1 cm: the raise keeps each node's
    momentum (the total is exactly conserved: no gravity, water or friction),
    and the kinetic energy it takes is booked as damping (the ledger closes)."""
    m, na = towards_with_mass_scaling()
    assert m.stable_time_step()["scaled_nodes"] == 0
    mass0 = np.array(m.mass)   # a copy: m.mass is a view
    E0 = 0.5 * (mass0[:, None] * m.velocities ** 2).sum()
    p0 = (mass0[:, None] * m.velocities).sum(axis=0)
    m.step(int(0.02 / m.dt))   # A and B 1 cm apart, not yet touching
    assert m._m.raised_nodes() > 0 and m.touching_pairs == 0
    st = m.stable_time_step()
    assert st["scaled_nodes"] > 0 and st["added_mass_fraction"] > 0.0
    mass = np.asarray(m.mass)
    assert np.all(mass >= np.asarray(m.mass_phys)) and np.all(mass >= m._m.mass_floor())
    assert np.array_equal(mass > mass0, m._m.mass_floor() > 0)   # raised exactly where floors are
    p = (mass[:, None] * m.velocities).sum(axis=0)
    np.testing.assert_allclose(p, p0, rtol=1e-12, atol=1e-12 * abs(p0[0]))
    e = m.energies()
    assert e["damping"] > 0.0
    assert e["kinetic"] + e["elastic"] + e["damping"] == pytest.approx(E0, rel=1e-9)


def test_mass_floors_travel_with_the_checkpoint():
    """A run whose nodes were raised mid-run, rebuilt from its checkpoint,
    gets the same masses and steps on bit for bit."""
    m, na = towards_with_mass_scaling()
    m.step(int(0.015 / m.dt))
    assert m._m.raised_nodes() > 0
    assert_resumes_bit_for_bit(m, lambda r: r.set(gravity=False, water=False, mu=0.0, penalty=S,
                                                  contact_reach=REACH, mass_scaling_dt=1e-12))


def test_where_the_reach_guard_measures_from_travels_with_the_checkpoint():
    """After the guard has taken the bound again (A has moved past reach/2),
    it measures later moves from there, not from the mesh: a model rebuilt
    from the checkpoint measures from the same place, so it re-checks (and
    raises masses) at the same steps as the run it continues."""
    m, na = towards_with_mass_scaling()
    m.step(int(0.015 / m.dt))
    x, y = m._m.reach_origin()
    assert np.abs(x - m.reference_positions[:, 0]).max() > 0.5 * REACH
    cp = m.checkpoint()
    r = engine.Model.from_checkpoint(cp, ICE)
    r.set(gravity=False, water=False, mu=0.0, penalty=S, contact_reach=REACH, mass_scaling_dt=1e-12, dt=m.dt)
    r.restore_checkpoint(cp)
    r.step(1)   # prepared: a restored model without the origin would measure from the mesh
    m.step(1)
    rx, ry = r._m.reach_origin()
    mx, my = m._m.reach_origin()
    assert np.array_equal(rx, mx) and np.array_equal(ry, my)


def test_points_split_within_a_call_are_measured_from_their_reference_place():
    """A split adds nodes in the middle of a step(n) call, which prepares the
    model once, at its start: the reach guard after it measures the new
    nodes from their reference places, as a call that starts after the
    split does (it read past the origins' end before). So the same steps
    taken in one call and one at a time give the same bits, guard and mass
    raises included."""
    from tests.engine.freeze_bonds_scenes import two_block_bar

    def flung():
        m, bp, nodes = two_block_bar(sigma_cr=1e4, tau_cr=5e4, G=0.2)
        m.set(penalty=1e11, contact_reach=0.01, mass_scaling_dt=2e-6)
        body, tri = np.asarray(m.body), np.asarray(m.triangles)
        v = np.zeros((m.n_nodes, 2))
        v[np.unique(tri[body == 0])] = (-0.05, 0.02)
        v[np.unique(tri[body == 1])] = (0.05, -0.01)
        m.set_velocities(v)
        m.set(dt=0.9 * m.stable_time_step()["dt"])
        return m, len(bp)

    whole, n_points = flung()
    whole.step(1500)
    apart, _ = flung()
    for _ in range(1500):
        apart.step(1)
    assert whole.bonds.counts["split"] == n_points   # the points split within the one call
    assert np.array_equal(whole.positions, apart.positions)
    assert np.array_equal(whole.velocities, apart.velocities)
    assert np.array_equal(whole.mass, apart.mass)
    rw, ra = whole._m.reach_origin(), apart._m.reach_origin()
    assert all(np.array_equal(a, b) for a, b in zip(rw, ra))
