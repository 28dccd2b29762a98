"""Freeze-bond cohesive law (Polojärvi & Tuhkuri 2013, eqs 5-12), Python side.

A thin layer over the compiled ``icerubble._cohesive_law``: every function takes
array-likes that broadcast against each other and returns numpy arrays; the loops
run in C++. Signs and axes: ``delta = x+ - x-``, ``n`` the bond normal from the
- side to the + side, ``t = (-n_y, n_x)``; the law's force ``(f_n, f_t)`` points
along the opening (eq 11) and acts as ``-f`` on node + and ``+f`` on node -.
Full description, choices and the energy caveat: docs/cohesive_law.md.

Force directions (``direction=``):
  ``"paper"``          eq 11 as printed (default): work over a full opening is
                       G l in tension but G l / beta in pure shear;
  ``"work_conjugate"`` Ortiz & Pandolfi (1999): work is G l on every path.
"""
import numpy as np

from icerubble import _cohesive_law as _law

TENSILE = _law.TENSILE
SHEAR = _law.SHEAR
DIRECTIONS = ("paper", "work_conjugate")

OpenedBondPoints = _law.OpenedBondPoints
ElasticBondPoints = _law.ElasticBondPoints

effective_opening = _law.effective_opening
failure_mode = _law.failure_mode
critical_opening = _law.critical_opening
initial_effective_force = _law.initial_effective_force
work_increment = _law.work_increment
stored_energy = _law.stored_energy
opening_components = _law.opening_components
nodal_forces = _law.nodal_forces
depth_factor = _law.depth_factor
min_elastic_stiffness = _law.min_elastic_stiffness


def effective_traction(t_n, t_t, sigma_cr, tau_cr, mu):
    """Effective traction t_e of eq 6 [Pa] (tension positive t_n).

    ``sqrt(t_t**2/beta**2 + t_n**2)`` for t_n >= 0, ``(|t_t| - mu |t_n|)/beta`` for
    t_n < 0, with beta = tau_cr/sigma_cr.
    """
    return _law.effective_traction(t_n, t_t, sigma_cr, tau_cr, mu)


def criterion_reached(t_n, t_t, sigma_cr, tau_cr, mu):
    """Eq 5: boolean array, True where the bond point starts to open (t_e >= sigma_cr)."""
    return _law.criterion_reached(t_n, t_t, sigma_cr, tau_cr, mu)


def initial_force_magnitude(m_plus, m_minus, f_plus, f_minus):
    """Eq 8: |f_c^0| = |-(m-/m) f+ + (m+/m) f-| [N/m].

    ``f_plus``, ``f_minus``: internal force vectors of the elements on each side
    of the split, shape (..., 2).
    """
    f_plus = np.asarray(f_plus, dtype=float)
    f_minus = np.asarray(f_minus, dtype=float)
    if f_plus.shape[-1:] != (2,) or f_minus.shape[-1:] != (2,):
        raise ValueError("f_plus and f_minus must have shape (..., 2) (x, y components)")
    return _law.initial_force_magnitude(m_plus, m_minus, f_plus[..., 0], f_plus[..., 1],
                                        f_minus[..., 0], f_minus[..., 1])


def strength_at_depth(depth, keel_depth, sigma_cr_top, tau_cr_top, G_top,
                      bottom_fraction=0.1):
    """sigma_cr, tau_cr and G at the given depths below the keel top (docs/model.md §2).

    Linear from the top value to ``bottom_fraction`` of it at ``keel_depth``,
    clipped outside the keel. Returns a dict of arrays.
    """
    for name, v in (("sigma_cr_top", sigma_cr_top), ("tau_cr_top", tau_cr_top),
                    ("G_top", G_top)):
        if not (np.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be finite and > 0 (got {v})")
    k = depth_factor(depth, keel_depth, bottom_fraction)
    return {"sigma_cr": sigma_cr_top * k, "tau_cr": tau_cr_top * k, "G": G_top * k}
