"""The per-step exchange between a YADE scene of rigid prisms and the project's
laws: YADE supplies the bodies' motion and each contact's geometry and normal
force (its polyhedra law, run frictionless); the engine returns the friction
(one history per contact) and the water's buoyancy and drag; they go back to
YADE as forces and torques on the bodies.

Only for use inside YADE (`yade -n -x script.py`): import it after yade.

    water = dict(params={...}, y_w=0.0)            # or None: no water
    bonds = dict(a=..., b=..., position=..., normal=..., k=..., l=..., sigma_cr=..., tau_cr=...,
                 mu=..., G=..., direction="paper")  # body ids are YADE ids; or None
    coupling = Coupling(block_ids, mu=0.3, k_t=1e8, dt=O.dt, water=water, bonds=bonds)
    O.engines = [..., InteractionLoop(...), PyRunner(iterPeriod=1, command='coupling()'),
                 NewtonIntegrator(damping=0, gravity=(0, -g, 0))]

Prisms are 1 m deep (z from -0.5 to 0.5), so every force is per metre of
width, as in the FEM-DEM. The Python loop over interactions only reads YADE's
state; the laws run in C++ over arrays.
"""
import numpy as np
from yade import Quaternion, Vector3
from yade.wrapper import O

from .. import _engine
from .water import BlockWater


def prism_corners(body):
    """A prism's outline as placed now: the corners of its z > 0 face relative to
    its centroid, counter-clockwise, in world axes. (YADE turns a polyhedron's
    body frame to its principal axes, which may put the prism's axis along
    body x or y: only world coordinates tell the outline.)"""
    s = body.state
    w = [s.ori * v for v in body.shape.v]
    xy = np.array([(p[0], p[1]) for p in w if p[2] > 0.0])
    c = xy.mean(axis=0)
    return xy[np.argsort(np.arctan2(xy[:, 1] - c[1], xy[:, 0] - c[0]))]


