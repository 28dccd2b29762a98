"""Freeze bonds between rigid blocks (engine rigid/rigid_bonds.hpp): a bonded
pair pulled apart peaks at sigma_cr x bonded length and dissipates G x length;
in shear it fails at tau_cr, under compression at tau_cr + mu |t_n|; a rigid
rotation of the pair opens nothing."""
import numpy as np
import pytest

from icerubble import _engine

L, N_PTS = 1.0, 4                    # bonded face length [m], bond points on it
SIG, TAU, MU, G, K = 10e3, 50e3, 0.3, 15.0, 1e9
CB = np.array([0.0, 0.15])           # b's centroid; a's at the origin; the face at y = 0


def bonded_pair(**override):
    xs = (np.arange(N_PTS) + 0.5) / N_PTS * L - L / 2
    face = np.column_stack([xs, np.zeros(N_PTS)])
    n = N_PTS
    args = dict(a=np.zeros(n, np.int32), b=np.ones(n, np.int32), anchor_a=face, anchor_b=face - CB,
                normal_a=np.tile([0.0, 1.0], (n, 1)), k=np.full(n, K), l=np.full(n, L / N_PTS),
                sigma_cr=np.full(n, SIG), tau_cr=np.full(n, TAU), mu=np.full(n, MU), G=np.full(n, G),
                n_bodies=2)
    args.update(override)
    return _engine.RigidBonds(**args)


def drive(bonds, path):
    """Move b along path (k, 2) of displacements from its bonded place; returns
    the bond force on b at each step and the work done on the bonds."""
    forces, work, prev_u, prev_f = [], 0.0, np.zeros(2), np.zeros(2)
    for k, u in enumerate(path):
        fx, fy, tz = bonds.step(np.array([0.0, CB[0] + u[0]]), np.array([0.0, CB[1] + u[1]]), np.zeros(2), 1e-3 * k)
        f = np.array([fx[1], fy[1]])
        work += -0.5 * (f + prev_f) @ (u - prev_u)   # work done against the bond forces
        forces.append(f)
        prev_u, prev_f = u, f
    return np.array(forces), work


def straight(to, steps):
    return np.outer(np.linspace(0.0, 1.0, steps + 1)[1:], to)


def test_pulled_apart_it_peaks_at_sigma_cr_times_length_and_dissipates_G_times_length():
    bonds = bonded_pair()
    f, work = drive(bonds, straight([0.0, 4e-3], 8000))          # 0.5 um steps to 4 mm
    assert -f[:, 1].min() == pytest.approx(SIG * L, rel=1e-3)      # peak of the pull-back
    assert np.all(bonds.state == 2)                                # all broken ...
    assert np.all(bonds.mode == 1)                                 # ... in tension
    assert bonds.dissipated.sum() == pytest.approx(G * L, rel=1e-12)
    assert work == pytest.approx(G * L, rel=1e-3)                  # trapezoid work of the path
    assert np.all(f[-1] == 0.0)


def test_sheared_it_fails_at_tau_cr_and_dissipates_G_over_beta():
    bonds = bonded_pair()
    f, work = drive(bonds, straight([4e-3, 0.0], 8000))
    assert -f[:, 0].min() == pytest.approx(TAU * L, rel=1e-3)
    assert np.all(bonds.mode == 2)
    # eq 11 as printed: the work of a full opening in pure shear is G l / beta
    # (docs/model.md §3.3); the dissipation book says G l
    assert bonds.dissipated.sum() == pytest.approx(G * L, rel=1e-12)
    assert work == pytest.approx(G * L * SIG / TAU, rel=2e-3)


