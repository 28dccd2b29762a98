"""Water on rigid blocks (rigid_dem/water.py, engine rigid/rigid_water.hpp):
floating draft, Archimedes at any angle, a plank's righting moment, drag of
translation and rotation, terminal rise speed, and the FEM-DEM's buoyancy on
the same block."""
import numpy as np
import pytest
from scipy.optimize import brentq

from icerubble import engine
from icerubble.rigid_dem.water import BlockWater, polygon_frame

RHO_I, RHO_W, G = 920.0, 1010.0, 9.81


def rect(w, h):
    return np.array([(-w / 2, -h / 2), (w / 2, -h / 2), (w / 2, h / 2), (-w / 2, h / 2)])


def one(w, params, y_w=0.0, poly=None):
    return BlockWater([rect(*w) if poly is None else poly], dict(params), y_w)


def at(water, cy, theta=0.0, cx=0.0, u=(0.0, 0.0), omega=0.0):
    f = water.forces(np.array([cx]), np.array([cy]), np.array([theta]), np.array([u[0]]),
                     np.array([u[1]]), np.array([omega]))
    return f[0][0], f[1][0], f[2][0]


def test_a_floating_block_rests_at_draft_rho_i_over_rho_w():
    w, h = 1.2, 0.3
    water = one((w, h), dict(drag_model="none"))
    weight = RHO_I * G * w * h
    # centroid height where buoyancy carries the weight
    cy = brentq(lambda y: at(water, y)[1] - weight, -h, h, xtol=1e-14)
    draft = h / 2 - cy
    assert draft / h == pytest.approx(RHO_I / RHO_W, rel=1e-10)


@pytest.mark.parametrize("theta", [0.0, 0.3, 1.0, 2.5, -0.7])
def test_a_submerged_block_gets_archimedes_force_at_its_centroid_at_any_angle(theta):
    poly = np.array([(0, 0), (1.0, 0.1), (1.3, 0.6), (0.2, 0.5)])   # a skew quadrilateral
    area, _, _ = polygon_frame(poly)
    water = one(None, dict(drag_model="none"), poly=poly)
    fx, fy, tz = at(water, cy=-3.0, theta=theta)
    assert fx == 0.0
    assert fy == pytest.approx(RHO_W * G * area, rel=1e-13)
    assert abs(tz) < 1e-10 * fy


def test_a_tilted_plank_is_righted_and_a_tilted_pole_is_not():
    # a plank floats flat: tilting it moves the centre of buoyancy to the low side
    plank = one((1.2, 0.3), dict(drag_model="none"))
    _, _, tz = at(plank, cy=0.15 - 0.3 * RHO_I / RHO_W, theta=0.1)
    assert tz < 0.0  # counter-clockwise tilt, clockwise moment back
    # a tall narrow pole floating upright is unstable: the moment tips it further
    pole = one((0.3, 1.2), dict(drag_model="none"))
    _, _, tz = at(pole, cy=0.6 - 1.2 * RHO_I / RHO_W, theta=0.1)
    assert tz > 0.0


def test_linear_drag_of_a_submerged_block_translating_and_rotating():
    w, h, c_w = 1.2, 0.3, 2.5e4
    water = one((w, h), dict(drag_model="linear", c_w=c_w))
    fx, fy, tz = at(water, cy=-2.0, u=(0.3, -0.1))
    assert fx == pytest.approx(-c_w * 0.3, rel=1e-12)
    assert fy - RHO_W * G * w * h == pytest.approx(c_w * 0.1, rel=1e-9)
    assert abs(tz) < 1e-9
    # rotation: -c_w omega (polar moment per area) = -c_w omega (w² + h²) / 12
    fx, fy, tz = at(water, cy=-2.0, theta=0.4, omega=0.5)
    assert tz == pytest.approx(-c_w * 0.5 * (w * w + h * h) / 12.0, rel=1e-12)
    assert abs(fx) < 1e-9 and fy == pytest.approx(RHO_W * G * w * h, rel=1e-13)


def test_drag_of_a_half_submerged_block_acts_on_its_wet_half_only():
    w, h, c_w = 1.0, 1.0, 1e4
    water = one((w, h), dict(drag_model="linear", c_w=c_w))
    fx, _, tz = at(water, cy=0.0, u=(1.0, 0.0))
    assert fx == pytest.approx(-0.5 * c_w, rel=1e-12)
    # the wet half's centroid is h/4 below: the drag there turns the block
    # about z by -(r x F) with r = (0, -h/4), F = (-c/2, 0): tz = -(h/4)(c/2)
    assert tz == pytest.approx(-0.25 * 0.5 * c_w, rel=1e-12)


@pytest.mark.parametrize("law", ["linear", "quadratic"])
def test_a_submerged_block_rises_at_the_drag_laws_terminal_speed(law):
    w, h = 1.2, 0.3
    params = dict(drag_model=law)
    water = one((w, h), params)
    mass = RHO_I * w * h
    net = (RHO_W - RHO_I) * G * w * h
    # terminal speed from the law: net buoyancy = c_b v
    v_t = net / 2.5e4 if law == "linear" else np.sqrt(2 * net / (RHO_W * 1.0 * w))
    # integrate the rise (deep: no surface in reach); semi-implicit Euler
    y, v, dt = -50.0, 0.0, 1e-3
    for _ in range(int(20.0 / dt)):
        _, fy, _ = at(water, cy=y, u=(0.0, v))
        v += dt * (fy - mass * G) / mass
        y += dt * v
    assert v == pytest.approx(v_t, rel=1e-6)


def test_buoyancy_equals_the_fem_dem_engines_on_the_same_block():
    """The FEM-DEM clips each triangle at the water line; the rigid law clips
    the whole polygon: force and moment about the centroid agree."""
    nodes, tris = engine.rectangle_mesh(12, 3, 0.1, origin=(-0.6, -0.15))
    theta, cy, y_w = 0.35, -0.05, 0.0
    R = np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])
    placed = nodes @ R.T + np.array([0.0, cy])
    m = engine.Model(placed, tris, np.zeros(len(tris), int), dict(E=1e9, nu=0.3, rho=RHO_I))
    m.set(gravity=False, buoyancy=True, drag=False, y_w=y_w, rho_w=RHO_W)
    m.evaluate()
    f = m.forces("buoyancy")
    F = f.sum(axis=0)
    T = np.sum((placed[:, 0] - 0.0) * f[:, 1] - (placed[:, 1] - cy) * f[:, 0])
    water = one((1.2, 0.3), dict(drag_model="none"))
    fx, fy, tz = at(water, cy=cy, theta=theta)
    assert fy == pytest.approx(F[1], rel=1e-12)
    assert tz == pytest.approx(T, rel=1e-10, abs=1e-9 * abs(fy))


def test_bad_blocks_are_refused_with_the_reason():
    with pytest.raises(ValueError, match="needs >= 3 corners"):
        BlockWater([np.zeros((2, 2))], {}, 0.0)
    with pytest.raises(ValueError, match="zero area"):
        BlockWater([np.array([(0, 0), (1, 0), (2, 0)])], {}, 0.0)
    with pytest.raises(ValueError, match="y_w"):
        BlockWater([rect(1, 1)], {}, float("nan"))
    water = one((1, 1), {})
    with pytest.raises(ValueError, match="theta"):
        water.forces(np.zeros(1), np.zeros(1), np.array([np.inf]), np.zeros(1), np.zeros(1), np.zeros(1))
