"""Indenter load analyses on an F-y_I record (paper Figs. 6-11, section 3.1).

All functions take plain arrays (y_I in m, down positive; F in N/m) so they serve
simulated and measured records alike.
"""
import numpy as np

# numpy 2 (a GPU machine's Python) renamed trapz; Debian's numpy 1.24 has trapz only
_trapezoid = getattr(np, "trapezoid", None) or np.trapz


def _check_record(y, F):
    y = np.asarray(y, dtype=float)
    F = np.asarray(F, dtype=float)
    if y.ndim != 1 or y.shape != F.shape or y.size < 2:
        raise ValueError("y_I and F must be 1-D arrays of equal length >= 2")
    if not (np.all(np.isfinite(y)) and np.all(np.isfinite(F))):
        raise ValueError("y_I and F must be finite")
    if np.any(np.diff(y) < 0):
        raise ValueError("y_I must be non-decreasing (indenter travel)")
    return y, F


# F^m is the cohesive peak. The paper's F^m comes at ~1 mm, "corresponded to the
# onset of the freeze bond failures" and "was also the maximum load in the
# simulations" (section 3.1.1). In our runs a late dynamic event (a block's pulse,
# a rattle, ridge 4's 49-83 kN/m at 12-18 mm) can exceed it, so the record maximum
# is not the paper's quantity: F^m is the maximum over the first 5 mm (five times
# the paper's ~1 mm, still inside the steep drop that lasts to ~20 mm). The record
# maximum is kept beside it (record_maximum).
COHESIVE_PEAK_TRAVEL = 5e-3  # m


def _maximum(y, F):
    i = int(np.argmax(F))
    return float(F[i]), float(y[i])


def cohesive_peak(y, F):
    """Peak load F^m and the travel y_I at which it occurs (Figs. 7, 8, 10, Table 2):
    the maximum over y_I <= COHESIVE_PEAK_TRAVEL, over the whole record if that
    is shorter. Returns (F_m [N/m], y_I_at_peak [m]); the first sample wins a tie."""
    y, F = _check_record(y, F)
    early = y <= COHESIVE_PEAK_TRAVEL
    if not early.any():
        raise ValueError(f"the record starts at y_I = {y[0] * 1e3:g} mm, after the cohesive-peak window "
                         f"0-{COHESIVE_PEAK_TRAVEL * 1e3:g} mm")
    return _maximum(y[early], F[early])


def record_maximum(y, F):
    """The maximum of the whole record and its y_I: (F [N/m], y_I [m]). The
    measured F^m of a field test (its peak came at 8.8-18.1 mm in Heinonen's
    tests), and in a simulation the check on whether a later event beat F^m."""
    return _maximum(*_check_record(y, F))


def load_at(y, F, y_I):
    """F at travel ``y_I`` [m] by linear interpolation, e.g. F(y_I = 20 mm) of Fig. 15.
    ValueError if ``y_I`` is outside the record."""
    y, F = _check_record(y, F)
    if not (y[0] <= y_I <= y[-1]):
        raise ValueError(f"y_I={y_I * 1e3:g} mm lies outside the record "
                         f"[{y[0] * 1e3:g}, {y[-1] * 1e3:g}] mm")
    return float(np.interp(y_I, y, F))


def mean_load(y, F, y_from, y_to):
    """Mean load over the travel interval [y_from, y_to] [m] (section 3.1.1: the mean
    for y_I = 150...300 mm), as the integral of F dy_I (trapezoids, with F
    interpolated at the ends) over the interval length, so uneven sampling does not
    bias it. ValueError if the record does not cover the interval.
    """
    y, F = _check_record(y, F)
    if not y_to > y_from:
        raise ValueError(f"interval end {y_to} must exceed its start {y_from}")
    if y_from < y[0] or y_to > y[-1]:
        raise ValueError(f"interval [{y_from * 1e3:g}, {y_to * 1e3:g}] mm not covered by the record "
                         f"[{y[0] * 1e3:g}, {y[-1] * 1e3:g}] mm")
    inside = (y > y_from) & (y < y_to)
    ys = np.concatenate(([y_from], y[inside], [y_to]))
    Fs = np.concatenate(([np.interp(y_from, y, F)], F[inside], [np.interp(y_to, y, F)]))
    return float(_trapezoid(Fs, ys) / (y_to - y_from))


def windowed_load(y, F, y_I, half_width):
    """Mean load over [y_I - half_width, y_I + half_width] [m] clipped to the record
    (mean_load), e.g. the F paired with F_d (Figs. 18, 20). ValueError if ``y_I`` is
    outside the record."""
    y, F = _check_record(y, F)
    if not half_width > 0:
        raise ValueError(f"half_width must be > 0 m, got {half_width}")
    if not (y[0] <= y_I <= y[-1]):
        raise ValueError(f"y_I={y_I * 1e3:g} mm lies outside the record "
                         f"[{y[0] * 1e3:g}, {y[-1] * 1e3:g}] mm")
    lo, hi = max(y[0], y_I - half_width), min(y[-1], y_I + half_width)
    if not hi > lo:   # a record of zero length
        return float(np.interp(y_I, y, F))
    return mean_load(y, F, lo, hi)


def record(run, y_max=None):
    """The F-y_I record of a run (Figs. 6, 7, 9), optionally cut at ``y_max`` [m].
    Returns (y_I [m], F [N/m])."""
    y, F = run.force_y, run.force_F
    if y_max is not None:
        keep = y <= y_max
        y, F = y[keep], F[keep]
    return y, F
