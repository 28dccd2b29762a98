"""Python API of the cohesive law: validation, broadcasting, depth scaling."""
import numpy as np
import pytest

from icerubble import cohesive_law as fb
from icerubble import _cohesive_law as law


@pytest.mark.parametrize("kwargs,name", [
    (dict(sigma_cr=0.0), "sigma_cr"), (dict(sigma_cr=-1.0), "sigma_cr"),
    (dict(tau_cr=0.0), "tau_cr"), (dict(mu=-0.1), "mu"), (dict(sigma_cr=np.nan), "sigma_cr")])
def test_criterion_rejects_bad_strength(kwargs, name):
    p = dict(sigma_cr=10e3, tau_cr=50e3, mu=0.3)
    p.update(kwargs)
    with pytest.raises(ValueError, match=name):
        fb.criterion_reached(1.0, 1.0, **p)
    with pytest.raises(ValueError, match=name):
        fb.effective_traction(1.0, 1.0, **p)


@pytest.mark.parametrize("kwargs,name", [
    (dict(f0=0.0), "f0"), (dict(G=0.0), "G"), (dict(G=-15.0), "G"), (dict(l=0.0), "l"),
    (dict(beta=-1.0), "beta"), (dict(direction="eq11"), "direction")])
def test_opened_bonds_reject_bad_parameters(kwargs, name):
    p = dict(f0=[1e3, 2e3], G=15.0, l=0.1, beta=5.0, direction="paper")
    p.update(kwargs)
    with pytest.raises(ValueError, match=name):
        fb.OpenedBondPoints(**p)


@pytest.mark.parametrize("kwargs,name", [
    (dict(sigma_cr=0.0), "sigma_cr"), (dict(tau_cr=-5.0), "tau_cr"), (dict(mu=-1.0), "mu"),
    (dict(G=0.0), "G"), (dict(l=-0.1), "l"), (dict(k=0.0), "k"),
    (dict(direction="rigid"), "direction")])
def test_elastic_bonds_reject_bad_parameters(kwargs, name):
    p = dict(k=1e9, l=0.1, sigma_cr=10e3, tau_cr=50e3, mu=0.3, G=15.0, direction="paper")
    p.update(kwargs)
    with pytest.raises(ValueError, match=name):
        fb.ElasticBondPoints(**p)


def test_step_rejects_bad_openings():
    b = fb.OpenedBondPoints([1e3, 1e3], 15.0, 0.1, 5.0)
    with pytest.raises(ValueError, match="one entry per bond point"):
        b.step([0.0], [0.0])
    with pytest.raises(ValueError, match="not finite"):
        b.step([0.0, np.nan], [0.0, 0.0])
    assert np.all(b.delta_m == 0.0)  # nothing was stepped
    with pytest.raises(ValueError, match="shape"):
        b.run_path(np.zeros((3, 2)), np.zeros((4, 2)))
    with pytest.raises(ValueError, match="equal lengths"):
        fb.OpenedBondPoints([1e3, 1e3], [15.0, 15.0, 15.0], 0.1, 5.0)


def test_vectorised_step_equals_one_by_one():
    rng = np.random.default_rng(3)
    n = 200
    f0 = rng.uniform(500, 5000, n)
    beta = rng.uniform(0.5, 10, n)
    steps = rng.normal(0, 3e-4, (40, n, 2)).cumsum(axis=0)   # random, non-monotonic paths
    for direction in fb.DIRECTIONS:
        many = fb.OpenedBondPoints(f0, 15.0, 0.1, beta, direction)
        r = many.run_path(steps[..., 0], steps[..., 1])
        for i in range(0, n, 37):
            one = fb.OpenedBondPoints(f0[i], 15.0, 0.1, beta[i], direction)
            ri = one.run_path(steps[:, i:i + 1, 0], steps[:, i:i + 1, 1])
            for key in ("f_n", "f_t", "dissipation", "failed"):
                assert np.array_equal(r[key][:, i], ri[key][:, 0])


def test_scalar_functions_broadcast():
    t_n = np.linspace(-1e4, 1e4, 5)[:, None]
    t_t = np.linspace(0, 6e4, 4)[None, :]
    te = fb.effective_traction(t_n, t_t, 10e3, 50e3, 0.3)
    assert te.shape == (5, 4)
    assert fb.criterion_reached(t_n, t_t, 10e3, [50e3, 50e3, 50e3, 50e3], 0.3).shape == (5, 4)
    assert fb.initial_force_magnitude(1.0, 2.0, np.ones((3, 2)), np.zeros((3, 2))).shape == (3,)


def test_depth_scaling():
    h = 4.0
    depth = np.array([-1.0, 0.0, 1.0, 2.0, 4.0, 5.0])
    k = fb.depth_factor(depth, h)
    np.testing.assert_allclose(k, [1.0, 1.0, 0.775, 0.55, 0.1, 0.1], rtol=1e-15)
    p = fb.strength_at_depth(depth, h, 10e3, 50e3, 15.0)
    np.testing.assert_allclose(p["tau_cr"] / p["sigma_cr"], 5.0, rtol=1e-15)  # beta constant
    np.testing.assert_allclose(p["G"], 15.0 * k, rtol=1e-15)
    assert fb.depth_factor(2.0, h, bottom_fraction=1.0) == 1.0
    with pytest.raises(ValueError, match="keel_depth"):
        fb.depth_factor(1.0, 0.0)
    with pytest.raises(ValueError, match="bottom_fraction"):
        fb.depth_factor(1.0, h, bottom_fraction=0.0)
    with pytest.raises(ValueError, match="G_top"):
        fb.strength_at_depth(1.0, h, 10e3, 50e3, -15.0)


def test_module_constants_match_results_format():
    # docs/results_format.md /bonds/mode: 1 tensile, 2 shear
    assert (law.TENSILE, law.SHEAR) == (1, 2)
