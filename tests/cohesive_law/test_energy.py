"""Energy of a full opening (eq 12 and the docs/model.md §3.3 caveat).

Integration: on a radial path delta = s * d_hat the force components are linear in s
between the kinks (delta_f, turning points), and every kink is a grid node, so the
trapezoid rule is exact; the only error is round-off (~N ulps, N <= 2000 steps), hence
the 1e-12 relative tolerance. The curved path uses Simpson with a Richardson bound.
"""
import numpy as np
import pytest

from icerubble import cohesive_law as fb

trapezoid = getattr(np, "trapezoid", None) or np.trapz  # numpy 2 renamed trapz

F0, G, L = 2.0e3, 15.0, 0.05
GL = G * L
DF = 2 * GL / F0
RTOL = 1e-12
BETAS = [0.5, 1.25, 5.0, 10.0]    # tau_cr / sigma_cr for sigma_cr = 10 kPa, Table 1 range


def unit_effective(d, beta):
    """Scale d so that the effective opening along s * d is s."""
    d = np.asarray(d, float)
    return d / fb.effective_opening(d[0], d[1], beta)


def run(direction, beta, d_hat, s):
    b = fb.OpenedBondPoints(F0, G, L, beta, direction)
    dn, dt = s[:, None] * d_hat[0], s[:, None] * d_hat[1]
    return b, dn, dt, b.run_path(dn, dt)


def mechanical_work(dn, dt, r):
    """Sum over steps of the trapezoid 1/2 (f_old + f_new) . d_delta (exact on linear steps)."""
    return fb.work_increment(r["f_n"][:-1], r["f_t"][:-1], r["f_n"][1:], r["f_t"][1:],
                             np.diff(dn, axis=0), np.diff(dt, axis=0)).sum(axis=0)


def grid(n=1000, beyond=5):
    return np.arange(n + beyond + 1) * (DF / n)


PATHS = {"tension": (1.0, 0.0), "shear": (0.0, 1.0), "shear_neg": (0.0, -1.0),
         "mixed": (0.7, 0.3), "mixed_closed": (-0.4, 0.9)}


def first_step_fix(dn, dt, r, beta, direction):
    """Force at s = 0+ (eq 11 limit along the path) replaces the undefined value at s = 0."""
    d = np.array([dn[1, 0], dt[1, 0]])
    de = fb.effective_opening(d[0], d[1], beta)
    power = 1 if direction == "paper" else 2
    r = {k: v.copy() for k, v in r.items()}
    r["f_n"][0, 0] = F0 * max(d[0], 0) / de
    r["f_t"][0, 0] = F0 * beta**power * d[1] / de
    return r


@pytest.mark.parametrize("direction", fb.DIRECTIONS)
@pytest.mark.parametrize("beta", BETAS)
@pytest.mark.parametrize("path", PATHS)
def test_effective_work_and_dissipation_equal_G_l(direction, beta, path):
    """Eq 12: integral of |f_c| d(delta_e) over a full opening is G l, on every path."""
    d_hat = unit_effective(PATHS[path], beta)
    s = grid()
    b, dn, dt, r = run(direction, beta, d_hat, s)
    de = fb.effective_opening(dn, dt, beta)[:, 0]
    if direction == "paper":
        F = np.hypot(r["f_n"], r["f_t"])[:, 0]
    else:
        F = ((r["f_n"] * np.maximum(dn, 0) + r["f_t"] * dt)[:, 0] / np.where(de > 0, de, 1))
    F[0] = F0  # the limit s -> 0+ (no direction at s = 0)
    assert trapezoid(F, de) == pytest.approx(GL, rel=RTOL)
    assert r["dissipation"].sum() == pytest.approx(GL, rel=RTOL)
    assert b.broken[0]


@pytest.mark.parametrize("beta", BETAS)
@pytest.mark.parametrize("path", PATHS)
def test_paper_direction_mechanical_work(beta, path):
    """Eq 11 as printed: W = G l (beta a^2 + <b>^2) for delta = s (b, a), beta^2 a^2 + <b>^2 = 1:
    G l in pure tension, G l / beta in pure shear (docs/model.md §3.3 energy caveat)."""
    d_hat = unit_effective(PATHS[path], beta)
    b_n, a_t = d_hat
    s = grid()
    _, dn, dt, r = run("paper", beta, d_hat, s)
    r = first_step_fix(dn, dt, r, beta, "paper")
    expected = GL * (beta * a_t**2 + max(b_n, 0.0) ** 2)
    assert mechanical_work(dn, dt, r)[0] == pytest.approx(expected, rel=RTOL)
    if path == "tension":
        assert expected == pytest.approx(GL, rel=1e-15)
    if path.startswith("shear"):
        assert expected == pytest.approx(GL / beta, rel=1e-15)


@pytest.mark.parametrize("beta", BETAS)
@pytest.mark.parametrize("path", PATHS)
def test_work_conjugate_mechanical_work_is_G_l(beta, path):
    d_hat = unit_effective(PATHS[path], beta)
    _, dn, dt, r = run("work_conjugate", beta, d_hat, grid())
    r = first_step_fix(dn, dt, r, beta, "work_conjugate")
    assert mechanical_work(dn, dt, r)[0] == pytest.approx(GL, rel=RTOL)


