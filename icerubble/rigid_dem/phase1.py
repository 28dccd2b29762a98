"""Phase 1 (paper section 2.4): rigid blocks float up under the consolidated layer into a pile.
Only inside YADE; yade_scripts/make_pile.py reads a table line and calls make_pile().

Model (2D, per metre of width; every block is a YADE polyhedron, a rectangle
extruded 1 m in z, motion in the x-y plane only):
- blocks are rigid_dem/prisms.py's prisms (their moment of inertia about z set,
  whichever way YADE turned their body frame);
- net buoyancy (rho_w - rho_i) g V upward on every block, applied as NewtonIntegrator
  gravity g_net = +(rho_w - rho_i)/rho_i g on bodies of density rho_i: no Python per step;
- the consolidated layer (bottom at y = -d) and two side walls at x = +-W/2 are fixed
  polyhedra, so the keel spans the domain width as in the paper;
- soft contacts (E_settle, normal force = E/2 x overlap volume) and Cundall local damping
  (NewtonIntegrator.damping) dissipate the kinetic energy: a settling device, not water drag.
  The pile is re-meshed afterwards, so the soft contact only sets the (mm) overlaps;
- friction: YADE 2023.02a polyhedra friction is wrong with more than one contact
  (docs/yade_notes.md), so the law runs frictionless and Coulomb friction mu_settle is
  added each step by the rigid-block model's own law (rigid_dem/yade_coupling.py's
  Coupling, engine rigid/rigid_friction.hpp: an elastic-plastic tangential spring per
  contact, Cundall-Strack in 2D, tangential stiffness k_n t_min). Friction jams the pile; a frictionless
  pile creeps for tens of seconds and ends denser (porosity ~0.14 on the demo pile).
  mu_settle defaults to 0.05, the lowest friction of the paper's study: one pile per
  ridge is run at every mu of the study, and a pile at rest within the 0.05 friction
  cone is at rest within any wider one. A pile settled at 0.3 holds blocks that slide
  at 0.05 (a corner-supported block of the small ridge 1 slid 10 cm in 5 s of the
  FEM-DEM settle and was still going). The pile file records it as `friction`.
- the hold stage (mu_hold >= 0; the paper scene's piles): after the rise at mu_settle,
  contacts with a common face of hold_bond_length or more (where the mesher bonds)
  stick and all others slide at mu_hold, until the pile is at rest again: at rest at
  mu_hold with its freeze bonds (docs/pile_and_mesh.md, "The paper scene's piles").
  hold_from runs this stage alone on a pile file made before.
Settled when the kinetic energy per block stays below ke_per_block for n_quiet checks.
"""
import builtins
import os
import time

import numpy as np
import yade
import yade.config
from yade import Vector3
from yade.wrapper import (O, PolyhedraMat, ForceResetter, InsertionSortCollider, Bo1_Polyhedra_Aabb,
                          InteractionLoop, Ig2_Polyhedra_Polyhedra_PolyhedraGeom,
                          Ip2_PolyhedraMat_PolyhedraMat_PolyhedraPhys,
                          Law2_PolyhedraGeom_PolyhedraPhys_Volumetric, NewtonIntegrator,
                          PyRunner)

from .. import machine
from ..files.pile_file import read_pile, write_pile
from ..geometry import pile
from ..parameters import PILE, PILE_SHARED, check_value, require_range
from .prisms import prism
from .yade_coupling import Coupling, prism_corners


def validate(P):
    """Each parameter against its registry range, then what ties them together."""
    for k, spec in PILE.items():
        check_value(k, getattr(P, k), spec)
    for k in PILE_SHARED:
        check_value(k, getattr(P, k))
    pile.validate_block_sizes(P.t_min, P.t_max, P.l_min, P.l_max)
    if P.mu_hold >= 0.0:
        require_range("mu_hold", P.mu_hold, 0.0, P.mu_settle)   # a hold at more friction holds nothing more
    if P.hold_from and not os.path.isfile(P.hold_from):
        raise ValueError(f"hold_from = {P.hold_from!r} is not a file")
    if P.hold_from and P.mu_hold < 0.0:
        raise ValueError("hold_from needs mu_hold >= 0 (the friction to hold its blocks at)")
    require_range("rho_w (kg/m^3)", P.rho_w, P.rho_i, lo_open=True)  # blocks must float


