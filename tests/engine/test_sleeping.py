"""The sleeping far field (engine/src/model/sleeping.hpp, docs/model.md §3.5):
bodies at rest are held and their triangles skipped, without
changing what the run computes beyond the stated sleep force."""
import numpy as np
import pytest

from icerubble import engine
from tests.engine.freeze_bonds_scenes import body_nodes, pull_bar, two_block_bar

ICE = dict(E=2e9, nu=0.3, rho=920.0, damping=0.0)


def block_on_floor(drop=False, threads=1, h=0.1, settle=True):
    """A 1 m x 0.5 m block at rest on a held floor (settled with local
    damping); with drop=True a second 0.4 m x 0.3 m block starts 0.1 m above
    it, falling. Elements of size h."""
    k = int(round(0.1 / h))
    nf, tf = engine.rectangle_mesh(20 * k, 2 * k, h, origin=(-1.0, -0.2))
    nb, tb = engine.rectangle_mesh(10 * k, 5 * k, h, origin=(-0.5, 0.0))
    parts = [(nf, tf), (nb, tb)]
    if drop:
        parts.append(engine.rectangle_mesh(4 * k, 3 * k, h, origin=(-0.3, 0.6)))
    nodes, tri, body, off = [], [], [], 0
    for b, (n, t) in enumerate(parts):
        nodes.append(n)
        tri.append(t + off)
        body.append(np.full(len(t), b))
        off += len(n)
    nodes, tri, body = np.concatenate(nodes), np.concatenate(tri), np.concatenate(body)
    m = engine.Model(nodes, tri, body, materials=ICE, node_sets={"floor": np.arange(len(nf))})
    m.set(gravity=True, water=False, mu=0.3, penalty=2e9, threads=threads, local_damping=0.7)
    m.fix("floor")
    m.set(dt_fraction=0.8)
    if drop:  # hold the falling block until the lower one is at rest
        top = body_nodes(m, 2)
        m.add_node_set("top", top)
        m.fix("top")
    if settle:
        m.step(int(0.23 / m.dt))
    m.set(local_damping=0.0)
    if drop:
        m.clear_boundary_conditions()
        m.fix("floor")
    return m


def centroid(m, b):
    return m.positions[body_nodes(m, b)].mean(axis=0)


def test_a_block_at_rest_falls_asleep_and_its_triangles_are_not_computed():
    m = block_on_floor()
    m.set(sleeping=True)
    n_tri = m.n_triangles
    e0 = m.timings()["element_steps"]
    m.step(200)  # quiet_steps = 100 updates, then one more computation
    block = body_nodes(m, 1)
    c = m.sleep_counts()
    assert c["asleep_nodes"] == len(block)  # the floor is held: held nodes never sleep
    floor_tris = int(np.sum(np.asarray(m.body) == 0))
    assert c["awake_triangles"] == floor_tris
    e1 = m.timings()["element_steps"]
    m.step(100)
    assert m.timings()["element_steps"] - e1 == 100 * floor_tris
    assert e1 - e0 < 200 * n_tri
    # held in place: the floor still carries the block's weight (to the sleep force)
    weight_block = 920.0 * 9.81 * 0.5
    weight_floor = 920.0 * 9.81 * 0.4
    ry = m.reaction("floor")[1]
    assert ry == pytest.approx(weight_block + weight_floor, abs=1e-3 * 9.81 * m.mass_phys[block].sum())


def test_an_impact_wakes_the_sleeping_block_and_the_run_matches_one_without_sleeping():
    runs = {}
    for sleeping in (False, True):
        m = block_on_floor(drop=True)
        m.set(sleeping=sleeping)
        m.step(300)  # lower block asleep, upper one falling
        asleep_before = m.sleep_counts()["asleep_nodes"]
        m.step(int(0.2 / m.dt))  # falls 0.1 m in 0.14 s, hits, bounces about
        runs[sleeping] = (m, asleep_before)
    m0, _ = runs[False]
    m1, asleep_before = runs[True]
    lower = body_nodes(m1, 1)
    assert asleep_before >= len(lower)
    # the lower block was woken by the impact and moved as it does without sleeping
    u0 = m0.positions[lower] - m0.reference_positions[lower]
    u1 = m1.positions[lower] - m1.reference_positions[lower]
    assert np.abs(u0).max() > 1e-6
    assert np.abs(u1 - u0).max() < 0.02 * np.abs(u0).max()
    assert centroid(m1, 2) == pytest.approx(centroid(m0, 2), abs=1e-4)
    # the ledger closes with the sleeping nodes' kinetic energy booked as damping
    e = m1.energies()
    assert abs(e["residual"]) < 1e-3 * e["work_gravity"]


def test_no_bond_point_fails_unseen_in_a_sleeping_region():
    """The bonded bar at rest falls asleep; pulling its far end wakes it and
    the bond fails at the step it fails without sleeping, to a few steps."""
    out = {}
    for sleeping in (False, True):
        m, bp, nodes, H = pull_bar(v_slow=1e-3, t_fast=0.03)
        m.set(sleeping=sleeping, sleep_quiet_steps=20)
        fail_step = None
        n = 0
        while fail_step is None and n < 400000:
            m.step(200)
            n += 200
            if m.bonds.counts["failed"] > 0:
                fail_step = n
        assert fail_step is not None
        out[sleeping] = (fail_step, m.bonds.counts["failed"], m.timings()["element_steps"])
    assert out[True][0] == pytest.approx(out[False][0], rel=0.01)
    assert out[True][1] == out[False][1]


