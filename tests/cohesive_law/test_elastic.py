"""Initially elastic freeze bond (rigid-block model): peak on the criterion, elastic
unloading, softening with the same G (docs/cohesive_law.md, 'Initially elastic bond').

Paths are radial, delta = s * d_hat, with grids that contain the analytic peak and
delta_f, so the trapezoid rule on the (piecewise linear) forces is exact and the
tolerance 1e-12 covers round-off only. The peak is located inside a step by bisection
to 2^-64 of the step, so t_e at the peak equals sigma_cr to round-off (1e-12).
"""
import numpy as np
import pytest

from icerubble import cohesive_law as fb

trapezoid = getattr(np, "trapezoid", None) or np.trapz  # numpy 2 renamed trapz

SIGMA, TAU, MU, G, L = 10e3, 50e3, 0.3, 15.0, 0.1
BETA = TAU / SIGMA
K = 1e8          # Pa: elastic opening at a tensile peak sigma l / k = 10 um << delta_f = 3 mm
GL = G * L
RTOL = 1e-12


def bonds(direction, n=1, k=K, mu=MU):
    return fb.ElasticBondPoints(np.full(n, k), L, SIGMA, TAU, mu, G, direction)


def unit_effective(d):
    d = np.asarray(d, float)
    return d / fb.effective_opening(d[0], d[1], BETA)


def peak_opening(direction, d_hat):
    """Analytic s at the peak on the tensile side along delta = s * d_hat (|d_hat|_e = 1)."""
    if direction == "work_conjugate":   # t_e = k delta_e / l
        return SIGMA * L / K
    return SIGMA * L / (K * np.hypot(*d_hat))   # paper: t_e = k |delta| / l


def path_grid(s0, sf):
    return np.r_[np.linspace(0, s0, 41), np.linspace(s0, sf, 2001)[1:], sf * (1 + np.arange(1, 4) / 100)]


def work(s, d_hat, r):
    f = r["f_n"][:, 0] * d_hat[0] + r["f_t"][:, 0] * d_hat[1]
    return trapezoid(f, s)


@pytest.mark.parametrize("direction", fb.DIRECTIONS)
@pytest.mark.parametrize("d", [(1, 0), (0, 1), (0, -1), (0.8, 0.3), (0.3, -0.8)])
def test_monotonic_opening_peak_on_criterion_and_energy(direction, d):
    d_hat = unit_effective(d)
    s0 = peak_opening(direction, d_hat)
    Fp = K * s0                       # effective force at the peak (F = k delta_e)
    sf = 2 * GL / Fp                  # eq 12 with the peak force
    assert s0 < sf
    s = path_grid(s0, sf)
    b = bonds(direction)
    r = b.run_path(s[:, None] * d_hat[0], s[:, None] * d_hat[1])
    # peak on the criterion (eq 5) and at the analytic opening
    t_e = fb.effective_traction(b.peak_f_n / L, b.peak_f_t / L, SIGMA, TAU, MU)
    assert t_e[0] == pytest.approx(SIGMA, rel=RTOL)
    assert b.delta_0[0] == pytest.approx(s0, rel=1e-9)   # kink within round-off of a node
    # documented energy: the effective work (and the dissipation) is G l
    assert r["dissipation"].sum() == pytest.approx(GL, rel=RTOL)
    power = 1 if direction == "paper" else 2
    factor = 1.0 if direction == "work_conjugate" else d_hat[0] ** 2 + BETA * d_hat[1] ** 2
    # mechanical work: G l (work-conjugate), G l (b^2 + beta a^2) for the paper's eq 11,
    # i.e. G l in tension and G l / beta in pure shear, exactly as the initially rigid law
    assert work(s, d_hat, r) == pytest.approx(GL * factor, rel=RTOL)
    assert b.state[0] == 2 and r["failed"].sum() == 1
    # elastic branch: f_n = k delta_n, f_t = k beta^power delta_t
    pre = s < s0 * (1 - 1e-9)
    np.testing.assert_allclose(r["f_n"][pre, 0], K * s[pre] * d_hat[0], rtol=RTOL, atol=1e-9)
    np.testing.assert_allclose(r["f_t"][pre, 0], K * BETA**power * s[pre] * d_hat[1], rtol=RTOL, atol=1e-9)
    # no force anywhere exceeds the peak force (the peak is the maximum)
    fmag = np.hypot(r["f_n"], r["f_t"])[:, 0]
    assert fmag.max() <= np.hypot(b.peak_f_n[0], b.peak_f_t[0]) * (1 + RTOL)


