"""Analyses of postproc on constructed data with answers known by hand (paper Figs. 12-20, eqs 13-15)."""
import math

import numpy as np
import pytest

from icerubble.files import results as R
from postproc import displaced_area, failure_plane, loads, plug, shear_strength

from tests.postproc import synthetic

W = 4.0          # indenter width [m]
Y0 = -0.9109     # keel top [m]

# Exact collinear points: least squares returns the line to round-off, so 1e-9 deg /
# 1e-9 m^2 is far above double round-off and far below any real error.
TOL_DEG = 1e-9
TOL_AREA = 1e-9


def _line(side, alpha_deg, depths, x0=W / 2):
    """Points on a plane starting at x = side*x0 at the keel top, moving away from the
    centre line by tan(alpha) per metre of depth (Fig. 12 sign convention)."""
    y = Y0 - np.asarray(depths, dtype=float)
    x = side * (x0 + (Y0 - y) * math.tan(math.radians(alpha_deg)))
    return np.column_stack([x, y])


def _bonds(points, y_fail, y_split=None):
    points = np.asarray(points, dtype=float)
    y_fail = np.asarray(y_fail, dtype=float)
    return {"position": points, "y_I_fail": y_fail,
            "y_I_split": y_fail if y_split is None else np.asarray(y_split, dtype=float)}


@pytest.mark.parametrize("a_left,a_right", [(30.0, 40.0), (-5.0, 12.5), (0.0, -10.0)])
def test_alpha_exact_on_known_lines_both_signs(a_left, a_right):
    depths = np.linspace(0.3, 3.9, 7)
    # start 1 m outside the corners so a negative angle stays outside |x| > w_I/2
    pts = np.vstack([_line(-1, a_left, depths, x0=3.0), _line(1, a_right, depths, x0=3.0)])
    left, right = failure_plane.fit_planes(pts, W)
    assert abs(left.alpha - a_left) < TOL_DEG
    assert abs(right.alpha - a_right) < TOL_DEG


def test_alpha_ignores_points_under_indenter_and_unfailed_points():
    depths = np.linspace(0.2, 3.8, 6)
    on_planes = np.vstack([_line(-1, 35.0, depths), _line(1, 45.0, depths)])
    under = np.array([[-1.5, -2.0], [0.3, -3.0], [1.9, -1.5]])   # |x| < w_I/2: not fitted
    late = np.array([[-9.0, -1.0], [8.0, -4.0]])                 # fails after y_I: not yet failed
    never = np.array([[-6.0, -2.0]])                             # never fails (NaN)
    pts = np.vstack([on_planes, under, late, never])
    y_fail = np.r_[np.full(len(on_planes), 5e-3), np.full(3, 1e-3), [50e-3, 60e-3], [np.nan]]
    b = _bonds(pts, y_fail)
    for choice in ("split", "failed"):   # split = fail here: the same points either way
        failed = failure_plane.failed_points(b, 20e-3, choice)
        assert len(failed) == len(on_planes) + 3
    left, right = failure_plane.fit_planes(failed, W)
    assert abs(left.alpha - 35.0) < TOL_DEG and abs(right.alpha - 45.0) < TOL_DEG
    # a point that has split but not fully failed counts as split only
    y_split = y_fail.copy()
    y_split[-1] = 1e-3
    b2 = _bonds(pts, y_fail, y_split)
    assert len(failure_plane.failed_points(b2, 20e-3, "split")) == len(failed) + 1
    assert len(failure_plane.failed_points(b2, 20e-3, "failed")) == len(failed)


def test_alpha_needs_three_points_per_side():
    pts = np.vstack([_line(-1, 30.0, [1.0, 2.0]), _line(1, 30.0, [1.0, 2.0, 3.0])])
    left, right = failure_plane.fit_planes(pts, W)
    assert left is None and abs(right.alpha - 30.0) < TOL_DEG


def test_plug_area_trapezoid_by_hand():
    # both sides from depth 0.5 to 3.5 m: a trapezoid with horizontal top and bottom
    aL, aR = 30.0, 40.0
    depths = np.linspace(0.5, 3.5, 5)
    pts = np.vstack([_line(-1, aL, depths), _line(1, aR, depths)])
    tL, tR = math.tan(math.radians(aL)), math.tan(math.radians(aR))
    top_w = W + 0.5 * (tL + tR)
    bottom_w = W + 3.5 * (tL + tR)
    expected = 3.0 * (top_w + bottom_w) / 2
    assert abs(plug.plug_area_from_points(pts, W) - expected) < TOL_AREA


def test_plug_area_slanted_top_and_bottom_edges():
    # vertical fits x = -2.5 and x = +2.5; top edge through (-2.5,-1) and (2.5,-1.4),
    # bottom through (-2.5,-5) and (2.5,-4.6): vertical sides 4.0 and 3.2 m, 5 m apart
    left = np.array([[-2.5, -1.0], [-2.5, -3.0], [-2.5, -5.0]])
    right = np.array([[2.5, -1.4], [2.5, -3.0], [2.5, -4.6]])
    area = plug.plug_area_from_points(np.vstack([left, right]), W)
    assert abs(area - 5.0 * (4.0 + 3.2) / 2) < TOL_AREA


