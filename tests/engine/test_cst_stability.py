"""Stable time step and the instability guard."""
import numpy as np
import pytest

from icerubble import engine

MAT = dict(E=1e9, nu=0.3, rho=900.0)


def distorted(nx=4, ny=3, h=0.2, seed=1, bodies=None):
    nodes, tri = engine.rectangle_mesh(nx, ny, h)
    i = np.arange(len(nodes)) % (nx + 1)
    j = np.arange(len(nodes)) // (nx + 1)
    inner = (i > 0) & (i < nx) & (j > 0) & (j < ny)
    nodes[inner] += np.random.default_rng(seed).uniform(-0.2, 0.2, (inner.sum(), 2)) * h
    body = np.zeros(len(tri), int) if bodies is None else bodies(tri, nodes)
    return nodes, tri, body


def global_omega_max(m, nodes):
    """Largest eigenfrequency of the lumped-mass system at the reference
    state, with the stiffness from central differences of the engine's own
    internal forces (exact for the linearised St Venant-Kirchhoff element
    up to O(eps²))."""
    n = len(nodes)
    K = np.zeros((2 * n, 2 * n))
    eps = 1e-7
    for k in range(2 * n):
        f = []
        for s in (1, -1):
            x = nodes.copy()
            x[k // 2, k % 2] += s * eps
            m.set_positions(x)
            m.evaluate()
            f.append(m.forces("internal").ravel())
        K[:, k] = -(f[0] - f[1]) / (2 * eps)
    Minv = 1.0 / np.repeat(m.mass, 2)
    w2 = np.linalg.eigvals(Minv[:, None] * K).real.max()
    m.set_positions(nodes)
    return np.sqrt(w2)


def test_element_bound_is_safe_and_not_wasteful():
    """Irons: the largest element eigenfrequency bounds the global one, so
    2/w_e <= 2/w_global. For a mesh of similar triangles the bound is within
    a factor ~1.5 of the truth; require better than 0.5."""
    nodes, tri, body = distorted()
    m = engine.Model(nodes, tri, body, MAT)
    m.set(gravity=False)
    w = global_omega_max(m, nodes)
    s = m.stable_time_step()
    assert s["governing"] == "element"
    assert s["dt_element"] <= 2.0 / w * (1 + 1e-6)
    assert s["dt_element"] >= 0.5 * 2.0 / w
    assert s["dt"] == pytest.approx(0.9 * s["dt_element"])


def test_damping_lowers_the_stable_step():
    """With strain-rate damping xi = w tau/2 the central difference is stable
    for dt <= (2/w)(sqrt(1 + xi²) - xi) (Belytschko)."""
    nodes, tri, body = distorted()
    m0 = engine.Model(nodes, tri, body, MAT)
    tau = 2e-5
    m1 = engine.Model(nodes, tri, body, dict(MAT, damping=tau))
    s0, s1 = m0.stable_time_step(), m1.stable_time_step()
    xi = 0.5 * (2.0 / s0["dt_element"]) * tau
    assert s1["damping_ratio"] == pytest.approx(xi)
    assert s1["dt_element"] == pytest.approx(s0["dt_element"] * (np.sqrt(1 + xi**2) - xi))


def two_bodies(h):
    nodes, tri = engine.rectangle_mesh(int(round(1.0 / h)), int(round(0.2 / h)), h)
    body = (nodes[tri].mean(axis=1)[:, 0] > 0.5).astype(int)
    m = engine.Model(nodes, tri, body, dict(E=2e9, nu=0.3, rho=920.0))
    m.set(penalty=2e11)
    return m


def test_contact_limit_at_paper_parameters():
    """Table 1: E = 2 GPa, s = 2e11 Pa. The penalty governs the step, and its
    limit sqrt(m/k) scales with the element size h (node mass ~ h², contact
    stiffness ~ s independent of h): exact for these similar structured meshes.
    The paper's dt = 1e-6 s is accepted at h = 0.1 m; at h = 0.05 m the
    potential contact (node stiffness several times s) needs a smaller step,
    and the guard says so, naming the contact limit."""
    coarse, fine = two_bodies(0.1), two_bodies(0.05)
    sc, sf = coarse.stable_time_step(), fine.stable_time_step()
    assert sc["governing"] == sf["governing"] == "contact"
    assert sf["dt_contact"] / sc["dt_contact"] == pytest.approx(0.5, rel=1e-9)
    coarse.set(dt=1e-6)
    coarse.step(2)
    fine.set(dt=1e-6)
    with pytest.raises(ValueError, match="contact"):
        fine.step(1)


def test_dt_above_the_stable_step_raises_before_stepping():
    nodes, tri, body = distorted()
    m = engine.Model(nodes, tri, body, MAT)
    s = m.stable_time_step()
    m.set(dt=1.01 * s["dt"])
    with pytest.raises(ValueError) as err:
        m.step(10)
    msg = str(err.value)
    assert "dt = " in msg and "stable time step" in msg and f"triangle {s['element']}" in msg
    assert "smallest altitude" in msg and "wave speed" in msg
    assert m.step_count == 0 and np.array_equal(m.positions, nodes)


def unstable_model(**params):
    nodes, tri, body = distorted()
    m = engine.Model(nodes, tri, body, MAT)
    m.set(gravity=False)
    w = global_omega_max(m, nodes)
    # 1.3 x the true critical step: the highest mode grows ~4.5x per step.
    m.set(dt=1.3 * 2.0 / w, check_stable_dt=False, **params)
    m.set_velocities(np.random.default_rng(0).normal(0, 1e-3, nodes.shape))
    return m


def test_unstable_run_stops_with_step_energy_and_place():
    m = unstable_model()
    with pytest.raises(engine.InstabilityError) as err:
        m.step(1000)
    msg = str(err.value)
    assert "run stopped at step" in msg
    assert "energy grew without an energy source" in msg
    assert "at node" in msg and "of body 0" in msg and "at triangle" in msg
    assert m.step_count < 50  # caught within a few steps of the blow-up


def test_unstable_run_without_energy_check_stops_before_writing_nan():
    """With the energy check effectively off, the guard still stops at the
    first collapsed element or non-finite value."""
    m = unstable_model(check_energy=False)
    with pytest.raises(engine.InstabilityError) as err:
        m.step(100000)
    msg = str(err.value)
    assert "run stopped at step" in msg
    assert ("element inverted" in msg and "at triangle" in msg) or ("non-finite" in msg and "at node" in msg)


def test_rough_start_at_the_stable_step_is_not_stopped():
    """The guard must not fire on a sound run: a random (mesh-scale) initial
    deformation released at the stable step puts energy into the highest
    modes, whose plain energy overshoots the conserved shadow energy (up to
    5x at 0.9 of the critical step). 3000 steps without an error, and the
    balance residual stays at the O((w dt)²) level of those modes (measured
    2e-3 of the initial energy; tolerance 1e-2)."""
    nodes, tri, body = distorted()
    m = engine.Model(nodes, tri, body, MAT)
    m.set(gravity=False)
    m.set_positions(nodes + np.random.default_rng(2).normal(0, 1e-4, nodes.shape))
    m.set(dt=m.stable_time_step()["dt"])
    m.step(3000)
    e = m.energies()
    assert abs(e["residual"]) < 1e-2 * e["initial"]


def test_contact_limit_of_a_bonded_mesh_is_that_of_its_split_bodies():
    """Freeze-bonded bodies share nodes until their bond points split; the
    contact limit must already hold for the split state (split nodes are
    lighter and become boundary nodes), so it equals the limit of the same
    bodies meshed apart (every shared node duplicated)."""
    h = 0.1
    nodes, tri = engine.rectangle_mesh(10, 4, h)
    body = (nodes[tri].mean(axis=1)[:, 0] > 0.5).astype(int)
    bonded = engine.Model(nodes, tri, body, dict(E=2e9, nu=0.3, rho=920.0))
    # duplicate the interface nodes for body 1
    shared = np.intersect1d(np.unique(tri[body == 0]), np.unique(tri[body == 1]))
    copy = {int(k): len(nodes) + i for i, k in enumerate(shared)}
    nodes2 = np.vstack([nodes, nodes[shared]])
    tri2 = tri.copy()
    for t in np.flatnonzero(body == 1):
        tri2[t] = [copy.get(int(k), k) for k in tri2[t]]
    apart = engine.Model(nodes2, tri2, body, dict(E=2e9, nu=0.3, rho=920.0))
    for m in (bonded, apart):
        m.set(penalty=2e11)
    sb, sa = bonded.stable_time_step(), apart.stable_time_step()
    assert sb["dt_contact"] == pytest.approx(sa["dt_contact"], rel=1e-12)


def test_a_step_just_above_the_stable_one_is_refused_with_digits_that_show_it():
    """4 digits printed 3.861e-08 for both steps; the message now shows the
    overshoot (issue 11)."""
    nodes, tri = engine.rectangle_mesh(4, 2, 0.1)
    m = engine.Model(nodes, tri, np.zeros(len(tri), dtype=int),
                   materials=dict(E=2e9, nu=0.3, rho=920.0))
    m.set(gravity=False, water=False)
    st = m.stable_time_step()["dt"]
    m.set(dt=st * (1 + 1e-12))
    with pytest.raises(ValueError) as e:
        m.step(1)
    msg = str(e.value)
    assert repr(st * (1 + 1e-12))[:14] in msg and repr(st)[:14] in msg
    assert "by 1.0000" in msg and "e-10 %" in msg


def test_a_run_at_exactly_the_stable_step_is_not_refused_when_bond_points_split():
    """dt_fraction = 1 is the stable step itself; the step recomputed after
    the bond points split (in the reference configuration, per-body shares)
    equals it up to round-off, which is no reason to stop (issue 11: the
    demo at 1.0 was refused at the first split, the step recomputed at the
    deformed positions 5e-7 below)."""
    from tests.engine.freeze_bonds_scenes import pull_bar
    m, bp, nodes, H = pull_bar(v_slow=1e-3, t_fast=0.03)
    m.set(dt_fraction=1.0)
    before = m.stable_time_step()["dt"]
    while m.bonds.counts["split"] < len(bp.node):
        m.step(500)
        assert m.time < 0.2
    m.step(500)  # on after every split
    assert m.stable_time_step()["dt"] == pytest.approx(before, rel=1e-12)
