"""Rubble shear strength from the peak load (paper eq 15, Tables 2 and 3).

tau = (F^m - F_b) / A_s with A_s = 2 h (two vertical shear planes through the keel
depth h, the "cylindrical failure" in 2D). Three buoyant components F_b
(section 4.1.1):
  tau^(1): F_b = 0
  tau^(2): F_b = a cylindrical plug, a fixed load (the paper: ~11 kN/m)
  tau^(3): F_b = F_b(A_p, eta) of eq 13 with A_p at y_I = 20 mm
"""
import numpy as np

from icerubble.files.results import FailureMode

from .failure_plane import mean_sd

CYLINDRICAL_PLUG_FORCE = 11e3  # N/m, the paper's value for w_I = h = 4 m


def shear_strength(F_m, F_b, keel_depth):
    """tau = (F^m - F_b) / (2 h) [Pa] (eq 15), F in N/m, h in m."""
    if not keel_depth > 0:
        raise ValueError(f"keel_depth must be > 0, got {keel_depth}")
    return (np.asarray(F_m, dtype=float) - np.asarray(F_b, dtype=float)) / (2.0 * keel_depth)


def three_strengths(F_m, keel_depth, plug_force, F_b_plug):
    """(tau1, tau2, tau3) [Pa] of Table 2 for one peak load: F_b = 0, F_b =
    ``plug_force`` (cylindrical plug), F_b = ``F_b_plug`` (eq 13)."""
    return tuple(float(shear_strength(F_m, fb, keel_depth)) for fb in (0.0, plug_force, F_b_plug))


def _ratio(n_t, n_s):
    return n_t / n_s if n_s > 0 else np.nan


def failure_mode_ratio(mode, y_I_fail=None):
    """(n_t, n_s, n_t/n_s) by mode at full failure (Table 3; the paper: tensile "if
    delta_n >= |delta_t| at the end of the cohesive crack growth process"): mode 1
    tensile, 2 shear (docs/results_format.md). With ``y_I_fail`` only points that
    have a failure travel are counted. n_t/n_s is NaN when n_s = 0."""
    mode = np.asarray(mode)
    done = np.ones(mode.shape, dtype=bool)
    if y_I_fail is not None:
        done = np.isfinite(np.asarray(y_I_fail, dtype=float))
    n_t = int(np.count_nonzero(done & (mode == FailureMode.tensile)))
    n_s = int(np.count_nonzero(done & (mode == FailureMode.shear)))
    return n_t, n_s, _ratio(n_t, n_s)


def initiation_side_ratio(y_I_split, split_tn):
    """(n_t, n_s, n_t/n_s) by the side of eq 6 on which each split point reached
    the criterion: t_n >= 0 (tension side, the ellipse) against t_n < 0 (shear under
    compression). ``split_tn``: normal traction at the split [Pa], None for a file
    without it. All NaN when it is None or a split point lacks its traction (a
    count over part of the points would pass for the whole)."""
    split = np.isfinite(np.asarray(y_I_split, dtype=float))
    if split_tn is None:
        return np.nan, np.nan, np.nan
    tn = np.asarray(split_tn, dtype=float)[split]
    if not np.isfinite(tn).all():
        return np.nan, np.nan, np.nan
    n_t, n_s = int(np.count_nonzero(tn >= 0.0)), int(np.count_nonzero(tn < 0.0))
    return n_t, n_s, _ratio(n_t, n_s)


def failed_fraction(y_I_split, y_I_fail):
    """n_failed/n_split: the share of the split points that have fully failed, so a
    full-failure count taken from a small subset shows as such. NaN without splits."""
    n_split = np.count_nonzero(np.isfinite(np.asarray(y_I_split, dtype=float)))
    n_failed = np.count_nonzero(np.isfinite(np.asarray(y_I_fail, dtype=float)))
    return n_failed / n_split if n_split else np.nan


TAU_KEYS = ("tau1_kPa", "tau2_kPa", "tau3_kPa")
# beside Table 2: the peaks and tau^(1) from the record maximum (loads.record_maximum)
PEAK_KEYS = ("F_m_kN_per_m", "F_record_max_kN_per_m", "tau1_record_max_kPa")
# Table 3's failure-mode columns, mean ± sd over runs
MODE_KEYS = ("nt_ns", "nt_ns_init", "failed_fraction")


# A summary row keeps its numbers to this many significant digits (summary.csv);
# travels are compared at it, so that a run read from its file and the same run read
# back from its stored row have equal travels (the file, listed first, is then kept).
ROW_SIGNIFICANT_DIGITS = 6


