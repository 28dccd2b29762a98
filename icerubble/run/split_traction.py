"""The traction at which each bond point split (/bonds/split_tn, split_tt).

The engine keeps it per cohesive pair (pair_split_tn, pair_split_tt). A point
splits as a whole: one check of eq 5 evaluates every pair of the point, and if
any pair reaches the criterion all of them split at that step, each storing the
traction of that same check (engine/src/bonds/freeze_bonds.cpp point_ratio,
bond_split.cpp split_points). So no pair of a point splits "first"; the pair
that decided the split is the one with the largest effective traction t_e
(eq 6), the engine's own measure of how far a point is past eq 5. An ordinary
point has one pair; only junction points have a choice to make.
"""
import numpy as np

from icerubble import cohesive_law


def point_split_traction(pair_point, pair_tn, pair_tt, sigma_cr, tau_cr, mu):
    """(split_tn, split_tt) [Pa] per bond point: the pair traction with the largest
    t_e (eq 6) among the point's pairs; NaN for a point that never split.

    pair_point: bond point of each pair; pair_tn, pair_tt: traction at the split
    per pair (NaN if not split); sigma_cr, tau_cr: per point [Pa]; mu: the
    friction of the criterion's compressive side."""
    pair_point = np.asarray(pair_point, dtype=np.int64)
    tn = np.asarray(pair_tn, dtype=float)
    tt = np.asarray(pair_tt, dtype=float)
    sigma_cr = np.asarray(sigma_cr, dtype=float)
    tau_cr = np.asarray(tau_cr, dtype=float)
    if not (pair_point.shape == tn.shape == tt.shape) or pair_point.ndim != 1:
        raise ValueError("pair_point, pair_tn and pair_tt must be 1-D arrays of one length (one entry per pair)")
    P = len(sigma_cr)
    if pair_point.size and (pair_point.min() < 0 or pair_point.max() >= P):
        raise ValueError(f"pair_point must lie in [0, {P}) (one entry per bond point in sigma_cr)")
    out_tn = np.full(P, np.nan)
    out_tt = np.full(P, np.nan)
    split = np.isfinite(tn) & np.isfinite(tt)
    if not split.any():
        return out_tn, out_tt
    k = np.flatnonzero(split)
    p = pair_point[k]
    t_e = np.asarray(cohesive_law.effective_traction(tn[k], tt[k], sigma_cr[p], tau_cr[p], mu), dtype=float)
    # per point, the largest t_e; the lowest pair index wins a tie (stable sort)
    order = np.lexsort((-t_e, p))
    first = np.r_[True, p[order][1:] != p[order][:-1]]
    best = k[order[first]]
    out_tn[pair_point[best]] = tn[best]
    out_tt[pair_point[best]] = tt[best]
    return out_tn, out_tt
