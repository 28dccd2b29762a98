"""Buoyancy, water drag and floating (docs/model.md §3.4)."""
import numpy as np
import pytest

from icerubble import engine

from icerubble.parameters import GRAVITY as G, RHO_I, RHO_W


def block(nx, ny, h, origin=(0.0, 0.0), **mat):
    nodes, tri = engine.rectangle_mesh(nx, ny, h, origin=origin)
    m = engine.Model(nodes, tri, np.zeros(len(tri), int),
                   dict(dict(E=1e8, nu=0.3, rho=RHO_I), **mat))
    return m, nodes, tri


def clip_below(poly, y_w):
    """Part of a convex polygon below y = y_w (Sutherland-Hodgman, one plane)."""
    out = []
    for p, q in zip(poly, np.roll(poly, -1, axis=0)):
        if p[1] < y_w:
            out.append(p)
        if (p[1] < y_w) != (q[1] < y_w):
            s = (y_w - p[1]) / (q[1] - p[1])
            out.append(p + s * (q - p))
    return np.array(out)


def area_centroid(poly):
    x, y = poly[:, 0], poly[:, 1]
    c = x * np.roll(y, -1) - np.roll(x, -1) * y
    a = 0.5 * c.sum()
    return a, np.array([((x + np.roll(x, -1)) * c).sum(), ((y + np.roll(y, -1)) * c).sum()]) / (6 * a)


def test_buoyancy_force_and_moment_of_a_tilted_block_are_exact():
    """Force rho_w g A_sub and its line of action through the centroid of the
    submerged part, for a tilted block cut by the water line through its
    triangles (Archimedes). Per-triangle clipping with the submerged centroid
    shared barycentrically is exact, so only round-off remains: 1e-12."""
    m, nodes, _ = block(5, 2, 0.2, origin=(-0.5, -0.2))
    th = np.radians(30.0)
    R = np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
    shift = np.array([0.3, 0.05])
    m.set_positions(nodes @ R.T + shift)
    m.set(gravity=False, buoyancy=True, y_w=0.0, rho_w=RHO_W)
    m.evaluate()
    corners = np.array([[-0.5, -0.2], [0.5, -0.2], [0.5, 0.2], [-0.5, 0.2]]) @ R.T + shift
    a_sub, c = area_centroid(clip_below(corners, 0.0))
    fb = m.forces("buoyancy")
    x = m.positions
    assert 0.05 < a_sub < 0.35  # really partly submerged
    assert fb[:, 1].sum() == pytest.approx(RHO_W * G * a_sub, rel=1e-12)
    assert np.sum(x[:, 0] * fb[:, 1]) == pytest.approx(RHO_W * G * a_sub * c[0], rel=1e-12)


def test_drag_on_a_rigidly_translating_submerged_block_is_minus_c_w_v():
    """docs/model.md §3.4: with c_w in Pa s the drag per unit width is -c_w v; the
    block then slows as v0 exp(-c_w t / (rho A)). The explicit drag gives
    (1 - dt k/m)^n, which differs from the exponential by n (dt k/m)²/2 =
    1e-4 here, so 1e-3."""
    c_w = 500.0
    m, nodes, _ = block(4, 2, 0.25)
    m.set(gravity=False, drag=True, drag_model="linear", buoyancy=False, y_w=10.0, c_w=c_w)
    v0 = np.array([1.0, -0.5])
    m.set_velocities(np.tile(v0, (len(nodes), 1)))
    m.evaluate()
    np.testing.assert_allclose(m.forces("total").sum(axis=0), -c_w * v0, rtol=1e-12)
    mass = RHO_I * 1.0 * 0.5
    dt = 2e-4
    m.set(dt=dt)
    m.step(2000)
    v = m.velocities
    np.testing.assert_allclose(v, np.tile(v0 * np.exp(-c_w * m.time / mass), (len(nodes), 1)), rtol=1e-3)
    e = m.energies()
    # All kinetic energy lost went into drag (round-off level residual).
    assert e["drag"] == pytest.approx(0.5 * mass * (v0 @ v0) - e["kinetic"], rel=1e-6)


