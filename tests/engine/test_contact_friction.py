"""Coulomb friction of the contact module on a single step (paper eq 4, docs/model.md §3.2).

One contactor triangle pressed onto a target triangle; a tangential load is added
to the assembled forces and apply_friction must either stop the tangential
relative velocity at the contact point exactly (stick, |f_t| <= mu |f_n|) or
apply mu |f_n| against the end-of-step slip (slip). Integrated behaviour (blocks
on slopes) is in test_contact_integrated.py.
"""
import numpy as np
import pytest

from icerubble import _engine

S = 2e11
DT = 1e-6
MU = 0.3


def scene(target_mass, d=1e-6, tilt=0.0):
    """Contactor (nodes 0-2, body 0) pressed a depth d into the top edge of the
    target (nodes 3-5, body 1); the whole scene rotated by `tilt`."""
    pts = np.array([[-0.5, -d], [0.5, -d], [0.1, 0.5], [-1.0, 0.0], [0.0, -1.0], [1.0, 0.0]])
    c, s = np.cos(tilt), np.sin(tilt)
    pts = pts @ np.array([[c, s], [-s, c]])
    tri = np.array([[0, 1, 2], [3, 4, 5]], dtype=np.int32)
    body = np.array([0, 1], dtype=np.int32)
    mass = np.array([1.0, 2.0, 1.5] + [target_mass] * 3)
    return pts, tri, body, mass


def step(pts, tri, body, mass, v, load, mu=MU, constrained=None, vbc=None):
    """Normal pass, add `load` (6x2) to the assembled forces, then friction."""
    n = len(pts)
    solver = _engine.ContactSolver()
    fx, fy = np.zeros(n), np.zeros(n)
    args = (pts[:, 0].copy(), pts[:, 1].copy(), v[:, 0].copy(), v[:, 1].copy(), mass, tri, body,
            np.arange(len(tri), dtype=np.int32))
    assert solver.compute_normal(*args, fx, fy, penalty=S, mu=mu, dt=DT) == 1
    fx += load[:, 0]
    fy += load[:, 1]
    f_before = np.c_[fx, fy].copy()
    kw = {}
    if constrained is not None:
        kw = dict(constrained=constrained, v_bc_x=vbc[:, 0].copy(), v_bc_y=vbc[:, 1].copy())
    power = solver.apply_friction(*args, fx, fy, penalty=S, mu=mu, dt=DT, **kw)
    pairs = solver.pairs
    return np.c_[fx, fy] - f_before, f_before, power, pairs


def slip_velocity(pairs, pts, tri, mass, v, f):
    """Tangential relative velocity at the contact point at the end of the step."""
    inv_m = np.where(mass > 0, 1.0 / np.where(mass > 0, mass, 1.0), 0.0)
    w = v + DT * f * inv_m[:, None]
    r = _engine.contact_pair(pts[tri[0]], pts[tri[1]], S)
    u = np.asarray(r["nc"]) @ w[tri[0]] - np.asarray(r["nt"]) @ w[tri[1]]
    n = pairs["normal"][0]
    return u @ np.array([-n[1], n[0]])


@pytest.mark.parametrize("tilt", [0.0, 0.4])
def test_stick_below_the_friction_limit_stops_sliding_exactly(tilt):
    pts, tri, body, mass = scene(target_mass=0.0, tilt=tilt)  # immovable target
    v = np.zeros((6, 2))
    v[:3] = 1e-4 * np.array([np.cos(tilt), np.sin(tilt)])  # already sliding slowly
    _, f0, _, pairs0 = step(pts, tri, body, mass, v, np.zeros((6, 2)), mu=0.0)
    fn = pairs0["fn"][0]
    t = np.array([np.cos(tilt), np.sin(tilt)])
    # Load = 0.6 of the friction limit, and the slow sliding is stopped within the
    # step too: with these masses this needs < mu fn in total (checked below).
    load = np.zeros((6, 2))
    load[:3] = 0.6 * MU * fn / 3 * t
    df, f, power, pairs = step(pts, tri, body, mass, v, load)
    ft = df[:3].sum(0)
    assert np.linalg.norm(ft) <= MU * fn * (1 + 1e-12)
    assert np.linalg.norm(ft) < 0.999 * MU * fn  # really in the stick state
    # Stick: the end-of-step tangential slip is zero up to round-off of
    # velocities of size 1e-4 m/s (1e-15 m/s is ~10 ulp of them).
    assert abs(slip_velocity(pairs, pts, tri, mass, v, f + df)) < 1e-15
    assert power == pytest.approx(0.0, abs=1e-12 * MU * fn * 1e-4)


