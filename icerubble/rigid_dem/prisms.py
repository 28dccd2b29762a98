"""YADE prisms for the rigid model (docs/model.md §6): a block's outline made a
convex 1 m prism, and the steps that put a rigid ridge (scene.rigid_scene)
into a YADE scene: bodies, stable step, bond arrays. The punch-through driver
(punch_through.py) and the FEM-DEM state loader (yade_state.py) both build
their scenes from these. Only inside YADE.
"""
import math

import numpy as np
from yade import Vector3, polyhedra_utils
from yade.wrapper import O

from ..polygon import min_width
from .scene import INSET, KIND_BLOCK, KIND_LAYER

DT_SAFETY = 0.5


def prism(mat, corners, fixed=False):
    """A polygon extruded from z = -0.5 to 0.5 m (1 m of width); a free one moves in the plane only.

    With rotations about x and y blocked, YADE's NewtonIntegrator turns a body
    as a sphere: omega_z += T_z dt / inertia[2], inertia being the principal
    moments in the body frame. YADE may have turned that frame so that the
    prism's axis is body x or y (it does for any block not aligned with the
    axes), and then inertia[2] is not the moment about z: a 2:1 block turned
    3x too slowly. Every entry is set to the moment about world z, the only
    turn the block has."""
    b = polyhedra_utils.polyhedra(mat, v=[Vector3(float(x), float(y), z) for (x, y) in corners
                                          for z in (-0.5, 0.5)], fixed=fixed)
    if not fixed:
        b.state.blockedDOFs = 'zXY'
        i_z = inertia_z(b)
        b.state.inertia = Vector3(i_z, i_z, i_z)
    return b


def inertia_z(body):
    """A body's moment of inertia about the world z axis [kg m² per m of width]:
    YADE keeps it in the body's principal frame, which it may have turned so
    that the prism's axis is body x or y."""
    s = body.state
    axes = (Vector3(1, 0, 0), Vector3(0, 1, 0), Vector3(0, 0, 1))
    return sum(s.inertia[k] * (s.ori * axes[k])[2] ** 2 for k in range(3))


def convex_outline(poly, straight=1e-3):
    """The convex hull of a polygon, counter-clockwise, without corners that turn
    by less than `straight` radians (YADE polyhedra are convex; near-straight
    corners make its intersections degenerate). Returns (outline, hull area /
    polygon area - 1)."""
    from scipy.spatial import ConvexHull
    q = np.asarray(poly, float)
    h = q[ConvexHull(q).vertices]           # counter-clockwise in 2D
    while len(h) > 3:
        u = h - np.roll(h, 1, axis=0)
        v = np.roll(h, -1, axis=0) - h
        turn = np.arctan2(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0], (u * v).sum(axis=1))
        k = int(np.argmin(turn))
        if turn[k] >= straight:
            break
        h = np.delete(h, k, axis=0)

    def area(a):
        return 0.5 * np.sum(a[:, 0] * np.roll(a[:, 1], -1) - np.roll(a[:, 0], -1) * a[:, 1])
    return h, area(h) / area(q) - 1.0


def polygon_inset(poly, d):
    """A convex counter-clockwise polygon moved inward by d on every edge."""
    q = np.asarray(poly, float)
    e = np.roll(q, -1, axis=0) - q
    n = np.column_stack([-e[:, 1], e[:, 0]]) / np.hypot(e[:, 0], e[:, 1])[:, None]   # inward (CCW)
    p = q + d * n                       # a point on each shifted edge line
    out = []
    for i in range(len(q)):
        j = i - 1                        # edges j (into vertex i) and i (out of it)
        A = np.column_stack([e[j], -e[i]])
        t = np.linalg.solve(A, p[i] - p[j])
        out.append(p[j] + t[0] * e[j])
    return np.array(out)


def place_bodies(mat, sc):
    """Every body of `sc` appended to O.bodies as a prism:
    returns (YADE ids, outlines as placed, hull area gain per body)."""
    kind = sc["body_kind"]
    hulls = [convex_outline(q) for q in sc["polygons"]]
    polys = [polygon_inset(h[0], INSET) for h in hulls]
    bodies = [prism(mat, poly, fixed=kind[b] == KIND_LAYER) for b, poly in enumerate(polys)]
    bodies[sc["indenter"]].state.blockedDOFs = 'xzXYZ'
    ids = np.asarray(O.bodies.append(bodies), int)
    return ids, polys, np.array([h[1] for h in hulls])


def rigid_step(sc, ids, polys):
    """The rigid step for bodies placed by place_bodies: (dt [s], thinnest block t_min [m])."""
    p, kind = sc["params"], sc["body_kind"]
    k_n = 0.5 * p["E"]
    t_min = min(min_width(sc["polygons"][b]) for b in np.flatnonzero(kind == KIND_BLOCK))
    dt = 2.0 / math.sqrt(4.0 * k_n / (p["rho_i"] * t_min))
    # each body on its bond springs (Gershgorin): k_t = beta k or beta^2 k
    beta = sc["tau_cr"] / sc["sigma_cr"]
    k_max = sc["bond_k"] * np.maximum(1.0, beta if p["force_direction"] == "paper" else beta * beta)
    K = np.zeros(len(kind))
    np.add.at(K, sc["bond_a"], k_max)
    np.add.at(K, sc["bond_b"], k_max)
    for b in np.flatnonzero((K > 0) & (kind != KIND_LAYER)):
        body = O.bodies[int(ids[b])]
        s = body.state
        r = max(np.hypot(*(polys[b] - (s.pos[0], s.pos[1])).T))
        dt = min(dt, 2.0 / math.sqrt(2.0 * K[b] * (1.0 / s.mass + r * r / inertia_z(body))))
    return DT_SAFETY * dt, t_min


def bond_arrays(sc, ids):
    """The Coupling's `bonds` of `sc`, with YADE ids for its bodies."""
    return dict(a=ids[sc["bond_a"]], b=ids[sc["bond_b"]], position=sc["bond_position"], normal=sc["bond_normal"],
                k=sc["bond_k"], l=sc["bond_length"], sigma_cr=sc["sigma_cr"], tau_cr=sc["tau_cr"],
                mu=sc["mu"], G=sc["G"], direction=sc["params"]["force_direction"])
