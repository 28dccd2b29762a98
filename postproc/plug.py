"""Plug area A_p and its buoyant load F_b (paper Figs. 12, 14, 15; eq 13).

Construction of A_p (paper, section 3.2.1: "limited by the linear fits used to
define the angle alpha and the lines passing the uppermost and lowermost failed
bond on each side of the indenter"; Fig. 12: "a four-sided polygon with two edges
aligned with the linear fits"). Exactly:

- top edge: the straight line through the uppermost failed bond point on the left
  (x < -w_I/2) and the uppermost failed bond point on the right (x > +w_I/2);
- bottom edge: the straight line through the lowermost failed bond points of the
  two sides;
- side edges: the two least-squares lines of failure_plane (x = a + b y);
- the four corners are where the top and bottom lines cut the fitted lines, and
  A_p is the area of that quadrilateral (shoelace formula).

When the bond points lie on the fitted lines the corners are the bond points
themselves. A_p is a bulk area (rubble and voids), hence the (1 - eta) in eq 13.
"""
import numpy as np

from icerubble.parameters import GRAVITY as G, RHO_I, RHO_W  # Table 1

from . import failure_plane


def _cut(p1, p2, fit):
    """Point where the line through p1, p2 meets x = fit.a + fit.b * y."""
    (x1, y1), (x2, y2) = p1, p2
    dx, dy = x2 - x1, y2 - y1
    den = dx - fit.b * dy
    if abs(den) < 1e-12 * max(abs(dx), abs(dy), 1.0):
        return None
    t = (fit.a + fit.b * y1 - x1) / den
    return np.array([x1 + t * dx, y1 + t * dy])


def plug_polygon(left, right):
    """Corners (4, 2) of the plug, counter-clockwise from the top left, or None when
    a side has no fit or the quadrilateral would not be simple (fits crossing)."""
    if left is None or right is None:
        return None
    top = ((left.x_top, left.y_top), (right.x_top, right.y_top))
    bottom = ((left.x_bottom, left.y_bottom), (right.x_bottom, right.y_bottom))
    tl, tr = _cut(*top, left), _cut(*top, right)
    bl, br = _cut(*bottom, left), _cut(*bottom, right)
    if any(p is None for p in (tl, tr, bl, br)):
        return None
    if not (tl[0] < tr[0] and bl[0] < br[0]):
        return None
    return np.array([tl, bl, br, tr])


def polygon_area(corners):
    """Shoelace area [m^2] of a simple polygon."""
    x, y = np.asarray(corners, dtype=float).T
    return float(0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def plug_area_from_points(points, indenter_width, min_points=failure_plane.MIN_POINTS):
    """A_p [m^2] (Fig. 12) from failed bond point positions; NaN when it cannot be made."""
    left, right = failure_plane.fit_planes(points, indenter_width, min_points)
    corners = plug_polygon(left, right)
    return polygon_area(corners) if corners is not None else np.nan


def plug_area(run, y_I, bond_points=failure_plane.DEFAULT_BOND_POINTS, min_points=failure_plane.MIN_POINTS):
    """A_p [m^2] of a run at travel ``y_I`` [m] (Figs. 14, 15); ``bond_points`` as in
    failure_plane."""
    pts = failure_plane.failed_points(run.bonds, y_I, bond_points)
    return plug_area_from_points(pts, run.indenter_width, min_points)


def buoyant_load(area, porosity, rho_w=RHO_W, rho_i=RHO_I, g=G):
    """F_b(A_p, eta) = (1 - eta)(rho_w - rho_i) g A_p [N/m] (eq 13); with A = A_d it is
    F_d of eq 14. ``area`` is a bulk area [m^2] (solid and voids)."""
    if not 0.0 <= porosity < 1.0:
        raise ValueError(f"porosity must be in [0, 1), got {porosity}")
    if not rho_w > rho_i > 0.0:
        raise ValueError(f"need rho_w > rho_i > 0, got rho_w={rho_w}, rho_i={rho_i}")
    return (1.0 - porosity) * (rho_w - rho_i) * g * np.asarray(area, dtype=float)


def run_buoyant_load(run, area):
    """eq 13 with the run's porosity, densities and g."""
    return buoyant_load(area, run.porosity, run.param("rho_w", RHO_W),
                        run.param("rho_i", RHO_I), run.param("g", G))


def trapezoid_plug_area(indenter_width, keel_depth, alpha_deg):
    """Plug area [m^2] of a trapezoid that starts at the indenter width at the keel top
    and widens by tan(alpha) on each side down to the keel bottom:
    A_p = h (w_I + h tan(alpha)). alpha = 0 gives the cylindrical plug w_I h
    (section 4.1.1). Used when no failed bond points exist (measured data)."""
    if indenter_width <= 0 or keel_depth <= 0:
        raise ValueError("indenter_width and keel_depth must be > 0")
    if not 0.0 <= alpha_deg < 90.0:
        raise ValueError(f"alpha must be in [0, 90) degrees, got {alpha_deg}")
    return keel_depth * (indenter_width + keel_depth * np.tan(np.radians(alpha_deg)))
