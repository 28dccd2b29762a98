"""The per-step exchange between a YADE scene of rigid prisms and the project's
laws: YADE supplies the bodies' motion and each contact's geometry and normal
force (its polyhedra law, run frictionless); the engine returns the friction
(one history per contact) and the water's buoyancy and drag; they go back to
YADE as forces and torques on the bodies.

Only for use inside YADE (`yade -n -x script.py`): import it after yade.

    water = dict(params={...}, y_w=0.0)            # or None: no water
    coupling = Coupling(block_ids, mu=0.3, k_t=1e8, dt=O.dt, water=water)
    O.engines = [..., InteractionLoop(...), PyRunner(iterPeriod=1, command='coupling()'),
                 NewtonIntegrator(damping=0, gravity=(0, -g, 0))]

Prisms are 1 m deep (z from -0.5 to 0.5), so every force is per metre of
width, as in the FEM-DEM. The Python loop over interactions only reads YADE's
state; the laws run in C++ over arrays.
"""
import numpy as np
from yade import Vector3
from yade.wrapper import O

from .. import _engine
from .water import BlockWater


def prism_corners(body):
    """A prism's outline in its body frame: the z > 0 face, counter-clockwise,
    relative to the centroid (YADE keeps polyhedra vertices about it)."""
    xy = np.array([(v[0], v[1]) for v in body.shape.v if v[2] > 0.0])
    c = xy.mean(axis=0)
    return xy[np.argsort(np.arctan2(xy[:, 1] - c[1], xy[:, 0] - c[0]))]


class Coupling:
    """Friction between all bodies and, optionally, water on the `block_ids`."""

    def __init__(self, block_ids, mu, k_t, dt, water=None):
        if not mu >= 0.0:
            raise ValueError(f"mu must be >= 0 (got {mu})")
        if not k_t > 0.0:
            raise ValueError(f"k_t must be > 0 N/m per m width (got {k_t})")
        if not dt > 0.0:
            raise ValueError(f"dt must be > 0 s (got {dt})")
        self.mu, self.k_t, self.dt = float(mu), float(k_t), float(dt)
        self.states = [b.state for b in O.bodies]
        self.friction = _engine.RigidFriction()
        self.blocks = np.asarray(block_ids, int)
        self.water = None
        if water is not None:
            # corners in each body's frame: world = pos + R(theta) corner, theta the
            # angle of the body's orientation (YADE may start it off zero: principal axes)
            polys = [prism_corners(O.bodies[int(i)]) for i in self.blocks]
            self.water = BlockWater(polys, water["params"], water["y_w"])

    @staticmethod
    def _theta(state):
        q = state.ori
        # yade Quaternion: (axis, angle); a prism turns about z only
        axis, angle = q.toAxisAngle()
        return float(angle) * (1.0 if axis[2] >= 0 else -1.0)

    def body_arrays(self):
        st = self.states
        pos = np.array([(s.pos[0], s.pos[1]) for s in st])
        vel = np.array([(s.vel[0], s.vel[1]) for s in st])
        omega = np.array([s.angVel[2] for s in st])
        return pos, vel, omega

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
            id1, id2 = i.id1, i.id2
            if id1 > id2:  # the engine wants a < b with the normal from a to b
                id1, id2, nx, ny = id2, id1, -nx, -ny
            s = np.hypot(nx, ny)
            a.append(id1)
            b.append(id2)
            p.append((g.contactPoint[0], g.contactPoint[1]))
            n.append((nx / s, ny / s))
            fn.append(f)
        k = len(a)
        return (np.array(a, np.int32), np.array(b, np.int32), np.array(p).reshape(k, 2),
                np.array(n).reshape(k, 2), np.array(fn))

    def __call__(self):
        pos, vel, omega = self.body_arrays()
        a, b, p, n, fn = self.contact_arrays()
        _, fx, fy, tz = self.friction.step(a, b, p[:, 0], p[:, 1], n[:, 0], n[:, 1], fn, pos[:, 0], pos[:, 1],
                                           vel[:, 0], vel[:, 1], omega, self.dt, self.k_t, self.mu)
        if self.water is not None:
            k = self.blocks
            theta = np.array([self._theta(self.states[int(i)]) for i in k])
            wx, wy, wt = self.water.forces(pos[k, 0], pos[k, 1], theta, vel[k, 0], vel[k, 1], omega[k])
            fx[k] += wx
            fy[k] += wy
            tz[k] += wt
        addF, addT = O.forces.addF, O.forces.addT
        for i in np.flatnonzero((fx != 0.0) | (fy != 0.0) | (tz != 0.0)):
            addF(int(i), Vector3(fx[i], fy[i], 0.0))
            addT(int(i), Vector3(0.0, 0.0, tz[i]))