def test_plug_area_nan_without_a_line_on_each_side():
    pts = _line(1, 30.0, [0.5, 1.5, 2.5, 3.5])
    assert math.isnan(plug.plug_area_from_points(pts, W))


def test_buoyant_load_eq13_and_trapezoid_plug():
    # (1 - 0.25)(1010 - 920) 9.81 * 16 = 10594.8 N/m: the paper's ~11 kN/m cylindrical plug
    assert abs(plug.buoyant_load(16.0, 0.25) - 10594.8) < 1e-6
    assert abs(plug.trapezoid_plug_area(4.0, 4.0, 0.0) - 16.0) < 1e-12
    assert abs(plug.trapezoid_plug_area(4.0, 4.0, 45.0) - 32.0) < 1e-12
    with pytest.raises(ValueError, match="porosity"):
        plug.buoyant_load(1.0, 1.0)


def test_displaced_area_from_synthetic_uy_field(tmp_path):
    """A u_y field set by hand on the synthetic mesh: 20 x 16 blocks of 0.75 m x 0.25 m
    (ridge 1, eta = 0.25) on 1 m columns centred at x = -9.5 ... 9.5."""
    import h5py
    path = synthetic.write_run(str(tmp_path / "r.h5"), "1", 0.05, 50e3, travel_end=0.03)
    run = R.load(path)
    snap = run.nearest_snapshot(20e-3)
    assert abs(snap.y_I - 20e-3) < 1e-12
    xc = run.elem_centroid[:, 0]
    u = np.zeros((len(xc), 2))
    u[np.abs(xc) < 3, 1] = -snap.y_I            # 6 columns x 16 blocks: 18 m^2 solid
    u[(np.abs(xc) > 3) & (np.abs(xc) < 5), 1] = -0.5 * snap.y_I   # 4 columns: 12 m^2 solid
    u[run.elem_kind != R.BLOCK, 1] = -snap.y_I  # layer and indenter never count
    with h5py.File(path, "r+") as f:
        f["snapshots"][snap.name]["u_elem"][...] = u
    assert abs(displaced_area.displaced_area(run, 0.9, 20e-3, basis="solid") - 18.0) < 1e-9
    assert abs(displaced_area.displaced_area(run, 0.5, 20e-3, basis="solid") - 18.0) < 1e-9  # strict >
    assert abs(displaced_area.displaced_area(run, 0.45, 20e-3, basis="solid") - 30.0) < 1e-9
    assert abs(displaced_area.displaced_area(run, 0.45, 20e-3) - 40.0) < 1e-9  # bulk = solid/(1-eta)
    # eq 14 on the bulk area = (rho_w - rho_i) g A_solid
    assert abs(displaced_area.displaced_load(run, 0.45, 20e-3) - 90.0 * 9.81 * 30.0) < 1e-6
    A = displaced_area.displaced_areas(run, (0.1, 0.9), [20e-3, 200e-3], basis="solid")
    assert np.allclose(A[0], [30.0, 18.0]) and np.isnan(A[1]).all()  # no snapshot at 200 mm


def test_correlation_perfect_and_inverse():
    x = np.linspace(10.0, 40.0, 14)
    R_, s, i0 = displaced_area.correlation(x, 3.0 * x + 2.0)
    assert abs(R_ - 1.0) < 1e-12 and abs(s - 3.0) < 1e-12 and abs(i0 - 2.0) < 1e-9
    assert abs(displaced_area.correlation(x, -x)[0] + 1.0) < 1e-12
    assert math.isnan(displaced_area.correlation([1.0], [2.0])[0])


def test_peak_mean_and_tau_from_constructed_record():
    # piecewise linear: (0,0) (1 mm, 40 kN/m) (20 mm, 20) (150 mm, 16) (300 mm, 13), uneven sampling
    yk = np.array([0, 1, 20, 150, 300]) * 1e-3
    Fk = np.array([0, 40, 20, 16, 13]) * 1e3
    y = np.unique(np.r_[yk, np.linspace(0, 1e-3, 3), np.geomspace(1e-3, 0.3, 57)])
    F = np.interp(y, yk, Fk)
    Fm, ym = loads.cohesive_peak(y, F)
    assert Fm == 40e3 and ym == 1e-3
    # trapezoids are exact on a piecewise-linear record whose knots are samples
    assert abs(loads.mean_load(y, F, 150e-3, 300e-3) - 14.5e3) < 1e-6
    assert abs(loads.load_at(y, F, 20e-3) - 20e3) < 1e-6
    with pytest.raises(ValueError, match="not covered"):
        loads.mean_load(y, F, 150e-3, 400e-3)
    # eq 15, h = 4 m: tau1 = 40/8 = 5 kPa; tau2 = (40 - 11)/8 = 3.625 kPa;
    # tau3: F_b = 0.75 * 90 * 9.81 * 20 = 13243.5 N/m -> (40000 - 13243.5)/8 = 3344.5625 Pa
    Fb3 = float(plug.buoyant_load(20.0, 0.25))
    t1, t2, t3 = shear_strength.three_strengths(Fm, 4.0, 11e3, Fb3)
    assert abs(t1 - 5000.0) < 1e-9 and abs(t2 - 3625.0) < 1e-9 and abs(t3 - 3344.5625) < 1e-9


