"""The contact's stable-step bound near a tiny element (contact.hpp,
contact_time_step.cpp).

A rubble pile's mesh has a few millimetre-sized elements where block faces
meet at a junction. The contact stiffness of a boundary node counts the other
body's side of the contact as the integral of 1/a' (a' the altitude of the
target triangle) over the stretch of boundary the node's edge can rest on; a
tiny element counts only over its own short edge. These tests make such an
element (a 3 mm bump on a block face, meshed by gmsh at h = 0.1 m) and check
that it does not cut the contact step of every node as the smallest altitude
anywhere did, that the bound's stiffness is the formula's on meshes where it
is known by hand, that a run at the bound stays stable through an impact on
the bump itself, and that selective mass scaling of viscous tiny elements
reaches its step with less mass than before.
"""
import gmsh
import numpy as np
import pytest

from icerubble import _engine, engine

ICE = dict(E=2e9, nu=0.3, rho=920.0, damping=0.0)
S = 2e11
H = 0.1          # element size [m]
BUMP = 3e-3      # width and height of the bump [m]


def mesh_polygon(points, h):
    """Triangles of a polygon (counter-clockwise), gmsh at size h."""
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("p")
        tags = [gmsh.model.geo.addPoint(x, y, 0.0, h) for x, y in points]
        lines = [gmsh.model.geo.addLine(tags[i], tags[(i + 1) % len(tags)]) for i in range(len(tags))]
        gmsh.model.geo.addPlaneSurface([gmsh.model.geo.addCurveLoop(lines)])
        gmsh.model.geo.synchronize()
        gmsh.model.mesh.generate(2)
        ids, xyz, _ = gmsh.model.mesh.getNodes()
        _, _, conn = gmsh.model.mesh.getElements(2)
        index = {int(t): i for i, t in enumerate(ids)}
        nodes = xyz.reshape(-1, 3)[:, :2].copy()
        tri = np.array([index[int(t)] for t in conn[0]], dtype=np.int64).reshape(-1, 3)
    finally:
        gmsh.finalize()
    # drop nodes gmsh kept but no triangle uses, keep counter-clockwise order
    used = np.unique(tri)
    remap = -np.ones(len(nodes), dtype=np.int64)
    remap[used] = np.arange(len(used))
    nodes, tri = nodes[used], remap[tri]
    p = nodes[tri]
    cross = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - \
            (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1])
    tri[cross < 0] = tri[cross < 0][:, [0, 2, 1]]
    return nodes, tri


def block(x0, y0, w, h, bump=False):
    """A w x h block; with bump, a BUMP-sized triangular bump sticks out of the
    middle of its left face (the tiny element of a pile's junction)."""
    pts = [(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)]
    if bump:
        ym = y0 + h / 2
        pts += [(x0, ym + BUMP / 2), (x0 - BUMP, ym), (x0, ym - BUMP / 2)]
    return mesh_polygon(pts, H)


def two_blocks(bump, gap=2e-3):
    """Block A (1 x 0.5 m) left of block B, which carries the bump facing A."""
    na, ta = block(-1.0 - gap - BUMP, 0.0, 1.0, 0.5)
    nb, tb = block(0.0, 0.0, 1.0, 0.5, bump=bump)
    nodes = np.r_[na, nb]
    tri = np.r_[ta, tb + len(na)].astype(np.int32)
    body = np.r_[np.zeros(len(ta)), np.ones(len(tb))].astype(np.int32)
    return nodes, tri, body, len(na)


def model(nodes, tri, body):
    m = engine.Model(nodes, tri, body, materials=ICE)
    m.set(dt=1e-8, gravity=False, water=False, mu=0.0, penalty=S)
    m.evaluate()
    return m


def contact_limits(m, nodes, tri, body, mass=None):
    mass = np.array(m.mass) if mass is None else mass
    return _engine.contact_critical_dt(nodes[:, 0].copy(), nodes[:, 1].copy(), mass, tri, S, body)


def smallest_altitude(nodes, tri):
    p = nodes[tri]
    area2 = np.abs((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
                   - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1]))
    edges = np.linalg.norm(p - p[:, [1, 2, 0]], axis=2)
    return (area2 / edges.max(axis=1)).min()