@pytest.mark.parametrize("direction", fb.DIRECTIONS)
def test_peak_located_inside_coarse_steps(direction):
    """Many directions at once, 30 coarse steps: the peak still lies on eq 5 exactly,
    including compression-shear directions (|t_t| = tau + mu |t_n|)."""
    ang = np.linspace(-0.9 * np.pi, 0.9 * np.pi, 37)
    ang = ang[np.abs(np.abs(ang) - np.pi / 2) > 1e-3]
    d_n, d_t = np.cos(ang), np.sin(ang)
    # skip compressive directions that never reach the criterion (friction wins)
    kt = K * BETA ** (1 if direction == "paper" else 2)
    ok = (d_n >= 0) | (kt * np.abs(d_t) > MU * K * np.abs(d_n) * 1.5)
    d_n, d_t = d_n[ok], d_t[ok]
    n = d_n.size
    b = bonds(direction, n)
    s = np.linspace(0, 3e-4, 31)[:, None]
    r = b.run_path(s * d_n, s * d_t)
    assert np.all(b.state >= 1)
    t_n, t_t = b.peak_f_n / L, b.peak_f_t / L
    np.testing.assert_allclose(fb.effective_traction(t_n, t_t, SIGMA, TAU, MU), SIGMA, rtol=RTOL)
    comp = t_n < 0
    assert comp.any()
    np.testing.assert_allclose(np.abs(t_t[comp]), TAU + MU * np.abs(t_n[comp]), rtol=RTOL)
    # every bond point initiated once, and one step before, the elastic traction was
    # still inside the criterion
    assert np.all(r["initiated"].sum(axis=0) == 1)
    first = np.argmax(r["initiated"], axis=0)
    cols = np.arange(n)
    before = fb.effective_traction(r["f_n"][first - 1, cols] / L, r["f_t"][first - 1, cols] / L,
                                   SIGMA, TAU, MU)
    assert np.all(before < SIGMA)


@pytest.mark.parametrize("direction", fb.DIRECTIONS)
@pytest.mark.parametrize("mu", [0.0, 0.3])
def test_compressed_bond_holds_until_tau_plus_friction(direction, mu):
    """Compress to t_n = -200 kPa, then shear: the bond stays elastic until
    |t_t| = tau_cr + mu |t_n|, and still dissipates G l."""
    k = 1e9   # stiff enough that the compressed peak stores less than G l
    kt = k * BETA ** (1 if direction == "paper" else 2)
    c = 200e3 * L / k
    dt0 = (TAU + mu * 200e3) * L / kt          # analytic tangential opening at the peak
    dt_f = 2 * GL / (k * BETA**2 * dt0)         # delta_f / beta, delta_f = 2 G l / (k beta dt0)
    dt = np.r_[np.zeros(10), np.linspace(0, 0.999 * dt0, 50), np.linspace(1.001 * dt0, 1.1 * dt_f, 2000)]
    dn = np.r_[np.linspace(0, -c, 10), np.full(dt.size - 10, -c)]
    b = fb.ElasticBondPoints(k, L, SIGMA, TAU, mu, G, direction)
    r = b.run_path(dn[:, None], dt[:, None])
    first = np.argmax(r["initiated"][:, 0])
    assert dt[first - 1] < dt0 <= dt[first]
    assert b.peak_f_t[0] / L == pytest.approx(TAU + mu * 200e3, rel=RTOL)
    assert b.peak_f_n[0] / L == pytest.approx(-200e3, rel=RTOL)
    assert r["dissipation"].sum() == pytest.approx(GL, rel=RTOL)
    assert b.mode[0] == fb.SHEAR
    # after the peak the normal cohesion is gone (closed crack: contact carries it)
    assert np.all(r["f_n"][first:, 0] == 0.0)


@pytest.mark.parametrize("direction", fb.DIRECTIONS)
def test_elastic_unloading_is_reversible(direction):
    d_hat = unit_effective((0.6, 0.4))
    s0 = peak_opening(direction, d_hat)
    s = np.r_[np.linspace(0, 0.9 * s0, 10), np.linspace(0.8 * s0, -0.5 * s0, 14), np.linspace(-0.4 * s0, 0.9 * s0, 14)]
    b = bonds(direction)
    r = b.run_path(s[:, None] * d_hat[0], s[:, None] * d_hat[1])
    power = 1 if direction == "paper" else 2
    np.testing.assert_allclose(r["f_n"][:, 0], K * s * d_hat[0], rtol=RTOL)
    np.testing.assert_allclose(r["f_t"][:, 0], K * BETA**power * s * d_hat[1], rtol=RTOL)
    assert b.state[0] == 0 and np.all(r["dissipation"] == 0)


