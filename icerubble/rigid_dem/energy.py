"""The energy ledger of a rigid-block run (docs/model.md §6), in the FEM-DEM's
terms (docs/results_format.md /energy), counted from the moment it starts
(the punch-through: the start of loading).

YADE's NewtonIntegrator is a leapfrog: at step n the forces F_n act at the
positions x_n, and v_{n+1/2} = v_{n-1/2} + dt (F_n / m + g). So the kinetic
energy at half steps changes by exactly sum F_n . (v_{n-1/2} + v_{n+1/2}) / 2 dt,
and that is how every force's work is counted here: each term's per-body
forces of step n are kept and paid out when the next step's velocities are
read. For a driven body (the indenter), whose displacement over step n is its
prescribed velocity times dt, the same mean is taken of the prescribed
velocities; what the rubble's forces do on it is the boundary's work, with
the sign turned (the work the indenter does on the rubble).

What each term is:
- kinetic: of the free bodies (translation and turn about z), at the half step;
- elastic: the intact and opened bond points' stored energy (the bond law's own);
- cohesive: the work done against the bond forces less what they store, as the
  FEM-DEM books it: the mechanical dissipation. (The bond law's own `dissipated`
  is eq 12's effective measure, G l at full failure; under the paper's force
  direction, eq 11 as printed, the forces' work differs from it, so it cannot
  be the ledger's term.);
- contact: the tangential springs' stored energy (f_t^2 / 2 k_t) plus the
  change, since the start, of YADE's normal contact energy. Its volumetric
  law is elastic but does not report an energy, so the change is minus the
  work of the normal forces on all bodies;
- friction: what the tangential forces' work leaves after the springs' store
  (the sliding dissipation);
- drag: minus the drag's work; damping: 0 (the load is undamped);
- work_gravity, work_buoyancy, work_boundary: cumulative work on the rubble;
- residual: the balance. Every term is a work or a state, so it closes to
  round-off exactly when the forces paid out are the forces YADE integrated
  with the masses and moments counted here; anything else shows in it.

The sums over bodies are exactly rounded (math.fsum), so they do not depend on
how the terms are grouped: with numpy's sum a resumed run's kinetic energy
differed from the run never stopped by 1.8e-15 J/m of 8 on an AMD EPYC, every
other record equal (docs/reproducibility.md).
"""
import math

import numpy as np

TERMS = ("contact", "friction", "buoyancy", "drag", "bond")


class RigidLedger:
    """Energy of the bodies whose velocities and forces it is given.

    free: mask of the bodies Newton integrates (their kinetic energy counts);
    driven: ids of bodies moved at a prescribed velocity (their forces' work
    is the boundary's); mass, inertia_z: per body [kg/m, kg m²/m]; g: gravity
    [m/s²], down -y; k_t: the friction springs' stiffness [N/m per m]."""

    def __init__(self, free, driven, mass, inertia_z, g, k_t):
        self.free = np.asarray(free, bool)
        self.driven = np.asarray(driven, int)
        self.mass = np.asarray(mass, float)
        self.inertia = np.asarray(inertia_z, float)
        self.g, self.k_t = float(g), float(k_t)
        self.work = dict.fromkeys(TERMS + ("gravity", "boundary"), 0.0)
        self.pending = None   # (vel, omega, {term: (fx, fy, tz)}) of the last step
        self.initial = self.spring0 = self.bonds0 = 0.0

    def kinetic(self, vel, omega):
        f = self.free
        return 0.5 * math.fsum(self.mass[f] * (vel[f] ** 2).sum(axis=1) + self.inertia[f] * omega[f] ** 2)

    def start(self, vel, omega, stored_bonds, friction_forces):
        """The state the ledger counts from."""
        self.spring0 = self.friction_stored(friction_forces)
        self.bonds0 = float(stored_bonds)
        self.initial = self.kinetic(vel, omega) + stored_bonds + self.spring0
        self.work = dict.fromkeys(self.work, 0.0)
        self.pending = None

    def friction_stored(self, forces):
        return math.fsum(np.ravel(np.asarray(forces, float) ** 2)) / (2.0 * self.k_t)

    def advance(self, vel, omega, dt):
        """Pay out the last step's forces with the velocities just read (the
        next half step's): call before the driven bodies' velocities are set."""
        if self.pending is None:
            return
        v0, w0, forces = self.pending
        vm, wm = 0.5 * (v0 + vel), 0.5 * (w0 + omega)
        f, d = self.free, self.driven
        for term, (fx, fy, tz) in forces.items():
            p = fx * vm[:, 0] + fy * vm[:, 1] + tz * wm
            self.work[term] += math.fsum(p[f]) * dt
            if term != "gravity":
                # on a driven body the rubble's force works against the drive
                driven = math.fsum(p[d])
                self.work["boundary"] -= driven * dt
                self.work[term] += driven * dt
        self.pending = None

    def hold(self, vel, omega, forces):
        """This step's per-term forces (dict of (fx, fy, tz)) and the velocities
        read with them (the previous half step's; the driven bodies' set for this
        step). Gravity is added here for the free bodies."""
        forces = dict(forces)
        n = len(self.mass)
        forces["gravity"] = (np.zeros(n), np.where(self.free, -self.mass * self.g, 0.0), np.zeros(n))
        self.pending = (np.array(vel, float), np.array(omega, float), forces)

    def energies(self, vel, omega, stored_bonds, friction_forces):
        """The ledger now, in docs/results_format.md's terms [J/m]. Velocities are
        the last read (the half step the last paid-out work reaches)."""
        w = self.work
        spring = self.friction_stored(friction_forces)
        e = dict(kinetic=self.kinetic(vel, omega), elastic=stored_bonds,
                 contact=spring - w["contact"], friction=-w["friction"] - (spring - self.spring0), damping=0.0,
                 drag=-w["drag"], cohesive=-w["bond"] - (stored_bonds - self.bonds0),
                 work_gravity=w["gravity"], work_buoyancy=w["buoyancy"], work_boundary=w["boundary"])
        e["residual"] = (e["kinetic"] + e["elastic"] + e["contact"] + e["friction"] + e["drag"] + e["cohesive"]
                         - self.initial - e["work_gravity"] - e["work_buoyancy"] - e["work_boundary"])
        return e