@pytest.fixture(scope="module")
def scenes():
    return {b: two_blocks(b) for b in (False, True)}


def test_the_bump_makes_tiny_elements(scenes):
    nodes, tri, _, _ = scenes[True]
    assert smallest_altitude(nodes, tri) < 0.03 * H


def test_a_tiny_element_does_not_set_the_contact_step_of_the_other_nodes(scenes):
    """The contact limit of block A's nodes (all regular) stays of the order
    of the clean mesh's when B gets the bump: the bump counts over its own
    3 mm, not over A's 0.1 m edges. Measured 0.65 of it: the bump's two 3.4 mm
    edges (l/a' = 1.25 each) and gmsh's graded triangles beside it (an 83 mm
    edge over a 33 mm altitude) put the worst 0.1 m window at ~5 instead of
    ~1.3. With the smallest altitude anywhere (2.7 mm) standing in for the
    other body it was sqrt((1 + 1.3)/(1 + 37)) ~ 0.25 of it."""
    lim = {}
    for b, (nodes, tri, body, na) in scenes.items():
        m = model(nodes, tri, body)
        mass = np.array(m.mass)
        mass[na:] = np.inf        # only A's nodes can govern
        lim[b] = contact_limits(m, nodes, tri, body, mass)["dt"]
    assert lim[True] > 0.5 * lim[False]


def test_a_node_of_the_tiny_element_gets_the_small_limit(scenes):
    """The limit of the whole mesh is set at the bump, by a light node there."""
    nodes, tri, body, na = scenes[True]
    m = model(nodes, tri, body)
    out = contact_limits(m, nodes, tri, body)
    assert out["node"] >= na
    x, y = nodes[out["node"]]
    assert np.hypot(x - (-BUMP), y - 0.25) < 3 * BUMP
    regular = contact_limits(*(lambda n, t, b, _: (model(n, t, b), n, t, b))(*scenes[False]))["dt"]
    assert out["dt"] < 0.5 * regular


@pytest.mark.parametrize("scaled", [False, True])
def test_an_impact_on_the_tiny_element_at_the_bound_conserves_energy(scenes, scaled):
    """A hits the bump face first at 1 m/s and rebounds; the run at 0.9 of the
    stable step (which includes the contact bound) conserves energy through
    the impact on the tiny elements. With selective mass scaling of the bump's
    nodes to the regular mesh's step (what the small scene does) too."""
    nodes, tri, body, na = scenes[True]
    m = model(nodes, tri, body)
    unscaled = m.stable_time_step()["dt"]
    if scaled:
        # to half the clean mesh's step: a few light nodes get mass
        nodes0, tri0, body0, _ = scenes[False]
        m.set(mass_scaling_dt=0.5 * model(nodes0, tri0, body0).stable_time_step()["dt"])
    st = m.stable_time_step()
    if scaled:
        heavier = np.flatnonzero(np.array(m.mass) > np.array(m.mass_phys))
        assert st["dt"] > 5 * unscaled
        assert 0 < len(heavier)
        # the bump's light nodes, and the one-triangle corners of B, whose
        # edges may rest on a junction of two stretches as stiff as the bump's
        assert len(heavier) <= 8
        assert st["added_mass_fraction"] < 0.01   # issue 9's bound for added mass
    dt = st["dt"]                      # 0.9 x the smallest limit
    m.set(dt=dt)
    v = np.zeros((len(nodes), 2))
    v[:na, 0] = 1.0
    m.set_velocities(v)
    mass = np.array(m.mass)
    E0 = 0.5 * mass[:na].sum()
    touched, t, chunk = 0, 0.0, 5e-5
    while t < 0.02 and not (touched and m.touching_pairs == 0):
        n = max(1, int(chunk / dt))
        m.step(n)
        t += n * dt
        touched = max(touched, m.touching_pairs)
        e = m.energies()
        assert np.isfinite(e["kinetic"])
        assert e["kinetic"] + e["elastic"] <= 1.005 * E0   # stored contact energy is >= 0
    assert touched > 0 and m.touching_pairs == 0, "A did not rebound within 20 ms"
    e = m.energies()
    # after separation nothing is stored in contact: kinetic + elastic = E0
    # up to the integration error of the impact (measured 1e-5; an unstable
    # step grows it without bound within a few hundred steps). The bound is
    # conservative on this impact: the tip meets A's flat face, whose overlap
    # grows as depth squared; the run stays stable up to 10x the limit.
    assert e["kinetic"] + e["elastic"] == pytest.approx(E0, rel=5e-3)