def test_drag_scales_with_submerged_fraction():
    m, nodes, _ = block(4, 4, 0.25, origin=(0.0, -0.3))  # 1 x 1 block, 0.3 m below water
    m.set(gravity=False, drag=True, drag_model="linear", y_w=0.0, c_w=1000.0)
    m.set_velocities(np.tile([0.0, 2.0], (len(nodes), 1)))
    m.evaluate()
    # The water line cuts through triangles: 30 % submerged, 1e-12 round-off.
    assert m.forces("total")[:, 1].sum() == pytest.approx(-1000.0 * 2.0 * 0.3, rel=1e-12)


def test_floating_block_settles_at_its_draft():
    """A 2 m x 0.5 m block released with its bottom at the water line floats
    at draft (rho_i/rho_w) t = 0.4554 m (Archimedes; the elastic shortening
    under its own weight, rho g t/E ~ 5e-5, is below the tolerance).

    Heave: w = sqrt(rho_w g/(rho_i t)) = 4.6 rad/s; c_w = 8e3 Pa s damps it at
    about the critical ratio, so 8 s leave exp(-w*8) ~ 1e-16 of the initial
    offset; the 1e-4 m tolerance covers round-off and the slow roll mode.
    The water line lies inside a row of triangles, so partial submersion is
    exercised."""
    t = 0.5
    m, nodes, _ = block(8, 2, 0.25, origin=(-1.0, 0.0))
    m.set(gravity=True, buoyancy=True, drag=True, drag_model="linear", y_w=0.0, rho_w=RHO_W, c_w=8e3)
    m.set(dt=0.9 * m.stable_time_step()["dt"])
    m.step(int(8.0 / m.params["dt"]))
    bottom = m.y[nodes[:, 1] == 0.0].mean()
    assert -bottom == pytest.approx(RHO_I / RHO_W * t, abs=1e-4)
    assert np.abs(m.velocities).max() < 1e-4
    e = m.energies()
    # Energy: gravity and buoyancy work went into drag (and the small
    # elastic energy); residual second order in dt.
    assert abs(e["residual"]) < 1e-3 * abs(e["work_gravity"])


def test_local_damping_brings_a_floating_block_to_rest_at_its_draft():
    """The same block with drag off: undamped it heaves for ever (it dives to
    ~2.8 m: once fully submerged only 0.1 g pushes it back; period ~5 s, so
    it is watched from 15 s to 20 s); with local (Cundall) damping 0.7, used to
    settle scenes, it comes to rest at the same draft - local damping does no
    work at rest, so the equilibrium is Archimedes' - and its work is booked
    as damping: the balance still closes (residual second order in dt)."""
    t = 0.5
    ends = {}
    for alpha in (0.0, 0.7):
        m, nodes, _ = block(8, 2, 0.25, origin=(-1.0, 0.0))
        m.set(gravity=True, buoyancy=True, drag=False, y_w=0.0, rho_w=RHO_W, local_damping=alpha)
        m.set(dt=0.9 * m.stable_time_step()["dt"])
        m.step(int(15.0 / m.params["dt"]))
        lows = []
        for _ in range(100):
            m.step(int(0.05 / m.params["dt"]))
            lows.append(m.y[nodes[:, 1] == 0.0].mean())
        ends[alpha] = (np.min(lows), np.max(lows), m.energies())
    lo, hi, _ = ends[0.0]
    assert hi - lo > 1.0  # still heaving by metres without damping
    lo, hi, e = ends[0.7]
    assert -lo == pytest.approx(RHO_I / RHO_W * t, abs=1e-4)
    assert hi - lo < 1e-4
    assert e["damping"] > 0.9 * e["work_gravity"] + e["work_buoyancy"] - 1e-9 * abs(e["work_gravity"])
    assert abs(e["residual"]) < 1e-3 * abs(e["work_gravity"])
