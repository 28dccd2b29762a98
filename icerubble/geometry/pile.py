"""Rubble pile of phase 1 (paper section 2.4): block generation and keel porosity.

Pure numpy, importable from /usr/bin/python3 and from inside ``yade``.
A *block* is a convex polygon given by its corners (k, 2), counter-clockwise.
The pile file: icerubble/files/pile_file.py.
"""
from __future__ import annotations

import numpy as np


from ..parameters import LAYER_THICKNESS, RHO_I, RHO_W, require_range
from ..polygon import ccw, polygon_area  # noqa: F401 (pile.ccw, pile.polygon_area)
from ..plain_products import dot2, rotated

# Paper section 2.4.
BLOCK_THICKNESS = (0.2, 0.4)
BLOCK_LENGTH = (0.6, 1.8)


def layer_bottom_y(layer_thickness=LAYER_THICKNESS, rho_i=RHO_I, rho_w=RHO_W):
    """y of the consolidated layer bottom (= keel top): -d, d = (rho_i/rho_w) t_c."""
    return -(rho_i / rho_w) * layer_thickness


# ---------------------------------------------------------------- validation

def validate_block_sizes(t_min, t_max, l_min, l_max):
    require_range("t_min (block thickness, m)", t_min, 0.0, lo_open=True)
    require_range("t_max (block thickness, m)", t_max, t_min)
    require_range("l_min (block length, m)", l_min, 0.0, lo_open=True)
    require_range("l_max (block length, m)", l_max, l_min)
    if l_min < t_max:
        raise ValueError(f"l_min = {l_min} must be >= t_max = {t_max} (a block's length is its long side)")


# ---------------------------------------------------------------- geometry

def rectangle(center, length, thickness, angle):
    """Corners (4, 2) of a length x thickness rectangle rotated by angle (rad), CCW."""
    c, s = np.cos(angle), np.sin(angle)
    hx, hy = 0.5 * length, 0.5 * thickness
    local = np.array([[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]])
    rot = np.array([[c, -s], [s, c]])
    return np.asarray(center, float) + rotated(local, rot)  # plain arithmetic, not BLAS (plain_products.py)


def clip_halfplane(poly, n, c):
    """Part of convex polygon `poly` with n.x <= c (Sutherland-Hodgman, one edge)."""
    out = []
    m = len(poly)
    for i in range(m):
        a, b = poly[i], poly[(i + 1) % m]
        da, db = dot2(n, a) - c, dot2(n, b) - c
        if da <= 0:
            out.append(a)
        if (da < 0 < db) or (db < 0 < da):
            out.append(a + (b - a) * (da / (da - db)))
    return np.array(out).reshape(-1, 2)


def clip_box(poly, x0, x1, y0, y1):
    """Part of convex polygon `poly` inside the axis-aligned box."""
    p = np.asarray(poly, float)
    for n, c in (((1.0, 0.0), x1), ((-1.0, 0.0), -x0), ((0.0, 1.0), y1), ((0.0, -1.0), -y0)):
        if len(p) == 0:
            break
        p = clip_halfplane(p, np.array(n), c)
    return p


# ---------------------------------------------------------------- generation

def _profiles(poly, xs):
    """Upper and lower boundary y of convex polygon `poly` at abscissae xs.

    A corner lying between two samples also counts at both, so that comparing
    intervals [xs[k], xs[k+1]] through these values is conservative.
    """
    up = np.full(len(xs), -np.inf)
    lo = np.full(len(xs), np.inf)
    m = len(poly)
    for k in range(m):
        a, b = poly[k], poly[(k + 1) % m]
        if a[0] != b[0]:
            x0, x1 = min(a[0], b[0]), max(a[0], b[0])
            sel = (xs >= x0) & (xs <= x1)
            y = a[1] + (b[1] - a[1]) * (xs[sel] - a[0]) / (b[0] - a[0])
            up[sel] = np.maximum(up[sel], y)
            lo[sel] = np.minimum(lo[sel], y)
        j = np.searchsorted(xs, a[0])
        for jj in (j - 1, j):
            if 0 <= jj < len(xs):
                up[jj] = max(up[jj], a[1])
                lo[jj] = min(lo[jj], a[1])
    return up, lo


