"""One opened bond point: softening, unloading/reloading, failure (eqs 8-11)."""
import numpy as np
import pytest

from icerubble import cohesive_law as fb

F0, G, L = 1.0e3, 15.0, 0.1          # |f_c^0| [N/m], J/m^2, m
DF = 2 * G * L / F0                  # eq 12: 3 mm
BETA = 5.0
# Forces are compared at 1e-12 relative: each is a handful of flops from exact
# inputs, so round-off is ~1e-15; 1e-12 leaves room without hiding any law error.
RTOL = 1e-12


def radial(d_hat, s):
    """Path delta = s * d_hat as (steps, 1) arrays."""
    s = np.asarray(s, float)[:, None]
    return s * d_hat[0], s * d_hat[1]


def F_of(direction, fn, ft, dn, dt):
    """Scalar |f_c| recovered from the force components (inverts eq 11)."""
    de = fb.effective_opening(dn, dt, BETA)
    if direction == "paper":
        return np.hypot(fn, ft)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(de > 0, (fn * np.maximum(dn, 0) + ft * dt) / de, 0.0)


@pytest.mark.parametrize("direction", fb.DIRECTIONS)
@pytest.mark.parametrize("d_hat", [(1.0, 0.0), (0.0, 1.0), (0.0, -1.0), (0.6, 0.3), (-0.5, 0.2)])
def test_loading_follows_linear_softening(direction, d_hat):
    b = fb.OpenedBondPoints(F0, G, L, BETA, direction)
    s = np.linspace(0, 0.9, 10) * DF / fb.effective_opening(*d_hat, BETA)
    dn, dt = radial(d_hat, s)
    r = b.run_path(dn, dt)
    de = fb.effective_opening(dn, dt, BETA)
    F = F_of(direction, r["f_n"], r["f_t"], dn, dt)
    np.testing.assert_allclose(F[1:], F0 * (1 - de[1:] / DF), rtol=RTOL)
    assert b.delta_m[0] == pytest.approx(de[-1, 0], rel=1e-15)


@pytest.mark.parametrize("direction", fb.DIRECTIONS)
def test_force_direction_eq11_and_work_conjugate(direction):
    dn, dt = 0.3e-3, -0.1e-3
    b = fb.OpenedBondPoints(F0, G, L, BETA, direction)
    r = b.step([dn], [dt])
    de = np.hypot(BETA * dt, dn)
    F = F0 * (1 - de / DF)
    power = 1 if direction == "paper" else 2
    np.testing.assert_allclose([r["f_n"][0], r["f_t"][0]],
                               [F * dn / de, F * BETA**power * dt / de], rtol=RTOL)


def test_closed_crack_carries_no_normal_cohesion():
    # delta_n < 0: Macaulay bracket, the normal pressure is the contact's business
    b = fb.OpenedBondPoints(F0, G, L, BETA, "paper")
    r = b.step([-1e-4], [1e-4])
    assert r["f_n"][0] == 0.0
    assert r["f_t"][0] == pytest.approx(F0 * (1 - BETA * 1e-4 / DF), rel=RTOL)


@pytest.mark.parametrize("direction", fb.DIRECTIONS)
def test_unload_reload_follows_secant_and_rejoins_softening(direction):
    d_hat = np.array([0.8, 0.6]) / fb.effective_opening(0.8, 0.6, BETA)  # delta_e = s
    s = np.r_[np.linspace(0, 0.4, 9), np.linspace(0.35, 0.05, 7), np.linspace(0.1, 0.4, 7),
              np.linspace(0.45, 0.7, 6)] * DF
    dn, dt = radial(d_hat, s)
    b = fb.OpenedBondPoints(F0, G, L, BETA, direction)
    r = b.run_path(dn, dt)
    F = F_of(direction, r["f_n"], r["f_t"], dn, dt)[:, 0]
    dm = 0.4 * DF
    unload = slice(9, 23)                      # below delta_m: secant to the origin
    np.testing.assert_allclose(F[unload], F0 * (1 - dm / DF) * s[unload] / dm, rtol=RTOL)
    assert np.all(r["dissipation"][unload] == 0.0)
    np.testing.assert_allclose(F[23:], F0 * (1 - s[23:] / DF), rtol=RTOL)  # back on the line
    assert b.delta_m[0] == pytest.approx(0.7 * DF, rel=1e-14)


