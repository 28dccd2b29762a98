"""Failure criterion of the freeze bonds (eqs 5-6) and its compressive side."""
import numpy as np
import pytest

from icerubble import cohesive_law as fb

SIGMA, MU = 10e3, 0.3
# Points are placed 1e-9 (relative) inside/outside the analytic boundary: the
# criterion is evaluated with a few ulps (~1e-15) of round-off in beta and the
# square root, so 1e-9 separates the sides unambiguously while being far below any
# physical margin.
EPS = 1e-9


@pytest.mark.parametrize("tau", [5e3, 12.5e3, 50e3, 100e3])
def test_pure_tension_fails_at_sigma_cr(tau):
    assert fb.effective_traction(SIGMA, 0.0, SIGMA, tau, MU) == pytest.approx(SIGMA, rel=1e-15)
    assert not fb.criterion_reached(SIGMA * (1 - EPS), 0.0, SIGMA, tau, MU)
    assert fb.criterion_reached(SIGMA * (1 + EPS), 0.0, SIGMA, tau, MU)


@pytest.mark.parametrize("tau", [5e3, 12.5e3, 50e3, 100e3])
def test_pure_shear_fails_at_tau_cr_either_sign(tau):
    for sign in (1.0, -1.0):
        assert not fb.criterion_reached(0.0, sign * tau * (1 - EPS), SIGMA, tau, MU)
        assert fb.criterion_reached(0.0, sign * tau * (1 + EPS), SIGMA, tau, MU)


@pytest.mark.parametrize("mu", [0.0, 0.05, 0.3])
def test_compression_shear_boundary_includes_friction(mu):
    tau = 50e3
    t_n = -np.array([1e3, 10e3, 100e3, 1e6])
    boundary = tau + mu * np.abs(t_n)
    assert not fb.criterion_reached(t_n, boundary * (1 - EPS), SIGMA, tau, mu).any()
    assert fb.criterion_reached(t_n, -boundary * (1 + EPS), SIGMA, tau, mu).all()
    # t_e measures the shear in excess of friction, scaled by 1/beta
    np.testing.assert_allclose(fb.effective_traction(t_n, boundary, SIGMA, tau, mu), SIGMA,
                               rtol=1e-14)


def test_compression_never_fails_below_tau_plus_friction():
    # Sweep the compressive side densely: no point with |t_t| < tau + mu|t_n| fails.
    tau = 12.5e3
    t_n = -np.linspace(0.0, 200e3, 401)[1:]
    frac = np.linspace(0.0, 1.0 - EPS, 201)
    tn, fr = np.meshgrid(t_n, frac)
    tt = fr * (tau + MU * np.abs(tn))
    assert not fb.criterion_reached(tn, tt, SIGMA, tau, MU).any()


@pytest.mark.parametrize("tau", [5e3, 50e3])
def test_mixed_mode_is_the_ellipse(tau):
    theta = np.linspace(-np.pi / 2, np.pi / 2, 181)
    t_n, t_t = SIGMA * np.cos(theta), tau * np.sin(theta)
    np.testing.assert_allclose(fb.effective_traction(t_n, t_t, SIGMA, tau, MU), SIGMA, rtol=1e-14)
    assert not fb.criterion_reached(t_n * (1 - EPS), t_t * (1 - EPS), SIGMA, tau, MU).any()
    assert fb.criterion_reached(t_n * (1 + EPS), t_t * (1 + EPS), SIGMA, tau, MU).all()


def test_criterion_is_continuous_across_t_n_zero():
    tau = 50e3
    t_t = 30e3
    below = fb.effective_traction(-1e-6, t_t, SIGMA, tau, MU)
    above = fb.effective_traction(1e-6, t_t, SIGMA, tau, MU)
    # both branches give |t_t|/beta at t_n = 0; the branches differ by O(mu*1e-6/beta)
    assert abs(below - above) < 1e-6