def compact_start(n_blocks, domain_width, top_y, rng, t_range=BLOCK_THICKNESS,
                  l_range=BLOCK_LENGTH, max_tilt=np.radians(30.0), gap=0.03, n_area=None,
                  resolution=0.02):
    """Compact start of phase 1: random blocks already "risen" into rough place.

    Blocks (thickness and length uniform in the ranges, tilt uniform in +-max_tilt)
    are taken one by one; each goes to the horizontal position where, moved straight
    up, it stops highest, `gap` below the ice above it (the layer bottom `top_y` or
    blocks placed before): a geometric version of the rise, so YADE only has to
    settle a nearly dense pile. A compact start settles in seconds of
    simulated time where a tall random column needs tens (docs/yade_notes.md).
    If `n_blocks` is None, blocks are added until their area reaches `n_area` (m^2).
    Returns (corners (n,4,2), thickness, length, angle).
    """
    validate_block_sizes(t_range[0], t_range[1], l_range[0], l_range[1])
    if domain_width < l_range[1] + 2 * gap:
        raise ValueError(f"domain_width = {domain_width} m must exceed the longest block "
                         f"l_max = {l_range[1]} m plus gaps")
    if n_blocks is None and not (n_area and n_area > 0):
        raise ValueError("give n_blocks > 0 or an ice area n_area > 0")
    x_left = -0.5 * domain_width + gap
    x_right = 0.5 * domain_width - gap
    xs = np.arange(x_left, x_right + 0.5 * resolution, resolution)
    sky = np.full(len(xs), top_y)  # lowest ice so far in each column
    corners, ts, ls, angs = [], [], [], []
    area = 0.0
    while (n_blocks is not None and len(corners) < n_blocks) or \
          (n_blocks is None and area < n_area):
        t = rng.uniform(*t_range)
        ln = rng.uniform(*l_range)
        a = rng.uniform(-max_tilt, max_tilt)
        w = ln * abs(np.cos(a)) + t * abs(np.sin(a))
        k = int(np.ceil(w / resolution)) + 1  # samples cover the whole block
        local = xs[:k] - xs[0]
        poly = rectangle((0.5 * w, 0.0), ln, t, a)
        up, lo = _profiles(poly, local)
        up_iv = np.maximum(up[:-1], up[1:])  # per interval between samples
        sky_iv = np.minimum(sky[:-1], sky[1:])
        # every horizontal position: how far up the block rises there
        win = np.lib.stride_tricks.sliding_window_view(sky_iv, k - 1)
        rise = np.min(win - gap - up_iv[None, :], axis=1)
        best = np.flatnonzero(rise >= rise.max() - 0.01)  # highest, ties at random
        j = best[rng.integers(len(best))]
        poly[:, 0] += xs[j]
        poly[:, 1] += rise[j]
        fin = np.isfinite(lo)
        seg = sky[j:j + k]
        seg[fin] = np.minimum(seg[fin], lo[fin] + rise[j])
        corners.append(poly)
        ts.append(t), ls.append(ln), angs.append(a)
        area += t * ln
    return np.array(corners), np.array(ts), np.array(ls), np.array(angs)


def blocks_for_keel(domain_width, keel_depth, porosity):
    """Ice area (m^2) that fills a keel of that depth at that porosity."""
    return (1.0 - porosity) * domain_width * keel_depth


# ---------------------------------------------------------------- keel region

def keel_bounds(polygons, keel_top_y, x_min, x_max, column_width=0.5):
    """Keel region (x_min, x_max, bottom_y, top_y).

    The keel bottom of a ragged pile is taken as the mean, over columns of width
    `column_width` across [x_min, x_max], of the lowest ice point in the column
    (a column without ice counts depth 0). Documented in docs/pile_and_mesh.md.
    """
    ncol = max(1, int(round((x_max - x_min) / column_width)))
    edges = np.linspace(x_min, x_max, ncol + 1)
    lowest = np.full(ncol, keel_top_y)
    for p in polygons:
        pxmin, pxmax = p[:, 0].min(), p[:, 0].max()
        for j in range(ncol):
            if edges[j + 1] <= pxmin or edges[j] >= pxmax:
                continue
            q = clip_box(p, edges[j], edges[j + 1], -np.inf, np.inf)
            if len(q) >= 3:
                lowest[j] = min(lowest[j], q[:, 1].min())
    return float(x_min), float(x_max), float(lowest.mean()), float(keel_top_y)


def porosity(polygons, bounds):
    """eta = void area / total area of the keel region (paper section 2.4, Table 1).

    `polygons` must not overlap (or overlap negligibly: phase-1 contact overlaps
    are ~1e-4 of the block area and are counted twice).
    """
    x0, x1, y0, y1 = bounds
    total = (x1 - x0) * (y1 - y0)
    if not total > 0:
        raise ValueError(f"keel region {bounds} has no area")
    ice = sum(abs(polygon_area(clip_box(p, x0, x1, y0, y1))) for p in polygons)
    return 1.0 - ice / total