def box(x0, x1, y0, y1):
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]


def world_corners(b):
    """Settled block outline: the z > 0 face of the prism, in world x-y, counter-clockwise."""
    p = b.state.pos
    return np.array([p[0], p[1]]) + prism_corners(b)


def contact_chord(c1, c2, normal):
    """Length of the common face of two touching convex blocks (corners CCW):
    the extent of their overlap along the contact plane (soft contacts overlap
    by mm along a face, by a corner's width at a corner)."""
    p = c1
    m = len(c2)
    for k in range(m):   # clip c1 by every edge of c2 (inside: left of the edge)
        a, b = c2[k], c2[(k + 1) % m]
        n = np.array([b[1] - a[1], a[0] - b[0]])   # outward normal of a CCW edge
        p = pile.clip_halfplane(p, n, float(n @ a))
        if len(p) == 0:
            return 0.0
    t = np.array([-normal[1], normal[0]])
    d = p @ t
    return float(d.max() - d.min())


def freeze_face_contacts(friction, outlines, walls, hold_bond_length):
    """Freeze every contact with a common face of hold_bond_length or more
    (where the mesher will bond them): it sticks at any tangential force; blocks
    against the phase-1 side walls (absent in phase 2) stay frictional. Returns
    how many were frozen."""
    pairs = []
    for i in O.interactions:
        if not i.isReal or i.phys.normalForce.norm() == 0.0 or i.id1 in walls or i.id2 in walls:
            continue
        n = i.geom.normal
        if contact_chord(outlines(i.id1), outlines(i.id2), (n[0], n[1])) >= hold_bond_length:
            pairs.append((i.id1, i.id2))
    return friction.stick(pairs)