# ------------------------------------------------------------ exact stiffness

def _strip_and_block(hb):
    """Block A (0.5 x 0.3 m, square cells h) above strip B (1 m x hb, one row of
    h x hb cells, 1 mm apart): B's top and bottom edges have l = h over
    altitude hb, its ends l = hb over altitude h."""
    h = H
    na, ta = engine.rectangle_mesh(5, 3, h, origin=(0.2, hb + 1e-3))
    nb, tb = engine.rectangle_mesh(10, 1, h, hb, origin=(0.0, 0.0))
    nodes = np.r_[na, nb]
    tri = np.r_[ta, tb + len(na)].astype(np.int32)
    body = np.r_[np.zeros(len(ta)), np.ones(len(tb))].astype(np.int32)
    return nodes, tri, body, len(na)


@pytest.mark.parametrize("hb, k_lo, k_hi", [
    # regular: every edge l = a = h, T = 1: k = 3/2 s x 2 edges x (1 + 1)
    (H, 6.0, 6.0),
    # B flat (a' = h/10 under its 0.1 m edges): T(h) = 10, and an edge over a
    # junction of two such stretches at most 10 x 1.1 (the length grid):
    # k = 3/2 s x 2 x (1 + 10 .. 11)
    (H / 10, 33.0, 36.0),
])
def test_a_corner_node_gets_the_stiffness_of_the_formula(hb, k_lo, k_hi):
    """Block A's lightest node (a corner with one triangle, two boundary edges
    l = a = h) against the other body's stiffest stretch (contact.hpp)."""
    nodes, tri, body, na = _strip_and_block(hb)
    m = model(nodes, tri, body)
    mass = np.array(m.mass)
    mass[na:] = np.inf
    out = contact_limits(m, nodes, tri, body, mass)
    assert out["node"] < na
    assert k_lo * S * (1 - 1e-9) <= out["stiffness"] <= k_hi * S * (1 + 1e-9)


# -------------------------------------------------- mass scaling with viscosity

def test_mass_scaling_of_viscous_tiny_elements_reaches_its_step_and_stays_stable(scenes):
    """With the block viscosity (Table 1's 2.5e4 Pa s) a tiny element's limit
    falls as its size squared; scaling its nodes' mass by
    need (need + 2 tau)/dt0² (time_step.hpp) brings the step to the target,
    and a run at that step keeps its energy bounded (it only decays: the
    viscosity dissipates; measured stable up to 2x that step, the bound taking
    the smallest corner mass ratio). The old rule (need/dt_e)² added ~20x
    more mass."""
    nodes, tri, body, na = scenes[True]
    m = engine.Model(nodes, tri, body, materials=dict(ICE, viscosity=2.5e4))
    m.set(dt=1e-9, gravity=False, water=False, mu=0.0, penalty=5e9)   # the small scene's
    before = m.stable_time_step()
    assert before["governing"] == "element" and before["damping_ratio"] > 1.0
    target = 10 * before["dt"]
    m.set(mass_scaling_dt=target)
    st = m.stable_time_step()
    assert st["dt"] >= target * (1 - 1e-12)
    # less than the rule m (need/dt_e)² would give the governing triangle's
    # corners alone (measured: ~1/20 of it)
    need = target / st["safety"]
    corners = tri[before["element"]]
    old_rule = np.sum(np.array(m.mass_phys)[corners]) * ((need / before["dt_element"]) ** 2 - 1)
    added = np.sum(np.array(m.mass) - np.array(m.mass_phys))
    assert 0 < added < 0.5 * old_rule
    m.set(dt=st["dt"])
    rng = np.random.default_rng(1)
    m.set_velocities(0.01 * rng.standard_normal((len(nodes), 2)))
    m.step(1)
    e0 = m.energies()["kinetic"] + m.energies()["elastic"]
    assert e0 > 0
    for _ in range(40):
        m.step(100)
        e = m.energies()
        assert np.isfinite(e["kinetic"]) and e["kinetic"] + e["elastic"] <= e0