@pytest.mark.parametrize("direction", fb.DIRECTIONS)
def test_unloading_after_peak_follows_secant(direction):
    d_hat = unit_effective((1.0, 0.0))
    s0 = peak_opening(direction, d_hat)
    sf = 2 * GL / (K * s0)
    sm = s0 + 0.3 * (sf - s0)
    s = np.r_[np.linspace(0, sm, 50), np.linspace(sm, 0.2 * sm, 9)[1:]]
    b = bonds(direction)
    r = b.run_path(s[:, None], 0 * s[:, None])
    Fm = K * s0 * (sf - sm) / (sf - s0)         # on the softening line at delta_m
    np.testing.assert_allclose(r["f_n"][-8:, 0], Fm * s[-8:] / sm, rtol=RTOL)


@pytest.mark.parametrize("direction", fb.DIRECTIONS)
def test_too_soft_bond_is_rejected(direction):
    k_min = fb.min_elastic_stiffness(SIGMA, TAU, G, L, direction)
    with pytest.raises(ValueError, match="k must be >"):
        fb.ElasticBondPoints(0.99 * k_min, L, SIGMA, TAU, MU, G, direction)
    # just above the bound every tensile-side peak is below delta_f: pure tension and
    # pure shear fail cleanly with G l dissipated
    b = fb.ElasticBondPoints(1.01 * k_min * np.ones(2), L, SIGMA, TAU, MU, G, direction)
    s = np.linspace(0, 0.2, 20001)[:, None]
    r = b.run_path(s * [1.0, 0.0], s * [0.0, 1.0])
    np.testing.assert_allclose(r["dissipation"].sum(axis=0), GL, rtol=RTOL)


def test_compressed_peak_beyond_delta_f_raises():
    # k barely above the tensile bound: under t_n = -100 kPa the peak force
    # (tau + mu|t_n|) l is 1.6x the shear peak, its elastic energy > G l
    k = 1.1 * fb.min_elastic_stiffness(SIGMA, TAU, G, L, "paper")
    b = fb.ElasticBondPoints(k, L, SIGMA, TAU, MU, G, "paper")
    c = 100e3 * L / k
    b.step([-c], [0.0])
    with pytest.raises(RuntimeError, match="raise the stiffness k"):
        b.step([-c], [1.0])
    assert b.state[0] == 0


def test_work_conjugate_elastic_mechanical_dissipation_matches_law():
    """Work-conjugate elastic bond, radial mixed path with the peak on a grid node and an
    unload/reload cycle: work done - stored energy equals the law's cumulative dissipation
    at every step (0 through the elastic branch, G l at the end)."""
    d_hat = unit_effective((0.5, 0.5))
    s0 = peak_opening("work_conjugate", d_hat)
    sf = 2 * GL / (K * s0)
    up = np.r_[np.linspace(0, s0, 21), np.linspace(s0, 0.5 * sf, 400)[1:]]
    s = np.r_[up, np.linspace(0.5 * sf, 0.1 * sf, 50)[1:], np.linspace(0.1 * sf, 1.05 * sf, 400)[1:]]
    b = bonds("work_conjugate")
    dn, dt = s[:, None] * d_hat[0], s[:, None] * d_hat[1]
    w, law, stored = [0.0], [0.0], [0.0]
    f_old = (0.0, 0.0)
    for i in range(1, s.size):
        r = b.step(dn[i], dt[i])
        w.append(w[-1] + float(fb.work_increment(f_old[0], f_old[1], r["f_n"][0], r["f_t"][0],
                                           dn[i, 0] - dn[i - 1, 0], dt[i, 0] - dt[i - 1, 0])))
        law.append(law[-1] + r["dissipation"][0])
        stored.append(b.stored_energy()[0])
        f_old = (r["f_n"][0], r["f_t"][0])
    mech = np.array(w) - np.array(stored)
    np.testing.assert_allclose(mech, law, rtol=1e-12, atol=1e-12 * GL)
    assert law[-1] == pytest.approx(GL, rel=RTOL)
    assert np.all(np.array(law)[:20] == 0.0)   # elastic branch: nothing dissipated
    assert law[20] < 1e-12 * GL                 # peak node (located to round-off)
