"""Buoyancy and water drag on rigid blocks: the FEM-DEM laws integrated over a
rigid polygon (engine/src/rigid/rigid_water.hpp), per metre of width.

    w = BlockWater(polygons, params, y_w)       # polygons: list of (k, 2) corners [m]
    fx, fy, tz = w.forces(cx, cy, theta, ux, uy, omega)

`polygons` are the blocks as placed at theta = 0 (e.g. the pile's corners);
each block's centroid there is its reference point, `BlockWater.centroid`.
"""
import numpy as np

from .. import _engine
from .. import parameters as P


def polygon_frame(corners):
    """(area, centroid, corners relative to the centroid, counter-clockwise) of a
    simple polygon; ValueError for fewer than 3 corners or zero area."""
    c = np.asarray(corners, float)
    if c.ndim != 2 or c.shape[1] != 2 or len(c) < 3:
        raise ValueError(f"a block polygon needs >= 3 corners as a (k, 2) array (got shape {c.shape})")
    x, y = c[:, 0], c[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    a = 0.5 * cross.sum()
    if not abs(a) > 0.0:
        raise ValueError("a block polygon has zero area")
    if a < 0:  # clockwise: reverse
        return polygon_frame(c[::-1])
    cen = np.array([((x + xn) * cross).sum(), ((y + yn) * cross).sum()]) / (6.0 * a)
    return a, cen, c - cen


class BlockWater:
    """The water law of a set of rigid blocks: parameters `params` (icerubble.parameters:
    rho_w, g, drag_model, c_w, C_d), water line y_w [m]."""

    def __init__(self, polygons, params, y_w, threads=1):
        p = P.validate(params)
        if not np.isfinite(y_w):
            raise ValueError(f"y_w (water line) must be finite (got {y_w})")
        if int(threads) < 1:
            raise ValueError(f"threads must be >= 1 (got {threads})")
        self.y_w = float(y_w)
        frames = [polygon_frame(c) for c in polygons]
        self.area = np.array([f[0] for f in frames])
        self.centroid = np.array([f[1] for f in frames]).reshape(-1, 2)
        local = [f[2] for f in frames]
        self.offset = np.concatenate([[0], np.cumsum([len(c) for c in local])]).astype(np.int32)
        corners = np.vstack(local) if local else np.zeros((0, 2))
        self.vx, self.vy = corners[:, 0].copy(), corners[:, 1].copy()
        self.params = p
        self.threads = int(threads)
        self.drag = True   # False: buoyancy only (the settle of a punch-through)

    def forces(self, cx, cy, theta, ux, uy, omega, buoyancy=True, drag=None):
        """(fx, fy, tz) of the water on every block [N/m, N/m, N m/m] at centroid
        positions (cx, cy), angles theta from the reference, centroid velocities
        (ux, uy) and angular velocities omega; `buoyancy`, `drag` (default: the
        `.drag` switch) to take one of the two alone."""
        p = self.params
        drag = self.drag if drag is None else drag
        return _engine.rigid_water_forces(
            self.offset, self.vx, self.vy, self.area, cx, cy, theta, ux, uy, omega,
            y_w=self.y_w, rho_w=p["rho_w"], g=p["g"], buoyancy=buoyancy,
            drag_model=p["drag_model"] if drag else "none", c_w=p["c_w"], C_d=p["C_d"], threads=self.threads)