def make_pile(P, description=""):
    """The pile of parameters P (a table line: yade.params.table), written to
    P.out (else pile_<description>.h5). ValueError for a bad parameter, before
    any work; RuntimeError if the settle goes unstable."""
    validate(P)
    t_wall0 = time.time()
    rng = np.random.default_rng(int(P.seed))
    top = pile.layer_bottom_y(P.layer_thickness, P.rho_i, P.rho_w)
    if P.hold_from:   # the blocks of a pile settled before: only the hold stage runs
        before = read_pile(P.hold_from)
        corners, ts, ls = before["corners"], before["thickness"], before["length"]
        if abs(float(before["meta"]["domain_width"]) - P.domain_width) > 1e-9:
            raise ValueError(f"hold_from {P.hold_from!r} is {before['meta']['domain_width']} m wide, "
                             f"domain_width is {P.domain_width} m")
    else:
        n_req = int(P.n_blocks) if int(P.n_blocks) > 0 else None
        area = None if n_req else pile.blocks_for_keel(P.domain_width, P.keel_depth, P.porosity_guess)
        corners, ts, ls, _ = pile.compact_start(
            n_req, P.domain_width, top, rng, (P.t_min, P.t_max), (P.l_min, P.l_max),
            np.radians(P.max_tilt), n_area=area)
    n = len(corners)

    O.reset()
    mat_ice = PolyhedraMat(density=P.rho_i, young=P.E_settle, poisson=0.3, frictionAngle=0.0)
    O.materials.append(mat_ice)
    W, bottom = P.domain_width, corners[:, :, 1].min() - 1.0
    O.bodies.append([
        prism(mat_ice, box(-0.5 * W - 2.0, 0.5 * W + 2.0, top, top + P.layer_thickness), fixed=True),
        prism(mat_ice, box(-0.5 * W - 1.0, -0.5 * W, bottom, top), fixed=True),
        prism(mat_ice, box(0.5 * W, 0.5 * W + 1.0, bottom, top), fixed=True),
    ])
    blocks = [prism(mat_ice, c) for c in corners]
    ids = O.bodies.append(blocks)
    for b in blocks if not P.hold_from else ():   # released with random velocities
        phi = rng.uniform(0, 2 * np.pi)
        s = P.v_max * np.sqrt(rng.uniform())
        b.state.vel = Vector3(s * np.cos(phi), s * np.sin(phi), 0.0)
        b.state.angVel = Vector3(0.0, 0.0, rng.uniform(-P.w_max, P.w_max))

    g_net = (P.rho_w - P.rho_i) / P.rho_i * P.g  # upward: net buoyancy per unit ice mass
    O.engines = [
        ForceResetter(),
        InsertionSortCollider([Bo1_Polyhedra_Aabb()], verletDist=0.05 * P.t_min),
        InteractionLoop([Ig2_Polyhedra_Polyhedra_PolyhedraGeom()],
                        [Ip2_PolyhedraMat_PolyhedraMat_PolyhedraPhys()],
                        [Law2_PolyhedraGeom_PolyhedraPhys_Volumetric()]),
        PyRunner(iterPeriod=1, command='_phase1_friction()'),
        NewtonIntegrator(damping=P.damping, gravity=(0.0, g_net, 0.0)),
    ]
    # Critical step of a chain of blocks pressed face to face: face stiffness k_n A,
    # mass rho t A, omega_max^2 = 4 k_n / (rho_i t_min). PWaveTimeStep is useless for
    # polyhedra (returns 1.0), GlobalStiffnessTimeStepper mixes units (docs/yade_notes.md).
    k_n = 0.5 * P.E_settle
    dt = P.dt_safety * 2.0 / np.sqrt(4.0 * k_n / (P.rho_i * P.t_min))
    O.dt = dt
    friction = Coupling((), P.mu_settle, k_n * P.t_min, dt)   # friction alone: no water, no bonds
    builtins._phase1_friction = friction   # PyRunner commands run in YADE's __main__ namespace
    if P.mu_settle == 0.0 and P.mu_hold < 0.0:
        O.engines = O.engines[:3] + O.engines[4:]
    steps_per_check = max(1, int(round(P.check_interval / dt)))

    block_states = [O.bodies[i].state for i in ids]
    def kinetic():
        ke = 0.0
        for s in block_states:
            v, w = s.vel, s.angVel
            ke += 0.5 * s.mass * v.squaredNorm() + 0.5 * s.inertia[2] * w[2] ** 2
        return ke  # J per metre of width (prisms are 1 m deep)

    def settle(stage, t_limit):
        """Run until the kinetic energy per block stays below ke_per_block."""
        quiet = 0
        while O.time < t_limit:
            O.run(steps_per_check, True)
            ke = kinetic()
            if not np.isfinite(ke) or ke / n > 1e3 * P.g * P.t_max * P.l_max * P.rho_w:
                worst = max(ids, key=lambda i: (not np.isfinite(O.bodies[i].state.vel.norm()),
                                                O.bodies[i].state.vel.norm()))
                raise RuntimeError(f"phase 1 unstable at step {O.iter} (t = {O.time:.3f} s): kinetic "
                                   f"energy {ke:.3e} J/m, fastest block {worst} at "
                                   f"{tuple(O.bodies[worst].state.pos)[:2]}; lower dt_safety "
                                   f"({P.dt_safety}) or E_settle ({P.E_settle})")
            quiet = quiet + 1 if ke / n < P.ke_per_block else 0
            print(f"  {stage} t {O.time:7.2f} s  step {O.iter:7d}  KE/block {ke / n:.3e} J/m  "
                  f"contacts {O.interactions.countReal():5d}  wall {time.time() - t_wall0:6.1f} s", flush=True)
            if quiet >= P.n_quiet:
                return True, ke
        print(f"make_pile: {stage} NOT settled after {O.time:.1f} s simulated (KE/block {ke / n:.3e} J/m)",
              flush=True)
        return False, ke

    print(f"make_pile: {n} blocks, domain {W} m, dt {dt:.3g} s, {steps_per_check} steps/check", flush=True)
    settled, ke, settle_time, hold = True, 0.0, 0.0, {}
    if not P.hold_from:
        settled, ke = settle("rise", P.max_time)
        settle_time = O.time
    if P.mu_hold >= 0.0 and settled:
        # The hold stage: freeze bonds form where blocks meet on a face (the
        # mesher bonds contacts of min_bond_length or more), and the pile must be
        # at rest at the lowest friction it will be run at: the face contacts
        # stick, every other contact slides at mu_hold; blocks held by friction
        # alone slide to a new rest here, in seconds, instead of in phase 2.
        if not O.interactions.countReal():   # a pile read from a file: find its contacts first
            O.run(1, True)
        frozen = freeze_face_contacts(friction, lambda i: world_corners(O.bodies[i]),
                                      walls=(O.bodies[1].id, O.bodies[2].id),
                                      hold_bond_length=P.hold_bond_length)
        friction.mu = P.mu_hold
        start = np.array([tuple(O.bodies[i].state.pos)[:2] for i in ids])
        t0 = O.time
        settled, ke = settle("hold", t0 + P.max_time)
        moved = np.hypot(*(np.array([tuple(O.bodies[i].state.pos)[:2] for i in ids]) - start).T)
        hold = dict(hold_friction=float(P.mu_hold), hold_frozen_contacts=int(frozen),
                    hold_time=float(O.time - t0), hold_max_block_move=float(moved.max()),
                    hold_blocks_moved_1cm=int((moved > 0.01).sum()))
        print(f"make_pile: hold at mu {P.mu_hold:g}: {frozen} face contacts frozen, {O.time - t0:.2f} s, "
              f"{hold['hold_blocks_moved_1cm']} blocks moved > 1 cm (at most {moved.max() * 1e3:.0f} mm)",
              flush=True)
    if P.hold_from:
        hold["hold_from"] = os.path.abspath(P.hold_from)
        settle_time = float(before["meta"]["settle_time"])

    out_corners = np.array([world_corners(O.bodies[i]) for i in ids])
    bounds = pile.keel_bounds(out_corners, top, -0.5 * W, 0.5 * W)
    eta = pile.porosity(out_corners, bounds)
    desc = description
    out = P.out or (f"pile_{desc}.h5" if desc and desc != 'interactive' else "pile.h5")
    params = {k: getattr(P, k) for k in (
        'seed', 'domain_width', 'n_blocks', 'keel_depth', 'porosity_guess', 't_min', 't_max',
        'l_min', 'l_max', 'max_tilt', 'v_max', 'w_max', 'mu_settle', 'E_settle', 'damping', 'dt_safety',
        'ke_per_block', 'check_interval', 'n_quiet', 'max_time', 'rho_i', 'rho_w', 'g',
        'layer_thickness', 'mu_hold', 'hold_bond_length')}
    if P.hold_from:   # the pile is the one made before, held: its own parameters and seed
        params = dict(before["params"], mu_hold=P.mu_hold, hold_bond_length=P.hold_bond_length)
    meta = dict(seed=int(params["seed"]), n_blocks=n, yade_version=yade.config.version,
                settled=int(settled), settle_time=float(settle_time), steps=int(O.iter), dt=dt,
                wall_time=time.time() - t_wall0, final_kinetic_energy=ke, ke_per_block=ke / n,
                porosity=eta, keel_x_min=bounds[0], keel_x_max=bounds[1],
                keel_bottom_y=bounds[2], keel_top_y=bounds[3], layer_bottom_y=top,
                layer_thickness=float(P.layer_thickness), domain_width=float(W),
                friction=float(params["mu_settle"]),
                # YADE's settle follows the processor's floating point: the
                # same seed makes another pile on another machine
                made_on=machine.processor(), **hold)
    write_pile(out, out_corners, ts, ls, params, meta)
    print(f"make_pile: wrote {out}: {n} blocks, settled={settled}, t={O.time:.2f} s simulated, "
          f"wall {meta['wall_time']:.1f} s, porosity {eta:.3f}, keel {bounds[3] - bounds[2]:.2f} m deep",
          flush=True)
