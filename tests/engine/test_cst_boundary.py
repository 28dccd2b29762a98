"""Boundary conditions: fixed nodes, prescribed velocity histories, reactions."""
import numpy as np
import pytest

from icerubble import engine

RHO, G = 920.0, 9.81


def block(nx=6, ny=3, h=0.2, **mat):
    nodes, tri = engine.rectangle_mesh(nx, ny, h)
    m = engine.Model(nodes, tri, np.zeros(len(tri), int),
                   dict(dict(E=1e8, nu=0.3, rho=RHO), **mat))
    return m, nodes


def test_reaction_of_a_fixed_base_carries_the_weight_at_rest():
    """A 1.2 x 0.6 m block on a fixed base, settled with strain-rate damping:
    the base pushes up with the weight rho g A and no net horizontal force.
    At rest the reaction is static; 1e-6 relative covers the decayed
    vibration: the vertical mode (w ~ pi c/(2H) ~ 900 rad/s) is damped at
    ratio w*damping/2 ~ 0.9 over ~13 periods, the lower rocking modes at
    ~0.4 over ~6: amplitudes below e^-14."""
    m, nodes = block(damping=2e-3)
    base = np.flatnonzero(nodes[:, 1] == 0.0)
    m.add_node_set("base", base)
    m.fix("base")
    m.set(dt=0.9 * m.stable_time_step()["dt"])
    m.step(4000)
    R = m.reaction("base")
    W = RHO * G * 1.2 * 0.6
    assert R[1] == pytest.approx(W, rel=1e-6)
    assert abs(R[0]) < 1e-6 * W
    assert np.all(m.velocities[base] == 0.0)


def test_smooth_ramp_drives_nodes_at_the_prescribed_velocity_and_displacement():
    """v = v_f (t/T - sin(2 pi t/T)/(2 pi)) up to T, then v_f. The node moves
    by the integral, v_f (t²/(2T) + T (cos(2 pi t/T) - 1)/(4 pi²)) before T;
    the central difference samples v at half steps (midpoint rule), so the
    displacement error is O(dt² v'') ~ 1e-12 m: tolerance 1e-9 m."""
    m, nodes = block()
    top = np.flatnonzero(nodes[:, 1] == nodes[:, 1].max())
    m.add_node_set("indenter", top)
    vf, T = 0.1, 0.02
    m.prescribe_velocity("indenter", direction=(0, -2), v_final=vf, ramp_time=T)
    m.set(gravity=False, dt=1e-5)
    m.step(1000)  # t = 0.01 = T/2
    t = m.time
    s = vf * (t / T - np.sin(2 * np.pi * t / T) / (2 * np.pi))
    ds = vf * (t**2 / (2 * T) + T * (np.cos(2 * np.pi * t / T) - 1) / (4 * np.pi**2))
    # velocity at t - dt/2 (the last half step)
    th = t - 0.5e-5
    sh = vf * (th / T - np.sin(2 * np.pi * th / T) / (2 * np.pi))
    np.testing.assert_allclose(m.velocities[top], np.tile([0.0, -sh], (len(top), 1)), rtol=1e-12)
    np.testing.assert_allclose(m.displacements[top, 1], -ds, atol=1e-9)
    np.testing.assert_allclose(m.displacements[top, 0], 0.0, atol=1e-15)
    m.step(2000)  # past the ramp: constant v_f
    np.testing.assert_allclose(m.velocities[top, 1], -vf, rtol=1e-14)
    assert s > 0


def test_table_history_is_piecewise_linear_and_held_after_the_end():
    m, nodes = block()
    left = np.flatnonzero(nodes[:, 0] == 0.0)
    m.add_node_set("left", left)
    m.prescribe_velocity("left", direction=(1, 0), table=([0.0, 1e-3, 2e-3], [0.0, 0.5, -0.25]), y=False)
    m.set(gravity=False, dt=1e-5)
    m.step(150)  # last half step at t = 1.495e-3: between 0.5 and -0.25
    expect = 0.5 + (1.495e-3 - 1e-3) / 1e-3 * (-0.75)
    np.testing.assert_allclose(m.velocities[left, 0], expect, rtol=1e-9)
    m.step(100)
    np.testing.assert_allclose(m.velocities[left, 0], -0.25, rtol=1e-14)
    # y is free: the nodes moved vertically only through the block's response
    assert np.any(m.velocities[left, 1] != 0.0)


def test_reaction_balances_momentum_of_a_driven_block():
    """Momentum balance: the only external force on a weightless block in
    vacuum is the boundary's, so sum of reaction over time equals the change
    of momentum (exact for the central difference up to round-off)."""
    m, nodes = block()
    left = np.flatnonzero(nodes[:, 0] == 0.0)
    m.add_node_set("left", left)
    m.prescribe_velocity("left", direction=(1, 0.3), v_final=0.2, ramp_time=5e-3)
    m.set(gravity=False, dt=1e-5)
    impulse = np.zeros(2)
    for _ in range(300):
        m.step(1)
        impulse += m.reaction("left") * 1e-5
    p = (m.mass[:, None] * m.velocities).sum(axis=0)
    np.testing.assert_allclose(impulse, p, rtol=1e-9, atol=1e-12)