def test_slip_above_the_limit_applies_mu_fn_against_the_slip():
    pts, tri, body, mass = scene(target_mass=0.0)
    v = np.zeros((6, 2))
    _, _, _, pairs0 = step(pts, tri, body, mass, v, np.zeros((6, 2)), mu=0.0)
    fn = pairs0["fn"][0]
    load = np.zeros((6, 2))
    load[:3, 0] = 30.0 * MU * fn / 3  # thirty times the limit, along +x
    df, f, power, pairs = step(pts, tri, body, mass, v, load)
    # The free nodes of a lone triangle also slide apart under the nodal normal
    # forces, so take the slip direction from the end-of-step velocities.
    tangent = np.array([-pairs["normal"][0][1], pairs["normal"][0][0]])  # (-1, 0) here
    w0 = slip_velocity(pairs, pts, tri, mass, v, f) * tangent[0]  # along +x
    assert w0 > 0
    ft = df[:3].sum(0)
    # Eq 4: magnitude mu |f_c| (round-off), tangential, against the slip.
    assert np.linalg.norm(ft) == pytest.approx(MU * fn, rel=1e-12)
    assert ft[0] == pytest.approx(-MU * fn, rel=1e-12)
    w = slip_velocity(pairs, pts, tri, mass, v, f + df) * tangent[0]
    assert 0 < w < w0  # still sliding forward, slower
    # Dissipation: the friction force times the sliding velocity it acts against.
    assert power == pytest.approx(MU * fn * w, rel=1e-9)


def test_friction_between_movable_triangles_conserves_momentum():
    pts, tri, body, mass = scene(target_mass=3.0, tilt=0.3)
    rng = np.random.default_rng(0)
    v = rng.normal(0, 0.01, (6, 2))
    for scale in (0.2, 5.0):  # stick and slip
        load = rng.normal(0, 1, (6, 2))
        _, _, _, pairs0 = step(pts, tri, body, mass, v, np.zeros((6, 2)), mu=0.0)
        load *= scale * MU * pairs0["fn"][0] / np.abs(load).sum()
        df, _, power, _ = step(pts, tri, body, mass, v, load)
        size = np.abs(df).max()
        assert size > 0
        # Equal and opposite at a common point: zero resultant and moment
        # (round-off of a few terms of size `size`; lever arms ~1 m).
        assert np.all(np.abs(df.sum(0)) <= 1e-13 * size)
        assert abs(np.sum(pts[:, 0] * df[:, 1] - pts[:, 1] * df[:, 0])) <= 1e-13 * size
        # Dissipation >= 0; in stick it is 0 up to round-off of velocities of
        # size |v| ~ 0.03 m/s times the force (1e-13 relative).
        assert power >= -1e-13 * MU * pairs0["fn"][0] * np.abs(v).max()


def test_prescribed_target_moves_the_contactor_along_in_stick():
    # The target (a conveyor) is driven at 1 mm/s along x; the contactor at
    # rest must be dragged to the belt speed when mu fn allows it.
    pts, tri, body, mass = scene(target_mass=5.0)
    v = np.zeros((6, 2))
    vbc = np.zeros((6, 2))
    vbc[3:, 0] = 1e-3
    cons = np.array([0, 0, 0, 3, 3, 3], dtype=np.uint8)
    v[3:] = vbc[3:]
    _, _, _, pairs0 = step(pts, tri, body, mass, v, np.zeros((6, 2)), mu=0.0)
    fn = pairs0["fn"][0]
    # Accelerating 4.5 kg of contactor to 1 mm/s within one step needs
    # 4.5 kN per m for dt = 1e-6 s; choose mu so that this is within the cone.
    mu = 2.0 * 4.5e-3 / DT / fn
    df, f, _, pairs = step(pts, tri, body, mass, v, np.zeros((6, 2)), mu=mu,
                           constrained=cons, vbc=vbc)
    inv_m = 1.0 / mass[:3]
    w = v[:3] + DT * (f + df)[:3] * inv_m[:, None]
    r = _engine.contact_pair(pts[tri[0]], pts[tri[1]], S)
    u = np.asarray(r["nc"]) @ w
    # The contact point of the contactor moves with the belt (round-off).
    assert u[0] == pytest.approx(1e-3, rel=1e-9)


def test_no_friction_without_mu():
    pts, tri, body, mass = scene(target_mass=0.0)
    load = np.zeros((6, 2))
    load[:3, 0] = 10.0
    df, _, power, _ = step(pts, tri, body, mass, np.zeros((6, 2)), load, mu=0.0)
    assert np.all(df == 0.0) and power == 0.0