def longer(travel_a, travel_b):
    """Whether travel_a is longer than travel_b at a summary row's precision."""
    return float(f"{travel_a:.{ROW_SIGNIFICANT_DIGITS}g}") > float(f"{travel_b:.{ROW_SIGNIFICANT_DIGITS}g}")


def longest_per_case(items, case, travel):
    """(kept, dropped): of the items of one case(item), the one of the longest
    travel(item), of equal ones (at a summary row's precision) the first, in
    order of each case's first appearance; dropped: (item set aside, item kept
    then) pairs. A study runs some cases twice, to 20 mm (Figs. 8-15) and to
    300 mm (Table 3), from one rest state, so both have the same first peak;
    counted twice, a case would weigh double in a mean over ridges, and the
    20 mm run's failure count would be mixed into the 300 mm one's."""
    kept, dropped = {}, []
    for item in items:
        k = case(item)
        if k not in kept:
            kept[k] = item
        elif longer(travel(item), travel(kept[k])):
            dropped.append((kept[k], item))
            kept[k] = item
        else:
            dropped.append((item, kept[k]))
    return list(kept.values()), dropped


def row_case(r):
    """A summary row's case: (model, force direction, ridge, mu, tau_cr)."""
    return r.get("model"), r.get("force_direction"), r["ridge"], float(r["mu"]), float(r["tau_cr_kPa"])


def row_travel(r):
    return r.get("y_I_end_mm", 0.0)


def one_run_per_case(rows):
    """One summary row per case (row_case), the longest run's (longest_per_case)."""
    return longest_per_case(rows, row_case, row_travel)[0]


def table2(rows, tau_cr_values=None):
    """Table 2 from per-run summary rows (postproc.summary): for each tau_cr [kPa],
    mean and sd of tau^(1..3) over all runs (both mu; one per case,
    one_run_per_case), and the ratios of the means tau1/tau3 and tau2/tau3.
    Returns a list of dicts, one per tau_cr."""
    rows = one_run_per_case(rows)
    if tau_cr_values is None:
        tau_cr_values = sorted({r["tau_cr_kPa"] for r in rows})
    out = []
    for tc in tau_cr_values:
        sel = [r for r in rows if np.isclose(r["tau_cr_kPa"], tc)]
        entry = {"tau_cr_kPa": tc, "n_runs": len(sel)}
        for k in TAU_KEYS + PEAK_KEYS:
            entry[k] = mean_sd([r[k] for r in sel])
        m1, m2, m3 = (entry[k][0] for k in TAU_KEYS)
        entry["tau1/tau3"] = m1 / m3 if m3 and np.isfinite(m3) else np.nan
        entry["tau2/tau3"] = m2 / m3 if m3 and np.isfinite(m3) else np.nan
        out.append(entry)
    return out


def table3(rows, mu_low=0.05, mu_high=0.3, tau_cr_values=None):
    """Table 3 from per-run summary rows: for each tau_cr [kPa], the ratio
    tau(mu_high)/tau(mu_low) of runs on the same ridge (mean and sd over ridges) for
    each tau measure; n_t/n_s at full failure and at initiation and the failed
    fraction (mean and sd over all runs of that tau_cr, one per case and the
    longest: one_run_per_case), the counts summed over those runs (a ratio with
    n_s = 0 is NaN, the sums still show it) and the travels they were counted over."""
    rows = one_run_per_case(rows)
    if tau_cr_values is None:
        tau_cr_values = sorted({r["tau_cr_kPa"] for r in rows})
    out = []
    for tc in tau_cr_values:
        sel = [r for r in rows if np.isclose(r["tau_cr_kPa"], tc)]
        entry = {"tau_cr_kPa": tc}
        low = {r["ridge"]: r for r in sel if np.isclose(r["mu"], mu_low)}
        high = {r["ridge"]: r for r in sel if np.isclose(r["mu"], mu_high)}
        ridges = sorted(set(low) & set(high))
        entry["n_pairs"] = len(ridges)
        for k in TAU_KEYS:
            ratios = [high[rd][k] / low[rd][k] for rd in ridges if low[rd][k]]
            entry[k + "_ratio"] = mean_sd(ratios)
        for k in MODE_KEYS:
            entry[k] = mean_sd([r[k] for r in sel])
        for k in ("n_t", "n_s", "n_t_init", "n_s_init"):
            entry[k + "_sum"] = float(np.sum([r[k] for r in sel]))
        entry["n_runs"] = len(sel)
        entry["y_I_end_mm"] = sorted({round(float(r.get("y_I_end_mm", np.nan))) for r in sel
                                      if np.isfinite(r.get("y_I_end_mm", np.nan))})
        out.append(entry)
    return out
