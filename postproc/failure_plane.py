"""Failure-plane angle alpha from failed bond points (paper Figs. 12 and 13).

Which bond points count as "failed" at travel y_I (``bond_points``):
  "split"  (default, the paper's): the failure criterion (eq 5) was reached, the
           point split and its cohesive crack grows: ``y_I_split <= y_I``. The paper
           fits alpha from y_I = 1 mm, where by its own softening law (delta_f of
           ~1-3 mm) no tension-opened bond can have fully failed yet: its "failed
           freeze bond points" are points where failure began.
  "failed" the cohesive force has vanished (delta_e = delta_f): ``y_I_fail <= y_I``.
           By 40 mm only 20-35 % of the split points have got there.

The lines are near vertical, so x is fitted as a function of y by least squares:
x = a + b y, one line for bond points with x < -w_I/2 and one for x > +w_I/2.
alpha is the angle of the line to the vertical, positive when the line moves away
from the indenter centre line as it goes down (the plug widens with depth):
right side alpha = atan(-b), left side alpha = atan(+b).
"""
from dataclasses import dataclass

import numpy as np

# A line through two points always fits exactly and says nothing about a plane.
MIN_POINTS = 3

# bond_points choice: (the /bonds travel from which a point counts, its name on figures)
BOND_POINTS = {"split": ("y_I_split", "split bond points (eq 5 reached)"),
               "failed": ("y_I_fail", "fully failed bond points")}
DEFAULT_BOND_POINTS = "split"


def check_bond_points(bond_points):
    """``bond_points`` itself, or ValueError naming the valid choices."""
    if bond_points not in BOND_POINTS:
        raise ValueError(f"bond_points must be one of {', '.join(map(repr, BOND_POINTS))}, "
                         f"got {bond_points!r}")
    return bond_points


@dataclass
class SideFit:
    """x = a + b*y through the failed bond points on one side of the indenter."""
    side: int            # -1 left (x < -w_I/2), +1 right (x > +w_I/2)
    a: float             # m
    b: float             # dx/dy [-]
    n: int               # number of bond points fitted
    y_top: float         # y of the uppermost failed bond point on this side [m]
    y_bottom: float      # y of the lowermost one [m]
    x_top: float         # x of that uppermost bond point [m]
    x_bottom: float      # x of that lowermost bond point [m]

    @property
    def alpha(self):
        """Angle to the vertical [deg], positive away from the centre line (Fig. 12)."""
        return float(np.degrees(np.arctan(-self.side * self.b)))

    def x_at(self, y):
        return self.a + self.b * np.asarray(y, dtype=float)


def failed_points(bonds, y_I, bond_points=DEFAULT_BOND_POINTS):
    """Positions (P', 2) of the bond points counted as failed at travel ``y_I`` [m]
    (``bond_points``: see module doc)."""
    travel = np.asarray(bonds[BOND_POINTS[check_bond_points(bond_points)][0]], dtype=float)
    with np.errstate(invalid="ignore"):   # NaN: never happened
        done = travel <= y_I
    return np.asarray(bonds["position"], dtype=float)[done]


def fit_side(points, side, indenter_width, min_points=MIN_POINTS):
    """Least-squares line x = a + b y through the points on one side (Fig. 12).

    side -1 takes x < -w_I/2, +1 takes x > +w_I/2. Returns None when fewer than
    ``min_points`` points lie there or their y values are all equal (no line).
    """
    if side not in (-1, 1):
        raise ValueError(f"side must be -1 (left) or +1 (right), got {side}")
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    sel = pts[side * pts[:, 0] > indenter_width / 2]
    if len(sel) < max(2, min_points):
        return None
    x, y = sel[:, 0], sel[:, 1]
    if np.ptp(y) == 0.0:
        return None
    b, a = np.polyfit(y, x, 1)
    top, bottom = int(np.argmax(y)), int(np.argmin(y))
    return SideFit(side=side, a=float(a), b=float(b), n=len(sel),
                   y_top=float(y[top]), y_bottom=float(y[bottom]),
                   x_top=float(x[top]), x_bottom=float(x[bottom]))


def fit_planes(points, indenter_width, min_points=MIN_POINTS):
    """(left SideFit or None, right SideFit or None) for the failed bond points."""
    return (fit_side(points, -1, indenter_width, min_points),
            fit_side(points, +1, indenter_width, min_points))


def alpha_at(run, y_I, bond_points=DEFAULT_BOND_POINTS, min_points=MIN_POINTS):
    """(alpha_left, alpha_right) [deg] of a run at travel ``y_I`` [m]; NaN for a side
    without a fit."""
    pts = failed_points(run.bonds, y_I, bond_points)
    fits = fit_planes(pts, run.indenter_width, min_points)
    return tuple(f.alpha if f is not None else np.nan for f in fits)


# Fig. 13: y_I = 1...20 mm; every millimetre is an instant.
ALPHA_TRAVELS = np.arange(1, 21) * 1e-3


def alpha_samples(run, travels=ALPHA_TRAVELS, bond_points=DEFAULT_BOND_POINTS, min_points=MIN_POINTS):
    """All alpha values [deg] of a run over ``travels`` (both sides pooled, NaNs dropped):
    the data behind one run's contribution to Fig. 13."""
    vals = []
    for y_I in travels:
        vals.extend(alpha_at(run, y_I, bond_points, min_points))
    vals = np.asarray(vals, dtype=float)
    return vals[np.isfinite(vals)]


def mean_sd(values):
    """Mean and sample standard deviation (ddof=1; NaN sd for one value)."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v)]
    if v.size == 0:
        return np.nan, np.nan
    return float(v.mean()), float(v.std(ddof=1)) if v.size > 1 else np.nan


def pooled_mean_sd(parts):
    """mean_sd of the samples of several runs pooled, from each run's (n, mean, sd)
    alone (a summary row's alpha_n, alpha_mean, alpha_sd): the same numbers as
    mean_sd of the samples themselves, since the sum of squares about the pooled
    mean splits into each part's own and its mean's offset."""
    parts = [(int(n), float(m), float(s)) for n, m, s in parts if np.isfinite(n) and n > 0]
    N = sum(n for n, _, _ in parts)
    if N == 0:
        return np.nan, np.nan
    mean = sum(n * m for n, m, _ in parts) / N
    if N == 1:
        return mean, np.nan
    ss = sum((n - 1) * (s * s if n > 1 else 0.0) + n * (m - mean) ** 2 for n, m, s in parts)
    return mean, float(np.sqrt(ss / (N - 1)))
