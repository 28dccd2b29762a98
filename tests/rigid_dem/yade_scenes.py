"""YADE scenes for tests/rigid_dem/test_yade_coupling.py (run inside YADE:
`yade -n -x tests/rigid_dem/yade_scenes.py`, with SCENE and OUT in the environment).

two_blocks_coupled / two_blocks_yade_friction: two 1.2 m x 0.3 m blocks on a
fixed floor, settled, then pushed sideways in opposite directions at half the
friction limit for 1 s; friction from the project's law (coupled) or from
YADE's polyhedra law (frictionAngle = atan mu). Writes each block's x travel.

floating_block: a block released at the water line with buoyancy and linear
drag from the project's water law; writes its draft after 6 s.
rising_block: the block released 20 m down with quadratic drag; writes its
speed after 8 s.

turned_block_spin: a 2:1 block at 30 degrees (YADE turns its principal frame
so the prism's axis is body x) under a constant torque about z; writes its
angular velocity after 1 s and its moment of inertia about z.
ledger: two blocks, one tilted and spinning, thrown at each other on a floor,
half in water with linear drag and the project's friction, for 1 s; writes
the energy ledger (icerubble/rigid_dem/energy.py) at the end and its largest
residual on the way.
"""
import json
import math
import os
import sys

sys.path.insert(0, os.getcwd())  # the repository: run from its root

import yade  # noqa: F401  (inside yade already loaded)
import numpy as np
import yade.log
from yade import Vector3
from yade.wrapper import (O, PolyhedraMat, ForceResetter, InsertionSortCollider, Bo1_Polyhedra_Aabb,
                          InteractionLoop, Ig2_Polyhedra_Polyhedra_PolyhedraGeom,
                          Ip2_PolyhedraMat_PolyhedraMat_PolyhedraPhys,
                          Law2_PolyhedraGeom_PolyhedraPhys_Volumetric, NewtonIntegrator, PyRunner)

from icerubble.rigid_dem.energy import RigidLedger
from icerubble.rigid_dem.prisms import inertia_z, prism
from icerubble.rigid_dem.yade_coupling import Coupling

yade.log.setLevel('Polyhedra_support.cpp', yade.log.ERROR)

RHO_I, RHO_W, G, MU = 920.0, 1010.0, 9.81, 0.35
E = 2e8
W, H = 1.2, 0.3


def box(x0, x1, y0, y1):
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]


def two_blocks(coupled):
    mat = PolyhedraMat(density=RHO_I, young=E, poisson=0.3, frictionAngle=0.0 if coupled else math.atan(MU))
    O.materials.append(mat)
    floor = O.bodies.append(prism(mat, box(-4.0, 4.0, -0.5, 0.0), fixed=True))
    ids = O.bodies.append([prism(mat, box(-2.1, -0.9, 0.0, H)), prism(mat, box(0.9, 2.1, 0.0, H))])
    k_n = 0.5 * E
    dt = 0.5 * 2.0 / math.sqrt(4.0 * k_n / (RHO_I * H))
    O.dt = dt
    engines = [ForceResetter(),
               InsertionSortCollider([Bo1_Polyhedra_Aabb()], verletDist=0.01),
               InteractionLoop([Ig2_Polyhedra_Polyhedra_PolyhedraGeom()],
                               [Ip2_PolyhedraMat_PolyhedraMat_PolyhedraPhys()],
                               [Law2_PolyhedraGeom_PolyhedraPhys_Volumetric()])]
    global coupling, push
    coupling = Coupling([floor] + ids, mu=MU, k_t=k_n * H, dt=dt) if coupled else None
    mass = O.bodies[ids[0]].state.mass
    P = 0.5 * MU * mass * G
    push_on = [False]

    def push():
        if coupling is not None:
            coupling()
        if push_on[0]:
            O.forces.addF(ids[0], Vector3(P, 0, 0))
            O.forces.addF(ids[1], Vector3(-P, 0, 0))

    newton = NewtonIntegrator(damping=0.5, gravity=(0.0, -G, 0.0))
    O.engines = engines + [PyRunner(iterPeriod=1, command='push()'), newton]
    O.run(int(0.5 / dt), True)           # settle onto the floor
    newton.damping = 0.0
    x0 = [O.bodies[i].state.pos[0] for i in ids]
    push_on[0] = True
    O.run(int(1.0 / dt), True)
    return dict(travel=[O.bodies[i].state.pos[0] - x for i, x in zip(ids, x0)], push=P, mass=mass,
                k_t=k_n * H, steps=O.iter)


def block_in_water(y_centre, water_params, steps):
    """One 1.2 m x 0.3 m block centred at height y_centre under the project's water
    law (water line y = 0) and gravity, run `steps` steps of 1 ms; its final state."""
    mat = PolyhedraMat(density=RHO_I, young=E, poisson=0.3, frictionAngle=0.0)
    O.materials.append(mat)
    ids = O.bodies.append([prism(mat, box(-0.6, 0.6, y_centre - H / 2, y_centre + H / 2))])
    O.dt = 1e-3
    global coupling
    coupling = Coupling(ids, mu=0.0, k_t=1.0, dt=O.dt,
                        water=dict(params=dict(water_params, rho_w=RHO_W, rho_i=RHO_I, g=G), y_w=0.0))
    O.engines = [ForceResetter(), PyRunner(iterPeriod=1, command='coupling()'),
                 NewtonIntegrator(damping=0.0, gravity=(0.0, -G, 0.0))]
    O.run(steps, True)
    return O.bodies[ids[0]].state


