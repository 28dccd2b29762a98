"""A polygon's signed area and orientation: what the pile file's writer
(files/pile_file.py) and the geometry (geometry/pile.py) both need, kept below
both. Pure numpy, importable from inside ``yade``.
"""
import numpy as np


def polygon_area(p):
    """Signed area (shoelace); positive for counter-clockwise corners."""
    p = np.asarray(p, float)
    if len(p) < 3:
        return 0.0
    x, y = p[:, 0], p[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def ccw(p):
    """Same polygon, counter-clockwise."""
    p = np.asarray(p, float)
    return p if polygon_area(p) >= 0 else p[::-1].copy()
