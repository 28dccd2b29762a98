"""The paper's definitions as the analyses read them (docs/postproc.md, "Definitions and
choices"), one test per definition, on constructed records and bond tables whose answer
is known by hand: F^m the cohesive peak, failed bond points = split points, n_t/n_s by
mode at full failure beside the initiation side, F paired with F_d averaged over travel."""
import math
from types import SimpleNamespace

import h5py
import numpy as np
import pytest

from icerubble.files import results
from postproc import displaced_area, failure_plane, loads, plug, shear_strength, summary

from tests.postproc import synthetic

W = 4.0          # indenter width [m]
Y0 = -0.9109     # keel top [m]
MM = 1e-3


def _spiky_record():
    """0 -> 30 kN/m at 1 mm (the cohesive peak), down to 12 at 10 mm, a 50 kN/m spike
    at 12 mm (a late dynamic event), 12 again from 14 mm to 30 mm; knots sampled."""
    yk = np.array([0, 1, 10, 12, 14, 30]) * MM
    Fk = np.array([0, 30, 12, 50, 12, 12]) * 1e3
    y = np.unique(np.r_[yk, np.arange(0, 30.001, 0.05) * MM])
    return y, np.interp(y, yk, Fk)


def test_F_m_is_the_cohesive_peak_and_a_later_spike_only_the_record_maximum():
    y, F = _spiky_record()
    assert loads.cohesive_peak(y, F) == pytest.approx((30e3, 1 * MM), abs=1e-9)
    assert loads.record_maximum(y, F) == pytest.approx((50e3, 12 * MM), abs=1e-9)
    # a record shorter than the 5 mm window: its own maximum (F is rising at 3 mm)
    short = y <= 3 * MM
    assert loads.cohesive_peak(y[short], F[short]) == pytest.approx((30e3, 1 * MM), abs=1e-9)
    rising = y <= 0.5 * MM
    assert loads.cohesive_peak(y[rising], F[rising]) == pytest.approx((15e3, 0.5 * MM), abs=1e-9)
    with pytest.raises(ValueError, match="after the cohesive-peak window 0-5 mm"):
        loads.cohesive_peak(y[y > 6 * MM], F[y > 6 * MM])


def test_summary_takes_tau_from_the_cohesive_peak_and_keeps_the_record_maximum(tmp_path):
    """The synthetic record peaks at 1 mm; a spike of twice that peak written at 12 mm
    must not move F^m or tau(1) = F^m/(2h), h = 4 m, and shows as the record maximum
    with tau(1) from it = 2 tau(1)."""
    p = synthetic.write_run(str(tmp_path / "r.h5"), "1", 0.05, 50e3, travel_end=0.03)
    with h5py.File(p, "r+") as f:
        y, F = f["force/y_I"][:], f["force/F"][:]
        F_peak = F[np.argmin(np.abs(y - 1 * MM))]
        assert F.max() == F_peak    # the synthetic peak at 1 mm is the record's maximum
        F[np.argmin(np.abs(y - 12 * MM))] = 2 * F_peak
        f["force/F"][...] = F
    row = summary.summarize(results.load(p))
    assert row["F_m_kN_per_m"] == pytest.approx(F_peak / 1e3, rel=1e-12) and row["y_I_peak_mm"] == pytest.approx(1.0)
    assert row["tau1_kPa"] == pytest.approx(F_peak / 8.0 / 1e3, rel=1e-12)
    assert row["F_record_max_kN_per_m"] == pytest.approx(2 * F_peak / 1e3, rel=1e-12)
    assert row["y_I_record_max_mm"] == pytest.approx(12.0)
    assert row["tau1_record_max_kPa"] == pytest.approx(2 * row["tau1_kPa"], rel=1e-12)


def _line(side, alpha_deg, depths):
    """Points on a plane from x = side*w_I/2 at the keel top, moving away from the
    centre line by tan(alpha) per metre of depth (Fig. 12 sign convention)."""
    y = Y0 - np.asarray(depths, dtype=float)
    return np.column_stack([side * (W / 2 + (Y0 - y) * math.tan(math.radians(alpha_deg))), y])


def test_failed_bond_points_are_the_split_points_at_1mm():
    """At y_I = 1 mm every point on the two planes has split (at 0.4 mm) and none has
    fully failed (3 mm, as delta_f ~ 1-3 mm allows): alpha and A_p come from the split
    points by default; with bond_points='failed' there is nothing to fit yet."""
    depths = np.linspace(0.5, 3.5, 5)
    aL, aR = 30.0, 40.0
    pts = np.vstack([_line(-1, aL, depths), _line(1, aR, depths)])
    n = len(pts)
    run = SimpleNamespace(bonds={"position": pts, "y_I_split": np.full(n, 0.4 * MM),
                                 "y_I_fail": np.full(n, 3.0 * MM)}, indenter_width=W)
    left, right = failure_plane.alpha_at(run, 1 * MM)
    assert left == pytest.approx(aL, abs=1e-9) and right == pytest.approx(aR, abs=1e-9)
    # trapezoid between depths 0.5 and 3.5 m: widths w_I + d (tan aL + tan aR)
    t = math.tan(math.radians(aL)) + math.tan(math.radians(aR))
    assert plug.plug_area(run, 1 * MM) == pytest.approx(3.0 * (2 * W + 4.0 * t) / 2, abs=1e-9)
    assert all(math.isnan(a) for a in failure_plane.alpha_at(run, 1 * MM, "failed"))
    assert math.isnan(plug.plug_area(run, 1 * MM, "failed"))
    # by 3 mm they have fully failed: both choices see the same planes
    assert failure_plane.alpha_at(run, 3 * MM, "failed") == pytest.approx((aL, aR), abs=1e-9)
    with pytest.raises(ValueError, match="bond_points must be one of 'split', 'failed', got 'broken'"):
        failure_plane.alpha_at(run, 1 * MM, "broken")