@pytest.mark.parametrize("asleep", [0, 1])
def test_a_split_wakes_the_bodies_of_the_bond_point(asleep):
    """One block free and asleep with a sleep force nothing reaches: it holds
    like a support while the other block is pulled off rigidly, and only the
    split of its bond points can wake it; the split wakes the whole block.
    Both ways round: a split gives new nodes to the lower body and leaves the
    shared node with the higher one, and either must wake."""
    m, bp, nodes = two_block_bar(sigma_cr=1e4, tau_cr=5e4, G=1.0)
    L = nodes[:, 0].max()
    free = body_nodes(m, asleep)
    driven = np.flatnonzero(nodes[:, 0] > 0.5 * L + 1e-9) if asleep == 0 else \
        np.flatnonzero(nodes[:, 0] < 0.5 * L - 1e-9)
    m.add_node_set("driven", driven)
    m.prescribe_velocity("driven", (1, 0) if asleep == 0 else (-1, 0), table=([0.0, 0.01], [0.0, 1e-2]))
    m.set(dt=0.9 * m.stable_time_step()["dt"])
    # a free body at rest falls asleep at the end of its first window (the
    # driven block never does) and stays asleep unless woken
    m.set(sleeping=True, sleep_force=1e9, sleep_velocity=1e3, sleep_quiet_steps=1)
    m.step(3)
    free = free[m._m.sleep_state()["sleep"][free] != 0]   # the shared nodes sleep with one of the two
    assert len(free) >= len(body_nodes(m, asleep)) - 5
    assert np.all(m._m.sleep_state()["sleep"][free] == 2)
    assert np.all(m._m.sleep_state()["sleep"][driven] == 0)
    x_free = m.positions[free].copy()
    while m.bonds.counts["split"] == 0:
        before, x_before = m._m.sleep_state()["sleep"][free], m.positions[free]
        m.step(1)
        assert m.time < 0.1
    assert np.all(before == 2)                  # asleep up to the split, and held in place ...
    np.testing.assert_array_equal(x_before, x_free)
    after = m._m.sleep_state()["sleep"]
    assert np.all(after[body_nodes(m, asleep)] == 0)  # ... and the split woke the whole block


def test_resume_with_sleeping_is_bit_identical():
    m = block_on_floor(drop=True)
    m.set(sleeping=True)
    m.step(400)
    cp = m.checkpoint()
    m_state = {k: np.copy(v) for k, v in m._m.sleep_state().items()}
    assert 0 < m.sleep_counts()["asleep_nodes"]
    m.step(3000)
    r = engine.Model.from_checkpoint(cp, ICE)
    r.set(gravity=True, water=False, mu=0.3, penalty=2e9, threads=1, dt=m.dt, sleeping=True)
    r.fix("floor")
    r.restore_checkpoint(cp)
    for k, v in r._m.sleep_state().items():   # nodes, their reference forces and the open window
        assert np.array_equal(v, m_state[k]), k
    r.step(3000)
    assert np.array_equal(r.positions, m.positions)
    assert np.array_equal(r.velocities, m.velocities)


def test_sleeping_parameters_are_checked():
    m = block_on_floor()
    for k, v in (("sleep_velocity", -1.0), ("sleep_force", float("nan")), ("sleep_quiet_steps", 0),
                 ("sleep_quiet_steps", 2.5)):
        with pytest.raises(ValueError, match=k):
            m.set(**{k: v})


def test_one_and_two_threads_agree_with_sleeping():
    """The lower block falls asleep while it settles (local
    damping on), the upper block falling meanwhile: a mixed state that
    changes every few steps."""
    runs = []
    for threads in (1, 2):
        m = block_on_floor(drop=True, threads=threads, h=0.025, settle=False)
        assert m.n_triangles >= 2048  # else the engine runs one thread
        m.set(local_damping=0.7, sleeping=True, sleep_velocity=1e-3, sleep_force=0.05, sleep_quiet_steps=20)
        asleep = []
        for _ in range(30):
            m.step(100)
            asleep.append(m.sleep_counts()["asleep_nodes"])
        runs.append((m, asleep))
    (a, asleep_a), (b, asleep_b) = runs
    assert asleep_a[0] == 0 and 0 < asleep_a[-1] < a.n_nodes
    assert asleep_a == asleep_b
    scale = np.abs(a.displacements).max()
    assert scale > 0
    assert np.abs(a.positions - b.positions).max() < 1e-9 * scale


@pytest.mark.parametrize("offset, sleeps", [(0.0, True), (0.01, False)])
def test_a_body_sleeps_only_in_balance(offset, sleeps):
    """A free block floating at its draft (rho_i/rho_w of its thickness)
    falls asleep; the same block 1 cm above it, out of balance by
    rho_w g w 0.01 (2.2 % of its weight), never does, however slow it is (the
    speed test is switched off here). A window of 10 ms averages the block's
    elastic vibration (period ~1 ms), not its heave (1.4 s)."""
    from icerubble.parameters import RHO_I, RHO_W
    t = 0.5
    bottom = -RHO_I / RHO_W * t + offset
    nodes, tri = engine.rectangle_mesh(8, 2, 0.25, origin=(-1.0, bottom))
    m = engine.Model(nodes, tri, np.zeros(len(tri), int), dict(E=1e8, nu=0.3, rho=RHO_I))
    m.set(gravity=True, buoyancy=True, drag=False, y_w=0.0, rho_w=RHO_W)
    m.set(dt=0.9 * m.stable_time_step()["dt"])
    quiet = int(round(0.01 / m.dt))
    m.set(sleeping=True, sleep_velocity=1e3, sleep_force=1e-3, sleep_quiet_steps=quiet)
    asleep = []
    for _ in range(20):
        m.step(quiet)
        asleep.append(m.sleep_counts()["asleep_nodes"])
    assert max(asleep) == (m.n_nodes if sleeps else 0)