def floating_block():
    s = block_in_water(0.0, dict(drag_model="linear", c_w=4e3), 6000)
    return dict(draft=0.0 - (s.pos[1] - H / 2), h=H, vy=s.vel[1], angle=s.ori.toAxisAngle()[1])


def rising_block():
    s = block_in_water(-20.0, dict(drag_model="quadratic", C_d=1.0), 8000)
    return dict(vy=s.vel[1], y=s.pos[1], w=W, h=H)


def turned(corners, degrees):
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    return [(c * x - s * y, s * x + c * y) for x, y in corners]


def turned_block_spin():
    mat = PolyhedraMat(density=RHO_I, young=E, poisson=0.3, frictionAngle=0.0)
    O.materials.append(mat)
    w, h, torque = 0.6, 0.3, 10.0
    i = O.bodies.append(prism(mat, turned(box(0.0, w, 0.0, h), 30.0)))
    O.dt = 1e-3
    global spin
    spin = lambda: O.forces.addT(i, Vector3(0.0, 0.0, torque))   # noqa: E731
    O.engines = [ForceResetter(), PyRunner(iterPeriod=1, command='spin()'),
                 NewtonIntegrator(damping=0.0, gravity=(0.0, 0.0, 0.0))]
    O.run(1, True)                       # YADE's first step turns nothing: count from after it
    w0 = O.bodies[i].state.angVel[2]
    O.run(1000, True)
    return dict(omega=O.bodies[i].state.angVel[2] - w0, torque=torque, t=1000 * O.dt,
                inertia_z=RHO_I * w * h * (w * w + h * h) / 12.0, yade_inertia=list(O.bodies[i].state.inertia))


def ledger():
    mat = PolyhedraMat(density=RHO_I, young=E, poisson=0.3, frictionAngle=0.0)
    O.materials.append(mat)
    floor = O.bodies.append(prism(mat, box(-4.0, 4.0, -0.5, 0.0), fixed=True))
    ids = O.bodies.append([prism(mat, box(-2.1, -0.9, 0.02, 0.02 + H)),
                           prism(mat, turned(box(-0.6, 0.6, -0.15, 0.15), 20.0))])
    O.bodies[ids[1]].state.pos += Vector3(1.5, 0.45, 0.0)
    O.bodies[ids[0]].state.vel = Vector3(1.0, 0.0, 0.0)
    O.bodies[ids[1]].state.vel = Vector3(-1.0, 0.0, 0.0)
    O.bodies[ids[1]].state.angVel = Vector3(0.0, 0.0, 2.0)
    k_n = 0.5 * E
    O.dt = 0.5 * 2.0 / math.sqrt(4.0 * k_n / (RHO_I * H))
    params = dict(rho_w=RHO_W, rho_i=RHO_I, g=G, drag_model="linear", c_w=2e3)
    global coupling, book
    coupling = Coupling(ids, mu=MU, k_t=k_n * H, dt=O.dt, water=dict(params=params, y_w=0.15))
    coupling.keep_terms = True
    bodies = [floor] + list(ids)
    free = np.array([False, True, True])
    led = RigidLedger(free, [], [O.bodies[i].state.mass for i in bodies],
                      [inertia_z(O.bodies[i]) for i in bodies], G, coupling.k_t)
    worst = [0.0]

    def energies(arrays):
        return led.energies(arrays[1], arrays[2], 0.0, coupling.friction.forces)

    def book():
        arrays = coupling.body_arrays()
        if led.pending is not None:
            led.advance(arrays[1], arrays[2], O.dt)
            worst[0] = max(worst[0], abs(energies(arrays)["residual"]))
        else:
            led.start(arrays[1], arrays[2], 0.0, coupling.friction.forces)
        coupling(arrays)
        led.hold(arrays[1], arrays[2], coupling.terms)

    O.engines = [ForceResetter(),
                 InsertionSortCollider([Bo1_Polyhedra_Aabb()], verletDist=0.01),
                 InteractionLoop([Ig2_Polyhedra_Polyhedra_PolyhedraGeom()],
                                 [Ip2_PolyhedraMat_PolyhedraMat_PolyhedraPhys()],
                                 [Law2_PolyhedraGeom_PolyhedraPhys_Volumetric()]),
                 PyRunner(iterPeriod=1, command='book()'),
                 NewtonIntegrator(damping=0.0, gravity=(0.0, -G, 0.0))]
    O.run(int(1.0 / O.dt), True)
    arrays = coupling.body_arrays()
    led.advance(arrays[1], arrays[2], O.dt)
    e = energies(arrays)
    return dict(e, initial=led.initial, worst_residual=worst[0])


scene = os.environ["SCENE"]
out = dict(two_blocks_coupled=lambda: two_blocks(True), two_blocks_yade_friction=lambda: two_blocks(False),
           floating_block=floating_block, rising_block=rising_block, turned_block_spin=turned_block_spin,
           ledger=ledger)[scene]()
with open(os.environ["OUT"], "w") as f:
    json.dump(out, f)