@pytest.mark.parametrize("beta", [1.25, 5.0])
def test_work_conjugate_curved_path_is_G_l(beta):
    """Monotonic curved path delta_n = s, delta_t = kappa s^2; W = integral of f . delta'(s) ds
    by composite Simpson up to s_f where delta_e(s_f) = delta_f (analytic). The integrand
    F(delta_e) delta_e'(s) is smooth there, so Simpson converges as h^4: the error of the
    fine result is bounded by |I_2N - I_N| / 15 (Richardson), plus round-off."""
    kappa = 0.5 / DF
    c = (beta * kappa) ** 2
    s_f = np.sqrt((-1 + np.sqrt(1 + 4 * c * DF**2)) / (2 * c))

    def simpson_work(n):
        s = np.linspace(0.0, s_f, n + 1)
        b = fb.OpenedBondPoints(F0, G, L, beta, "work_conjugate")
        dn, dt = s[:, None], kappa * s[:, None] ** 2
        r = b.run_path(dn, dt)
        g = r["f_n"][:, 0] * 1.0 + r["f_t"][:, 0] * 2 * kappa * s
        g[0] = F0 * 1.0  # limit s -> 0+: direction (1, 0), delta_e' = 1
        w = np.ones(n + 1)
        w[1:-1:2], w[2:-1:2] = 4, 2
        return (s[1] - s[0]) / 3 * np.dot(w, g)

    coarse, fine = simpson_work(400), simpson_work(800)
    bound = abs(fine - coarse) / 15 + 1e-12 * GL
    assert abs(fine - GL) <= bound
    assert bound < 1e-6 * GL  # the check is sharp, not vacuous


@pytest.mark.parametrize("beta", [0.5, 5.0])
def test_work_conjugate_unload_reload_cycles_dissipate_nothing_extra(beta):
    """The secant branch of the work-conjugate law derives from 1/2 k_s delta_e^2: cycles
    below delta_m return their work, and the total to full failure is still G l. At any
    point, mechanical work - stored secant energy = dissipation 1/2 F0 delta_m."""
    d_hat = unit_effective((0.5, 0.5), beta)
    h = DF / 200
    legs = [(0, 80), (80, 20), (20, 120), (120, 0), (0, 150), (150, 60), (60, 205)]
    s = np.concatenate([np.arange(a, b, 1 if b > a else -1) for a, b in legs] + [[205]]) * h
    b, dn, dt, r = run("work_conjugate", beta, d_hat, s)
    r = first_step_fix(dn, dt, r, beta, "work_conjugate")
    assert mechanical_work(dn, dt, r)[0] == pytest.approx(GL, rel=RTOL)
    # stop after the (150 -> 60) unloading leg: delta_m = 150 h, delta_e = 60 h
    stop = sum(abs(b_ - a_) for a_, b_ in legs[:6]) + 1
    part = {k: v[:stop] for k, v in r.items()}
    w = mechanical_work(dn[:stop], dt[:stop], part)[0]
    dm, de = 150 * h, 60 * h
    stored = 0.5 * F0 * (1 - dm / DF) / dm * de**2
    assert w - stored == pytest.approx(0.5 * F0 * dm, rel=RTOL)
    assert r["dissipation"][:stop].sum() == pytest.approx(0.5 * F0 * dm, rel=RTOL)


@pytest.mark.parametrize("direction", fb.DIRECTIONS)
def test_secant_branch_is_conservative_for_both_directions(direction):
    """Work done minus stored_energy (the mechanical dissipation) does not change on
    un-/reloading legs and never decreases; for the paper direction it differs from the
    law's dissipation 1/2 F0 delta_m only by the eq-11 factor, for work-conjugate it equals it."""
    beta = 5.0
    d_hat = unit_effective((0.3, 0.7), beta)
    h = DF / 200
    legs = [(0, 80), (80, 10), (10, 130), (130, 40), (40, 205)]
    s = np.concatenate([np.arange(a, b, 1 if b > a else -1) for a, b in legs] + [[205]]) * h
    b, dn, dt, r = run(direction, beta, d_hat, s)
    r = first_step_fix(dn, dt, r, beta, direction)
    w = np.r_[0.0, np.cumsum(fb.work_increment(r["f_n"][:-1], r["f_t"][:-1], r["f_n"][1:],
                                               r["f_t"][1:], np.diff(dn, axis=0),
                                               np.diff(dt, axis=0))[:, 0])]
    dm = np.maximum.accumulate(s)
    stored = fb.stored_energy(dn[:, 0], dt[:, 0], beta, F0, DF, dm, direction)
    mech = w - stored
    secant = s < dm
    # on secant steps the mechanical dissipation is unchanged (to round-off of G l)
    steps_on_secant = secant[1:] & secant[:-1] | (secant[1:] & (s[:-1] == dm[:-1]))
    assert np.abs(np.diff(mech)[steps_on_secant]).max() < 1e-13 * GL
    assert np.all(np.diff(mech) > -1e-13 * GL)
    law = np.r_[0.0, np.cumsum(r["dissipation"][1:, 0])]
    b_n, a_t = d_hat
    factor = 1.0 if direction == "work_conjugate" else b_n**2 + beta * a_t**2
    np.testing.assert_allclose(mech, factor * law, rtol=1e-12, atol=1e-13 * GL)
