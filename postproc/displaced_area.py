"""Displaced rubble area A_d(K, y_I), its buoyant load F_d, and the F-A_d
correlation (paper Figs. 17, 18, 20; eq 14).

A_d(K, y_I): the rubble displaced downward by more than K y_I, from the u_y field
of the snapshot at y_I: the keel block elements (body kind 0) whose centroid moved
down by -u_y > K y_I (strict, as the paper's "u_y > 0.5 x 100 mm").

Solid or bulk area: the sum of the selected element areas is SOLID ice area,
whereas eq 14 multiplies by (1 - eta) as for the bulk polygon A_p of eq 13. To keep
eq 14 right, A_d is reported as a BULK area, A_d = A_solid / (1 - eta) (the pile's
porosity spread evenly), so F_d = (1 - eta)(rho_w - rho_i) g A_d = (rho_w - rho_i) g
A_solid. ``basis="solid"`` returns the plain element-area sum.

The F paired with F_d (Figs. 18, 20): the mean load over y_I ± 5 mm (paired_load),
not the one sample at y_I: post-peak F rattles by ~2.8 kN/m (sd) from sample to
sample while F_d changes by ~0.25 kN/m, so single samples would measure the
rattle and hide the correlation the paper reports.
"""
import numpy as np

from icerubble.files.results import BLOCK

from . import loads, plug

# Fig. 20: K = {0.1, 0.45, 0.9}, y_I = {20, 30, ..., 150} mm
FIG20_K = (0.1, 0.45, 0.9)
FIG20_TRAVELS = np.arange(20, 151, 10) * 1e-3
# Half width of the travel window F is averaged over: the snapshots lie 10 mm
# apart, so the windows of neighbouring snapshots just meet and never overlap.
LOAD_WINDOW_HALF_WIDTH = 5e-3  # m


def paired_load(run, y_I):
    """F̄(y_I) [N/m]: the run's mean load over [y_I - 5 mm, y_I + 5 mm] clipped to
    its record (loads.windowed_load). ValueError if y_I is outside the record."""
    return loads.windowed_load(run.force_y, run.force_F, y_I, LOAD_WINDOW_HALF_WIDTH)


def solid_displaced_area(area, kind, u_y, K, y_I):
    """Sum of the areas [m^2] of block elements with -u_y > K y_I (Fig. 17)."""
    if not 0.0 <= K <= 1.0:
        raise ValueError(f"K must be in [0, 1], got {K}")
    if y_I <= 0:
        raise ValueError(f"y_I must be > 0, got {y_I}")
    area = np.asarray(area, dtype=float)
    sel = (np.asarray(kind) == BLOCK) & (-np.asarray(u_y, dtype=float) > K * y_I)
    return float(area[sel].sum())


def displaced_area(run, K, y_I, basis="bulk"):
    """A_d(K, y_I) [m^2] of a run (Figs. 17, 18, 20), from the snapshot nearest y_I
    (see RunResult.nearest_snapshot); NaN when the run has no such snapshot.
    The threshold uses the snapshot's own y_I."""
    if basis not in ("bulk", "solid"):
        raise ValueError(f"basis must be 'bulk' or 'solid', got {basis!r}")
    snap = run.nearest_snapshot(y_I)
    if snap is None:
        return np.nan
    u = run.u_elem(snap)
    a = solid_displaced_area(run.elem_area, run.elem_kind, u[:, 1], K, snap.y_I)
    return a / (1.0 - run.porosity) if basis == "bulk" else a


def displaced_areas(run, Ks, travels, basis="bulk"):
    """A_d [m^2] as an array (len(travels), len(Ks)), reading each snapshot once;
    rows of travels without a snapshot are NaN."""
    out = np.full((len(travels), len(Ks)), np.nan)
    for i, y_I in enumerate(travels):
        snap = run.nearest_snapshot(y_I)
        if snap is None:
            continue
        u_y = run.u_elem(snap)[:, 1]
        for j, K in enumerate(Ks):
            out[i, j] = solid_displaced_area(run.elem_area, run.elem_kind, u_y, K, snap.y_I)
    return out / (1.0 - run.porosity) if basis == "bulk" else out


def displaced_load(run, K, y_I):
    """F_d(K, y_I) = (1 - eta)(rho_w - rho_i) g A_d [N/m] (eq 14)."""
    return float(plug.run_buoyant_load(run, displaced_area(run, K, y_I)))


def displaced_loads(run, Ks, travels):
    """F_d [N/m] (eq 14) as an array (len(travels), len(Ks)) from displaced_areas,
    each snapshot read once; rows of travels without a snapshot are NaN."""
    return plug.run_buoyant_load(run, displaced_areas(run, Ks, travels))


def correlation(x, y):
    """Pearson correlation R and least-squares line y = slope x + intercept (Fig. 20).
    Returns (R, slope, intercept); NaNs when fewer than 2 finite pairs or no spread."""
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    ok = np.isfinite(x) & np.isfinite(y)
    x, y = x[ok], y[ok]
    if x.size < 2 or np.ptp(x) == 0.0:
        return np.nan, np.nan, np.nan
    slope, intercept = np.polyfit(x, y, 1)
    R = np.nan if np.ptp(y) == 0.0 else float(np.corrcoef(x, y)[0, 1])
    return R, float(slope), float(intercept)