def test_under_compression_shear_fails_at_tau_cr_plus_mu_times_the_pressure():
    bonds = bonded_pair()
    press = -2e-6                                  # closing: t_n = K press / l per point
    t_n = K * press / (L / N_PTS)
    path = np.vstack([straight([0.0, press], 50), np.column_stack([np.linspace(0, 3e-4, 6001)[1:], np.full(6000, press)])])
    f, _ = drive(bonds, path)
    assert -f[:, 0].min() == pytest.approx((TAU + MU * abs(t_n)) * L, rel=1e-3)
    assert bonds.t_initiated.min() > 0.0 and np.all(np.isfinite(bonds.t_initiated))


def test_a_rigid_rotation_of_the_bonded_pair_opens_nothing():
    bonds = bonded_pair()
    for phi in np.linspace(0.0, 2.0, 50):
        R = np.array([[np.cos(phi), -np.sin(phi)], [np.sin(phi), np.cos(phi)]])
        cb = R @ CB + np.array([3.0, -1.0])
        fx, fy, tz = bonds.step(np.array([3.0, cb[0]]), np.array([-1.0, cb[1]]), np.array([phi, phi]), 0.0)
        assert np.abs(np.concatenate([fx, fy, tz])).max() < 1e-9 * SIG * L
    assert np.all(bonds.state == 0)


def test_bond_forces_are_action_and_reaction_with_balanced_moments():
    bonds = bonded_pair()
    # a small skew move of b: still intact, every point loaded differently
    x, y, th = np.array([0.0, 5e-7]), np.array([0.0, 0.15 + 2e-7]), np.array([0.0, 4e-7])
    fx, fy, tz = bonds.step(x, y, th, 0.0)
    assert np.all(bonds.state == 0) and np.abs(fx).max() > 0 and np.abs(tz).max() > 0
    assert abs(fx.sum()) < 1e-9 * np.abs(fx).max() and abs(fy.sum()) < 1e-9 * np.abs(fy).max()
    moment = tz + x * fy - y * fx
    assert abs(moment.sum()) < 1e-9 * np.abs(moment).max()


def test_unload_reload_before_the_peak_is_elastic_and_after_it_on_the_secant():
    bonds = bonded_pair()
    d0 = SIG * (L / N_PTS) / K                      # opening at the peak
    up, down = straight([0.0, 3 * d0], 300), straight([0.0, 3 * d0], 300)[::-1][1:]
    f, _ = drive(bonds, np.vstack([up, down, up]))
    fy = -f[:, 1]
    # back at 1.5 d0 on the way down: on the secant through the origin
    k_sec = fy[299] / (3 * d0)
    assert fy[299 + 150] == pytest.approx(k_sec * 1.5 * d0, rel=1e-9)
    assert bonds.dissipated.sum() < G * L            # partly open, not failed
    assert bonds.stored_energy() > 0.0


def test_a_bond_too_soft_for_its_strength_is_refused():
    with pytest.raises(ValueError, match="k = .* must exceed"):
        bonded_pair(k=np.full(N_PTS, 1e5))
    with pytest.raises(ValueError, match="unit vector"):
        bonded_pair(normal_a=np.tile([0.0, 2.0], (N_PTS, 1)))
    with pytest.raises(ValueError, match="two different ids"):
        bonded_pair(b=np.zeros(N_PTS, np.int32))


def test_held_bonds_stay_intact_and_elastic_until_failure_is_switched_on():
    bonds = bonded_pair()
    bonds.failure = False
    f, _ = drive(bonds, straight([0.0, 1e-4], 100))        # 20 x the peak opening
    assert np.all(bonds.state == 0)
    assert -f[-1, 1] == pytest.approx(K * 1e-4 * N_PTS, rel=1e-12)   # on the elastic line
    bonds.failure = True
    # released held 20 x past its peak, with more elastic energy than G l:
    # it breaks at once, in tension, booking G l
    f, _ = drive(bonds, np.array([[0.0, 1e-4]]))
    assert np.all(bonds.state == 2) and np.all(bonds.mode == 1)
    assert np.all(f == 0.0)
    assert bonds.dissipated.sum() == pytest.approx(G * L, rel=1e-12)
