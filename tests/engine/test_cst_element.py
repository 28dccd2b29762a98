"""The CST element: patch test and objectivity (docs/model.md §3.1).

Analytic reference: St Venant-Kirchhoff in plane strain, E_G = (F^T F - I)/2,
S = lambda tr(E_G) I + 2 mu E_G, Cauchy sigma = F S F^T / det F.
"""
import numpy as np
import pytest

from icerubble import engine

E, NU, RHO = 1e9, 0.3, 900.0
LAM = E * NU / ((1 + NU) * (1 - 2 * NU))
MU = E / (2 * (1 + NU))


def svk_cauchy(F):
    Eg = 0.5 * (F.T @ F - np.eye(2))
    S = LAM * np.trace(Eg) * np.eye(2) + 2 * MU * Eg
    sig = F @ S @ F.T / np.linalg.det(F)
    return np.array([sig[0, 0], sig[1, 1], sig[0, 1]]), F @ S, Eg, S


def rotation(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s], [s, c]])


def distorted_block(nx=5, ny=4, h=0.2, seed=3):
    """A block whose interior nodes are moved randomly by up to 0.25 h, so the
    patch test is not passed by symmetry of a regular mesh."""
    nodes, tri = engine.rectangle_mesh(nx, ny, h)
    rng = np.random.default_rng(seed)
    i = np.arange(len(nodes)) % (nx + 1)
    j = np.arange(len(nodes)) // (nx + 1)
    interior = (i > 0) & (i < nx) & (j > 0) & (j < ny)
    nodes[interior] += rng.uniform(-0.25, 0.25, (interior.sum(), 2)) * h
    return nodes, tri, interior, i, j


def make(nodes, tri, **mat):
    return engine.Model(nodes, tri, np.zeros(len(tri), int),
                      dict(dict(E=E, nu=NU, rho=RHO), **mat))


def test_patch_uniform_strain_gives_exact_uniform_stress_and_balanced_interior_nodes():
    nodes, tri, interior, i, j = distorted_block()
    F = np.array([[1.002, 0.0007], [-0.0004, 0.9985]])
    m = make(nodes, tri)
    m.set(gravity=False)
    m.set_positions(nodes @ F.T + np.array([0.3, -0.1]))
    m.evaluate()
    sig, P, Eg, S = svk_cauchy(F)
    smax = np.abs(sig).max()
    # Every triangle carries the same F, so the stress is exact up to
    # round-off of F (relative 1e-15 on strains of 1e-3): 1e-9 relative.
    np.testing.assert_allclose(m.stress, np.tile(sig, (len(tri), 1)), rtol=0, atol=1e-9 * smax)
    f = m.forces("internal")
    # Interior nodes: equilibrium under uniform stress, force sums cancel to
    # round-off of corner forces of size |sigma| h.
    assert np.abs(f[interior]).max() < 1e-9 * smax * 0.2
    # The right edge carries the first Piola-Kirchhoff traction P N over its
    # reference length (0.8 m); internal forces are minus that.
    right = i == i.max()
    np.testing.assert_allclose(f[right].sum(axis=0), -P[:, 0] * 0.8, rtol=1e-9)
    # Strain energy density W = lambda/2 tr(E)² + mu E:E over the block area.
    W = 0.5 * LAM * np.trace(Eg) ** 2 + MU * np.sum(Eg * Eg)
    assert m.energies()["elastic"] == pytest.approx(W * 1.0 * 0.8, rel=1e-9)


@pytest.mark.parametrize("degrees", [90.0, 180.0, 37.0, -123.0])
def test_rigid_rotation_gives_zero_stress_and_zero_elastic_energy(degrees):
    nodes, tri, *_ = distorted_block()
    m = make(nodes, tri)
    m.set(gravity=False)
    m.set_positions(nodes @ rotation(np.radians(degrees)).T + np.array([5.0, -2.0]))
    m.evaluate()
    # Only round-off of cos² + sin² = 1 remains: strain ~1e-15, so stress
    # below 1e-12 E. (A small-strain CST would give strains of order 1 here.)
    assert np.abs(m.stress).max() < 1e-12 * E
    assert m.energies()["elastic"] < 1e-24 * E
    assert np.abs(m.forces("internal")).max() < 1e-12 * E * 0.2


def test_stress_rotates_with_the_body():
    """Objectivity: rotating a stretched patch rotates its Cauchy stress."""
    nodes, tri, *_ = distorted_block()
    U = np.array([[1.003, 0.001], [0.001, 0.999]])
    R = rotation(np.radians(130.0))
    m = make(nodes, tri)
    m.set_positions(nodes @ (R @ U).T)
    m.evaluate()
    s0, *_ = svk_cauchy(U)
    s = np.array([[s0[0], s0[2]], [s0[2], s0[1]]])
    sr = R @ s @ R.T
    np.testing.assert_allclose(m.stress, np.tile([sr[0, 0], sr[1, 1], sr[0, 1]], (len(tri), 1)),
                               rtol=0, atol=1e-9 * np.abs(s0).max())


def test_spinning_block_stays_unstressed_through_half_a_turn():
    """A free block spun at omega for half a turn: only centrifugal stress.

    A spinning disc has peak stress (3+nu)/8 rho w² R²; the block starts
    unstressed, so it oscillates about that with at most twice the static
    value. Bound: 2 rho w² R² with R the half diagonal. A non-objective
    element would reach ~E (1 - cos 180°) = 2e9 Pa here.
    """
    n, h = 8, 0.125
    nodes, tri = engine.rectangle_mesh(n, n, h, origin=(-0.5, -0.5))
    m = make(nodes, tri)
    w = 2.0
    dt = 0.9 * m.stable_time_step()["dt"]
    m.set(gravity=False, dt=dt)
    v = w * np.column_stack((-nodes[:, 1], nodes[:, 0]))
    m.set_velocities(v)
    ke0 = 0.5 * np.sum(m.mass[:, None] * v**2)
    steps = int(round(np.pi / w / dt))
    m.step(steps)
    bound = 2 * RHO * w**2 * 0.5
    assert np.abs(m.stress).max() < bound
    # Half a turn: node (0.5, 0.5) is now near (-0.5, -0.5); the angle
    # error is at most w*dt/2 from rounding the step count (plus O(dt²)).
    corner = np.argmin(np.hypot(nodes[:, 0] - 0.5, nodes[:, 1] - 0.5))
    ang = np.arctan2(m.y[corner], m.x[corner]) - np.pi / 4
    err = (ang - (w * m.time)) % (2 * np.pi)
    assert min(err, 2 * np.pi - err) < w * dt + 1e-4
    e = m.energies()
    # Undamped and force free: kinetic + elastic energy is conserved; the
    # balance residual of the midpoint rule is O(dt²): 1e-6 of KE.
    assert abs(e["residual"]) < 1e-6 * ke0
    assert e["kinetic"] == pytest.approx(ke0, rel=1e-3)