class Coupling:
    """Friction between all bodies and, optionally, water on the `block_ids` and
    freeze bonds (anchored where the bodies are when the coupling is made)."""

    def __init__(self, block_ids, mu, k_t, dt, water=None, bonds=None):
        if not mu >= 0.0:
            raise ValueError(f"mu must be >= 0 (got {mu})")
        if not k_t > 0.0:
            raise ValueError(f"k_t must be > 0 N/m per m width (got {k_t})")
        if not dt > 0.0:
            raise ValueError(f"dt must be > 0 s (got {dt})")
        self.mu, self.k_t, self.dt = float(mu), float(k_t), float(dt)
        self.states = [b.state for b in O.bodies]
        # every angle is measured from the pose each body has now
        self.ori0 = [Quaternion(s.ori) for s in self.states]
        self.friction = _engine.RigidFriction()
        self.blocks = np.asarray(block_ids, int)
        self.dry = np.zeros(len(self.blocks), bool)   # per entry of block_ids
        self.degenerate = 0   # contacts YADE gave no finite geometry (skipped)
        self.keep_terms, self.terms = False, None   # per-law forces, for an energy ledger
        self.water = None
        if water is not None:
            # corners as placed now: world = pos + R(theta) corner, theta the turn since
            polys = [prism_corners(O.bodies[int(i)]) for i in self.blocks]
            self.water = BlockWater(polys, water["params"], water["y_w"])
        self.bonds = None
        if bonds is not None:
            self.bonds = self._make_bonds(bonds)

    def _make_bonds(self, bd):
        """RigidBonds anchored in both bodies' frames at their present poses."""
        pos, _, _, theta = self.body_arrays()
        a, b = np.asarray(bd["a"], np.int32), np.asarray(bd["b"], np.int32)
        p, n = np.asarray(bd["position"], float), np.asarray(bd["normal"], float)

        def to_frame(ids, v):   # R(theta)^T v
            c, s = np.cos(theta[ids]), np.sin(theta[ids])
            return np.column_stack([c * v[:, 0] + s * v[:, 1], -s * v[:, 0] + c * v[:, 1]])

        return _engine.RigidBonds(a, b, to_frame(a, p - pos[a]), to_frame(b, p - pos[b]), to_frame(a, n),
                                  np.asarray(bd["k"], float), np.asarray(bd["l"], float),
                                  np.asarray(bd["sigma_cr"], float), np.asarray(bd["tau_cr"], float),
                                  np.asarray(bd["mu"], float), np.asarray(bd["G"], float),
                                  n_bodies=len(self.states), direction=bd.get("direction", "paper"))

    def _theta(self, i):
        """Body i's turn about z since the coupling was made [rad]: the in-plane
        angle of ori(t) ori0^-1 (motion is in the plane, so that is about z)."""
        v = (self.states[i].ori * self.ori0[i].conjugate()) * Vector3(1.0, 0.0, 0.0)
        return float(np.arctan2(v[1], v[0]))

    def body_arrays(self, turns=True):
        """Every body's centroid, velocity, angular velocity and turn since the
        coupling was made: (pos (n, 2), vel (n, 2), omega (n,), theta (n,));
        theta None without `turns` (friction alone does not read it, and its
        quaternions are most of this call's cost)."""
        st = self.states
        pos = np.array([(s.pos[0], s.pos[1]) for s in st])
        vel = np.array([(s.vel[0], s.vel[1]) for s in st])
        omega = np.array([s.angVel[2] for s in st])
        theta = np.array([self._theta(i) for i in range(len(st))]) if turns else None
        return pos, vel, omega, theta

    def stick(self, pairs):
        """Make these body pairs (YADE ids, either order) stick at any
        tangential force from now on: no Coulomb cap (phase 1's hold stage).
        Returns how many pairs stick now."""
        p = np.sort(np.asarray(pairs, np.int32).reshape(-1, 2), axis=1)
        self.friction.stick(p[:, 0], p[:, 1])
        return len(self.friction.stuck)

    def contact_arrays(self):
        a, b, p, n, fn = [], [], [], [], []
        for i in O.interactions:
            if not i.isReal:
                continue
            f = i.phys.normalForce.norm()
            if f == 0.0:
                continue
            g = i.geom
            nx, ny = g.normal[0], g.normal[1]
            cp = g.contactPoint
            if not (np.isfinite(nx) and np.isfinite(ny) and np.isfinite(cp[0]) and np.isfinite(cp[1])
                    and np.isfinite(f) and nx * nx + ny * ny > 0.0):
                # YADE's polyhedra intersection degenerates for faces touching
                # exactly edge on edge (a zero or NaN normal): no friction there this step
                self.degenerate += 1
                continue
            id1, id2 = i.id1, i.id2
            if id1 > id2:  # the engine wants a < b with the normal from a to b
                id1, id2, nx, ny = id2, id1, -nx, -ny
            s = np.hypot(nx, ny)
            a.append(id1)
            b.append(id2)
            p.append((cp[0], cp[1]))
            n.append((nx / s, ny / s))
            fn.append(f)
        k = len(a)
        return (np.array(a, np.int32), np.array(b, np.int32), np.array(p).reshape(k, 2),
                np.array(n).reshape(k, 2), np.array(fn))

    def __call__(self, arrays=None):
        """One step's exchange; `arrays`: this step's body_arrays() if the caller
        has read them already. With `keep_terms` set, each law's per-body
        (fx, fy, tz) is kept in `terms` (for an energy ledger), and YADE's own
        (normal) contact forces as read before any of them is added."""
        turns = self.water is not None or self.bonds is not None
        pos, vel, omega, theta = self.body_arrays(turns) if arrays is None else arrays
        terms = {} if self.keep_terms else None
        if terms is not None:
            terms["contact"] = self.yade_forces()
        a, b, p, n, fn = self.contact_arrays()
        _, fx, fy, tz = self.friction.step(a, b, p[:, 0], p[:, 1], n[:, 0], n[:, 1], fn, pos[:, 0], pos[:, 1],
                                           vel[:, 0], vel[:, 1], omega, self.dt, self.k_t, self.mu)
        if terms is not None:
            terms["friction"] = (fx.copy(), fy.copy(), tz.copy())
        if self.water is not None:
            k = self.blocks
            args = (pos[k, 0], pos[k, 1], theta[k], vel[k, 0], vel[k, 1], omega[k])
            wx, wy, wt = self.water.forces(*args)
            dry = self.dry   # bodies the water is not applied to (e.g. a driven indenter)
            wx[dry], wy[dry], wt[dry] = 0.0, 0.0, 0.0
            fx[k] += wx
            fy[k] += wy
            tz[k] += wt
            if terms is not None:
                # buoyancy alone, and the drag as the rest (the same sums)
                bx, by, bt = self.water.forces(*args, drag=False)
                bx[dry], by[dry], bt[dry] = 0.0, 0.0, 0.0
                terms["buoyancy"] = self._on_bodies(k, bx, by, bt)
                terms["drag"] = self._on_bodies(k, wx - bx, wy - by, wt - bt)
        if self.bonds is not None:
            bx, by, bt = self.bonds.step(pos[:, 0], pos[:, 1], theta, O.time)
            fx += bx
            fy += by
            tz += bt
            if terms is not None:
                terms["bond"] = (bx, by, bt)
        self.terms = terms
        addF, addT = O.forces.addF, O.forces.addT
        for i in np.flatnonzero((fx != 0.0) | (fy != 0.0) | (tz != 0.0)):
            addF(int(i), Vector3(fx[i], fy[i], 0.0))
            addT(int(i), Vector3(0.0, 0.0, tz[i]))

    def _on_bodies(self, ids, fx, fy, tz):
        n = len(self.states)
        out = np.zeros(n), np.zeros(n), np.zeros(n)
        for o, v in zip(out, (fx, fy, tz)):
            o[ids] = v
        return out

    def yade_forces(self):
        """Every body's force and torque from YADE's engines this step so far
        (its contact law's normal forces, before the coupling adds anything)."""
        n = len(self.states)
        f, t = O.forces.f, O.forces.t
        out = np.empty((n, 3))
        for i in range(n):
            v, w = f(i, sync=True), t(i)
            out[i] = v[0], v[1], w[2]
        return out[:, 0], out[:, 1], out[:, 2]