def test_mode_ratio_at_full_failure_beside_the_initiation_side():
    """Ten bond points: eight split, four of them fully failed (modes 1, 1, 1, 2);
    at the split five had t_n >= 0 (one exactly 0, the tension side of eq 6) and
    three t_n < 0. n_t/n_s = 3/1, at initiation 5/3, failed fraction 4/8."""
    nan = np.nan
    y_split = np.array([1, 1, 2, 2, 3, 3, 4, 5, nan, nan]) * MM
    y_fail = np.array([2, 3, 4, 6, nan, nan, nan, nan, nan, nan]) * MM
    mode = np.array([1, 1, 1, 2, 0, 0, 0, 0, 0, 0])
    split_tn = np.array([10e3, 0.0, 8e3, -5e3, 9e3, -1e3, -2e3, 7e3, nan, nan])
    assert shear_strength.failure_mode_ratio(mode, y_fail) == (3, 1, 3.0)
    assert shear_strength.initiation_side_ratio(y_split, split_tn) == (5, 3, pytest.approx(5 / 3))
    assert shear_strength.failed_fraction(y_split, y_fail) == 0.5
    # no traction in the file, or a split point without one: no count rather than a partial one
    assert all(math.isnan(v) for v in shear_strength.initiation_side_ratio(y_split, None))
    gap = split_tn.copy()
    gap[7] = nan
    assert all(math.isnan(v) for v in shear_strength.initiation_side_ratio(y_split, gap))
    # every split on the tension side: 8 : 0, the ratio undefined
    n_t, n_s, r = shear_strength.initiation_side_ratio(y_split, np.abs(split_tn))
    assert (n_t, n_s) == (8, 0) and math.isnan(r)


def test_windowed_load_averages_over_travel_clipped_to_the_record():
    # F = 1e6 y [N/m], y in m: the mean over an interval is F at its midpoint
    y = np.linspace(0.0, 30 * MM, 601)
    F = 1e6 * y
    assert loads.windowed_load(y, F, 12 * MM, 5 * MM) == pytest.approx(12e3, abs=1e-6)
    assert loads.windowed_load(y, F, 2 * MM, 5 * MM) == pytest.approx(3.5e3, abs=1e-6)    # [0, 7] mm
    assert loads.windowed_load(y, F, 30 * MM, 5 * MM) == pytest.approx(27.5e3, abs=1e-6)  # [25, 30] mm
    with pytest.raises(ValueError, match="outside the record"):
        loads.windowed_load(y, F, 31 * MM, 5 * MM)


def test_R_from_F_averaged_over_travel_against_single_samples():
    """F_d rises linearly, 100 N/m per snapshot (20, 30, ..., 150 mm); F = F_d plus a
    ripple A (-1)^k w(y - y_k) in the 10 mm around snapshot k, w(u) = (cos(2 pi u/L) +
    cos(4 pi u/L))/2 with L = 10 mm: 1 at the snapshot, 0 at the window edges (F stays
    continuous) and zero mean over the window (whole cosine periods, on which the
    trapezoid rule is exact), so F̄ = F_d and R = 1; single samples carry e_k = A (-1)^k. With s = k - 6.5: S_xx = d² Σs² =
    227.5 d², S_xe = d A Σ s (-1)^k = -7 d A, S_ee = 14 A², and
    R = (S_xx + S_xe)/sqrt(S_xx (S_xx + 2 S_xe + S_ee))."""
    d, A = 100.0, 1000.0
    yk = displaced_area.FIG20_TRAVELS
    k = np.arange(len(yk))
    Fd = 20e3 + d * k
    y = np.round(np.arange(0.0, 160.0 + 1e-9, 0.05), 10) * MM
    idx = np.clip(np.round((y - yk[0]) / (10 * MM)).astype(int), 0, len(yk) - 1)
    slope = d / (10 * MM)
    u = 2 * np.pi * (y - yk[idx]) / (10 * MM)
    F = 20e3 + slope * (y - yk[0]) + A * (-1.0) ** idx * 0.5 * (np.cos(u) + np.cos(2 * u))
    run = SimpleNamespace(force_y=y, force_F=F)
    F_bar = [displaced_area.paired_load(run, t) for t in yk]
    assert np.allclose(F_bar, Fd, rtol=0, atol=1e-6)
    assert displaced_area.correlation(Fd, F_bar)[0] == pytest.approx(1.0, abs=1e-12)
    F_one = [loads.load_at(y, F, t) for t in yk]
    Sxx, Sxe, See = 227.5 * d ** 2, -7.0 * d * A, 14.0 * A ** 2
    R_hand = (Sxx + Sxe) / math.sqrt(Sxx * (Sxx + 2 * Sxe + See))   # 0.2707
    assert displaced_area.correlation(Fd, F_one)[0] == pytest.approx(R_hand, abs=1e-9)
    assert R_hand < 0.3
