"""A polygon's signed area, orientation and width: what the pile file's writer
(files/pile_file.py), the geometry (geometry/) and the rigid-block model
(rigid_dem/) need, kept below them all. Pure numpy, importable from inside ``yade``.
"""
import numpy as np

from .plain_products import dot2


def polygon_area(p):
    """Signed area (shoelace); positive for counter-clockwise corners."""
    p = np.asarray(p, float)
    if len(p) < 3:
        return 0.0
    x, y = p[:, 0], p[:, 1]
    # elementwise products and numpy's sums, not BLAS's dot, whose kernels the
    # processor picks (plain_products.py)
    return 0.5 * float(np.sum(x * np.roll(y, -1)) - np.sum(np.roll(x, -1) * y))


def ccw(p):
    """Same polygon, counter-clockwise."""
    p = np.asarray(p, float)
    return p if polygon_area(p) >= 0 else p[::-1].copy()


def min_width(p):
    """Smallest extent of a convex polygon across its edges [m] (0 for a
    degenerate one; edges of zero length have no direction and are skipped)."""
    p = np.asarray(p, float)
    widths = []
    for k in range(len(p)):
        e = p[(k + 1) % len(p)] - p[k]
        ln = np.hypot(*e)
        if ln == 0.0:
            continue
        d = dot2(p - p[k], np.array([-e[1], e[0]]) / ln)
        widths.append(d.max() - d.min())
    return float(min(widths)) if widths else 0.0