def test_failure_mode_ratio_counts_fully_failed_only():
    mode = np.array([1, 1, 2, 0, 2, 1, 0])
    y_fail = np.array([1, 2, 3, np.nan, 4, np.nan, np.nan]) * 1e-3  # 6th: tensile code but not failed
    assert shear_strength.failure_mode_ratio(mode, y_fail) == (2, 2, 1.0)
    assert math.isnan(shear_strength.failure_mode_ratio(np.array([1, 1]))[2])  # n_s = 0


def test_tables_from_rows_by_hand():
    rows = []
    for ridge, f in (("1", 1.0), ("2", 2.0)):
        for mu, g in ((0.05, 1.0), (0.3, 1.1)):
            rows.append({"ridge": ridge, "mu": mu, "tau_cr_kPa": 50.0, "tau1_kPa": 4.0 * f * g,
                         "tau2_kPa": 3.0 * f * g, "tau3_kPa": 2.0 * f * g, "nt_ns": f,
                         "F_m_kN_per_m": 32.0 * f * g, "F_record_max_kN_per_m": 40.0 * f,
                         "tau1_record_max_kPa": 5.0 * f, "nt_ns_init": 2.0 * f, "failed_fraction": 0.25 * f,
                         "n_t": 3, "n_s": 1, "n_t_init": 10, "n_s_init": 0})
    t2 = shear_strength.table2(rows)[0]
    assert abs(t2["tau1_kPa"][0] - np.mean([4, 4.4, 8, 8.8])) < 1e-12
    assert abs(t2["tau1/tau3"] - 2.0) < 1e-12 and abs(t2["tau2/tau3"] - 1.5) < 1e-12
    # the record maximum and tau(1) from it beside: means of 40, 40, 80, 80 and 5, 5, 10, 10
    assert abs(t2["F_record_max_kN_per_m"][0] - 60.0) < 1e-12 and abs(t2["tau1_record_max_kPa"][0] - 7.5) < 1e-12
    assert abs(t2["F_m_kN_per_m"][0] - np.mean([32, 35.2, 64, 70.4])) < 1e-12
    t3 = shear_strength.table3(rows)[0]
    assert t3["n_pairs"] == 2
    assert abs(t3["tau3_kPa_ratio"][0] - 1.1) < 1e-12 and abs(t3["tau3_kPa_ratio"][1]) < 1e-12
    assert abs(t3["nt_ns"][0] - 1.5) < 1e-12
    assert abs(t3["nt_ns_init"][0] - 3.0) < 1e-12 and abs(t3["failed_fraction"][0] - 0.375) < 1e-12
    # summed counts show 40 : 0 where every per-run ratio is 10/0 = NaN
    assert (t3["n_t_sum"], t3["n_s_sum"], t3["n_t_init_sum"], t3["n_s_init_sum"]) == (12, 4, 40, 0)


def test_a_case_run_to_20_and_to_300_mm_counts_once_by_its_long_run():
    """Ridge 1 at mu 0.05 run to 20 mm (n_t/n_s 3) and from the same rest state to
    300 mm (1/3): Table 3 counts the 300 mm run only, and Table 2 the case once."""
    def row(ridge, travel, nt_ns, n_t, n_s, tau1):
        return {"ridge": ridge, "mu": 0.05, "tau_cr_kPa": 50.0, "y_I_end_mm": travel, "tau1_kPa": tau1,
                "tau2_kPa": 1.0, "tau3_kPa": 1.0, "F_m_kN_per_m": 8.0 * tau1, "F_record_max_kN_per_m": 8.0 * tau1,
                "tau1_record_max_kPa": tau1, "nt_ns": nt_ns, "nt_ns_init": 1.0, "failed_fraction": 0.5,
                "n_t": n_t, "n_s": n_s, "n_t_init": 1, "n_s_init": 1}
    rows = [row("1", 20.0, 3.0, 3, 1, 5.0), row("1", 300.0, 1 / 3, 1, 3, 5.0), row("2", 20.0, 2.0, 2, 1, 7.0)]
    t3 = shear_strength.table3(rows)[0]
    assert t3["n_runs"] == 2 and (t3["n_t_sum"], t3["n_s_sum"]) == (3, 4)
    assert abs(t3["nt_ns"][0] - (1 / 3 + 2.0) / 2) < 1e-12 and t3["y_I_end_mm"] == [20, 300]
    t2 = shear_strength.table2(rows)[0]
    assert t2["n_runs"] == 2 and abs(t2["tau1_kPa"][0] - 6.0) < 1e-12
    # the order of the rows does not choose
    assert shear_strength.table3(rows[::-1])[0]["n_t_sum"] == 3