@pytest.mark.parametrize("direction", fb.DIRECTIONS)
def test_no_force_after_full_failure_irreversibly(direction):
    s = np.r_[np.linspace(0, 1.2, 13), np.linspace(1.0, 0.0, 11), np.linspace(0.1, 0.5, 5)] * DF
    dn, dt = radial((0.6, 0.8 / BETA), s)       # delta_e = s
    b = fb.OpenedBondPoints(F0, G, L, BETA, direction)
    r = b.run_path(dn, dt)
    first = np.argmax(r["failed"][:, 0])
    assert r["failed"][:, 0].sum() == 1        # reported once
    assert fb.effective_opening(dn[first], dt[first], BETA) >= DF
    assert fb.effective_opening(dn[first - 1], dt[first - 1], BETA) < DF
    assert np.all(r["f_n"][first:] == 0.0) and np.all(r["f_t"][first:] == 0.0)
    assert b.broken[0]


@pytest.mark.parametrize("dn,dt,mode", [
    (1.0, 0.5, fb.TENSILE), (1.0, -1.0, fb.TENSILE), (0.5, 1.0, fb.SHEAR),
    (0.0, -1.0, fb.SHEAR), (-0.3, 1.0, fb.SHEAR), (1.0, 1.0000001, fb.SHEAR)])
def test_failure_mode_classification(dn, dt, mode):
    # scale the direction so the bond fails in one step
    k = 2 * DF / fb.effective_opening(dn, dt, BETA)
    b = fb.OpenedBondPoints(F0, G, L, BETA)
    r = b.step([k * dn], [k * dt])
    assert r["failed"][0] and b.mode[0] == mode
    assert fb.failure_mode(dn, dt) == mode


def test_cohesive_pair_conserves_momentum_and_resists_opening():
    rng = np.random.default_rng(1)
    ang = rng.uniform(0, 2 * np.pi, 50)
    nx, ny = np.cos(ang), np.sin(ang)
    dx, dy = rng.normal(0, 1e-4, 50), rng.normal(0, 1e-4, 50)
    dn, dt = fb.opening_components(dx, dy, nx, ny)
    np.testing.assert_allclose(np.hypot(dn, dt), np.hypot(dx, dy), rtol=1e-14)
    b = fb.OpenedBondPoints(np.full(50, F0), G, L, BETA)
    r = b.step(dn, dt)
    fpx, fpy, fmx, fmy = fb.nodal_forces(r["f_n"], r["f_t"], nx, ny)
    assert np.all(fpx == -fmx) and np.all(fpy == -fmy)        # f+ = -f-
    opening = dn > 0
    # the force on node + pulls it back towards node - (f+ . delta < 0)
    assert np.all((fpx * dx + fpy * dy)[opening | (dt != 0)] < 0)


def test_eq8_keeps_node_accelerations_continuous():
    # The cohesive force g on x+ (and -g on x-) that keeps a+ = a- = a (the unsplit
    # node's acceleration) is g = -(m-/m) f+ + (m+/m) f-; its magnitude is eq 8.
    rng = np.random.default_rng(2)
    mp, mm = rng.uniform(1, 10, 20), rng.uniform(1, 10, 20)
    fp, fm = rng.normal(size=(20, 2)), rng.normal(size=(20, 2))
    mag = fb.initial_force_magnitude(mp, mm, fp, fm)
    a = (fp + fm) / (mp + mm)[:, None]
    g = (-(mm[:, None]) * fp + mp[:, None] * fm) / (mp + mm)[:, None]
    np.testing.assert_allclose((fp + g) / mp[:, None], a, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose((fm - g) / mm[:, None], a, rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(mag, np.hypot(g[:, 0], g[:, 1]), rtol=1e-14)


@pytest.mark.parametrize("direction", fb.DIRECTIONS)
def test_first_force_equals_split_force_in_pure_shear(direction):
    # with initial_effective_force the first cohesive force equals the split force
    f_split = 4.0e3
    f0 = fb.initial_effective_force(0.0, f_split, BETA, direction)
    b = fb.OpenedBondPoints(f0, G, L, BETA, direction)
    r = b.step([0.0], [1e-12])
    # a 1e-12 m opening moves the force by F0*beta*1e-12/delta_f ~ 1e-8 relative
    assert r["f_t"][0] == pytest.approx(f_split, rel=1e-7)
