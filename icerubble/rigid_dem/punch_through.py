"""The punch-through with rigid blocks in YADE (docs/model.md §6): the same
ridge, loading and result file as the FEM-DEM run (icerubble/run/), with each
body a YADE polyhedron prism and the project's friction, water and freeze-bond
laws through the coupling. Only inside YADE.

Phases, as the FEM-DEM driver's: settle (gravity, buoyancy, bonds held, no
drag, Cundall damping 0.7, the indenter free with the rubble bonded to it)
until every body is slower than SETTLE_SPEED; hold the indenter where it came
to rest and measure the force that takes (F_at_rest, ~0 in balance); then load
(damping off, drag and bond failure on) with the indenter driven down on the
engine's smooth ramp to the target travel. F is the force of the rubble on the
driven indenter (contacts, friction, bonds; the water is not applied to it, so
nothing of its own buoyancy is in F).
"""
import builtins
import math
import os
import signal
import time

import numpy as np
import yade.log
from yade import Vector3
from yade.wrapper import O

from .. import _engine
from ..files.mesh_file import read_mesh
from ..run.progress import Progress, loading_eta_text, settle_eta_text
from ..run.checkpoint import checkpoint_path
from ..run.loading import ENERGY_EVERY
from ..run.driver import Driver, RunInterrupted
from ..files.recorder import RunRecorder
from . import checkpoint
from .energy import RigidLedger
from .prisms import inertia_z
from .scene import KIND_BLOCK, rigid_scene
from .yade_state import load_into_yade

yade.log.setLevel('Polyhedra_support.cpp', yade.log.ERROR)

SETTLE_DAMPING = 0.7     # Cundall local damping while settling, as the FEM-DEM settle
SETTLE_SPEED = 1e-3      # [m/s] every block slower than this: at rest
SETTLE_MIN, SETTLE_MAX = 0.2, 5.0   # [s] simulated
SAMPLE_TRAVEL = 1e-4     # [m] force samples at least this often
HOLD_TIME = 0.05         # [s] the indenter held before loading (F at rest: second half)


class RigidPunchThrough(Driver):
    def __init__(self, mesh_path, out_path, params, meta, threads=1, checkpoint_every_s=600.0):
        if not checkpoint_every_s > 0.0:
            raise ValueError(f"checkpoint_every_s must be > 0 s (got {checkpoint_every_s})")
        self.mesh_path, self.out_path = mesh_path, out_path
        self.ckpt_path = checkpoint_path(out_path)
        self.checkpoint_every_s = float(checkpoint_every_s)
        self.mesh = read_mesh(mesh_path)
        self.sc = rigid_scene(self.mesh, params)
        self.params = self.sc["params"]
        self.meta = dict(meta, model="rigid-dem")
        self.threads = threads

    # --- the YADE scene -----------------------------------------------------
    def build(self):
        """The ridge as YADE prisms with the coupling (yade_state.load_into_yade),
        set up to settle: Cundall damping, bonds held intact, no drag."""
        sc = self.sc
        O.reset()
        st = load_into_yade(sc, damping=SETTLE_DAMPING, failure=False, drag=False,
                            step_command="_rigid_run.each_step()")
        kind = sc["body_kind"]
        if list(st.ids) != list(range(len(kind))):
            raise RuntimeError("YADE numbered the bodies other than the mesh: expected 0..n-1")
        self.hull_added_area = st.hull_added_area   # worst block's area gained by its hull
        self.blocks = np.flatnonzero(kind == KIND_BLOCK)
        self.indenter = sc["indenter"]
        self.floating = np.append(self.blocks, self.indenter)   # free while settling, the coupling's order
        self.dt, self.coupling, self.newton = st.dt, st.coupling, st.newton
        builtins._rigid_run = self   # PyRunner commands run in YADE's __main__ namespace
        self.loading = False
        self.body0 = self._poses()

    def _poses(self):
        pos, _, _, theta = self.coupling.body_arrays()
        return pos, theta

    def _max_block_speed(self):
        return max(O.bodies[int(b)].state.vel.norm() for b in self.floating)

    # --- each step --------------------------------------------------------------
    def each_step(self):
        arrays = self.coupling.body_arrays()
        if self.loading:
            _, vel, omega, _ = arrays
            started = self.ledger.pending is not None   # it holds a step's forces from the first loaded step on
            self.ledger.advance(vel, omega, O.dt)
            v = float(_engine.ramp_velocity(O.time - self.t_load, self.params["v_final"], self.params["ramp_time"]))
            O.bodies[self.indenter].state.vel = Vector3(0.0, -v, 0.0)
            vel[self.indenter] = (0.0, -v)
            if not started:
                b = self.coupling.bonds
                self.ledger.start(vel, omega, b.stored_energy(), self.coupling.friction.forces)
        self.coupling(arrays)
        if self.loading:
            self.ledger.hold(arrays[1], arrays[2], self.coupling.terms)
            if not self.done:
                self.record(arrays)

    def energies(self, arrays):
        b = self.coupling.bonds
        return self.ledger.energies(arrays[1], arrays[2], b.stored_energy(), self.coupling.friction.forces)

    def record(self, arrays):
        """This step's indenter travel and force (contacts, friction, bonds: all
        forces of the step are in by now), sampled as the FEM-DEM run samples;
        the energy every ENERGY_EVERY samples."""
        rec, target = self.rec, self.params["target_travel"]
        y = self.y0 - O.bodies[self.indenter].state.pos[1]
        F = O.forces.f(self.indenter, sync=True)[1]   # the rubble pushes the indenter up
        if not math.isfinite(F):
            raise RuntimeError(f"rigid run unstable at t = {O.time:.3g} s, y_I = {y * 1e3:.2f} mm: "
                               "the indenter force is not finite")
        self.work += 0.5 * (F + self.F_prev) * (y - self.y_prev)
        self.F_prev, self.y_prev = F, y
        t = O.time - self.t_load
        if y - self.y_sample >= SAMPLE_TRAVEL or y >= target:
            rec.force(t, y, self.work / (y - self.y_sample) if y > self.y_sample else F, F)
            self.work, self.y_sample = 0.0, y
            self.t_sample.append((t, y))
            if len(self.t_sample) % ENERGY_EVERY == 0 or y >= target:
                rec.energy(t, self.energies(arrays))
        if rec.wants_snapshot(y):
            self._snapshot(rec, y)
        if y >= target:
            self.done = True
            O.pause()

    # --- the phases, in the order run() (run/driver.py) takes them ------------------
    # run(resume): settle, hold, load and write the result. With `resume`, a
    # checkpoint of this run (OUT.checkpoint.h5, written while loading) is
    # taken up where it was; a run stopped while settling starts again.
    def start(self):
        self.build()

    def resume(self, path):
        checkpoint.restore(self, path)
        print(f"[rigid punch-through] resumed from {path} at step {O.iter}, "
              f"y_I = {1e3 * self.y_prev:.3f} mm", flush=True)

    def settled(self):
        return self.loading    # checkpoints are written while loading

    def settle(self):
        self.settle_and_hold()

    def write(self):
        """The result; its wall times are the run's own, counted across resumes
        (the checkpoint keeps them), not this process's."""
        rec = self.rec
        self._bond_events(rec, np.array(self.t_sample))
        rec.meta.update(settle_time=self.settle_time, settle_max_speed=self.settle_speed, F_at_rest=self.F_at_rest,
                        dt=self.dt, wall_settle_s=self.wall_settle_s, wall_load_s=self.wall_load_s,
                        load_steps=O.iter - self.iter_load, degenerate_contacts=self.coupling.degenerate,
                        hull_added_area=self.hull_added_area)
        rec.write(self.out_path)

    def settle_and_hold(self):
        """Settle to rest, hold the indenter (F at rest) and make the loading's
        recorder and energy ledger."""
        t_wall = time.perf_counter()
        chunk = max(1, int(round(0.05 / self.dt)))
        prog = Progress("rigid settle", O.iter, eta=lambda t, rate: settle_eta_text(t, SETTLE_MAX, self.dt, rate))
        while True:
            O.run(chunk, True)
            self._stop_if_signalled("settle")
            speed = self._max_block_speed()
            prog.update(O.iter, O.time, f"fastest body {speed:.2g} m/s (at rest < {SETTLE_SPEED:g})")
            if not math.isfinite(speed):
                raise RuntimeError(f"rigid run unstable while settling at t = {O.time:.3g} s (a block's speed "
                                   f"is not finite); dt = {self.dt:.3g} s")
            if O.time >= SETTLE_MIN and speed < SETTLE_SPEED:
                break
            if O.time >= SETTLE_MAX:
                raise RuntimeError(f"the rigid pile did not come to rest in {SETTLE_MAX} s simulated "
                                   f"(fastest block {speed:.3g} m/s > {SETTLE_SPEED} m/s)")
        self.settle_time, self.settle_speed = O.time, speed
        # hold the indenter where it came to rest: what that takes is F at rest
        ind = O.bodies[self.indenter]
        ind.dynamic = False
        ind.state.vel = Vector3(0, 0, 0)
        ind.state.angVel = Vector3(0, 0, 0)
        self.coupling.dry[-1] = True          # the indenter is last in self.floating
        self.newton.damping = 0.0
        self.coupling.water.drag = True
        n_hold = max(20, int(round(HOLD_TIME / self.dt)))
        O.run(n_hold // 2, True)
        self._stop_if_signalled("hold")
        held = []
        for _ in range(10):
            O.run(max(1, n_hold // 20), True)
            held.append(O.forces.f(self.indenter, sync=True)[1])
        self.F_at_rest = float(np.mean(held))
        ref_pos, ref_theta = self._poses()
        # the load starts here
        self.wall_settle_s, self.wall_load_s, self.iter_load = time.perf_counter() - t_wall, 0.0, O.iter
        self.coupling.bonds.failure = True
        self.coupling.keep_terms = True
        self.ledger = self.make_ledger()
        self.loading, self.t_load = True, O.time
        self.y0 = ind.state.pos[1]
        self.rec = self._recorder(ref_pos, ref_theta)
        self.rec.force(0.0, 0.0, self.F_at_rest)
        print(f"[rigid settle] at rest after {self.settle_time:.3f} s simulated (fastest body "
              f"{self.settle_speed:.2g} m/s); indenter force at rest {self.F_at_rest:.1f} N/m", flush=True)
        self.work, self.y_prev, self.F_prev, self.y_sample, self.t_sample = 0.0, 0.0, 0.0, 0.0, []
        self.done = False

    def _stop_if_signalled(self, phase):
        """A scheduler's stop before loading: no checkpoint (a run asked again
        settles again), but the stop is prompt, with the batch script's exit 75."""
        if self._stop_signal is not None:
            raise RunInterrupted(f"stopped by {signal.Signals(self._stop_signal).name} at step {O.iter} ({phase}, "
                                 "before loading: no checkpoint, a rerun settles again)")

    def make_ledger(self):
        free = np.zeros(len(self.sc["body_kind"]), bool)
        free[self.blocks] = True
        return RigidLedger(free, [self.indenter], [s.mass for s in self.coupling.states],
                           [inertia_z(O.bodies[i]) for i in range(len(free))], self.params["g"],
                           self.coupling.k_t)

    def load(self):
        """Drive the indenter to the target travel, recording in the PyRunner
        (one O.run per step costs milliseconds of thread hand-over); a
        checkpoint every checkpoint_every_s of wall time and on a stop signal."""
        chunk = max(1, int(round(2e-3 / self.dt)))
        p = self.params
        prog = Progress("rigid punch-through", O.iter, eta=lambda t, rate: loading_eta_text(
            t, p["target_travel"], p["v_final"], p["ramp_time"], self.dt, rate))
        t_wall = t_ckpt = time.perf_counter()
        wall_before = self.wall_load_s
        while not self.done:
            O.run(chunk, True)
            b = self.coupling.bonds
            prog.update(O.iter, O.time - self.t_load,
                        lambda: f"y_I {self.y_prev * 1e3:8.3f} mm  F {self.F_prev / 1e3:9.3f} kN/m  "
                                f"bond pairs opened {int((b.state >= 1).sum())}/{len(b.state)} "
                                f"broken {int((b.state == 2).sum())}")
            self.wall_load_s = wall_before + time.perf_counter() - t_wall
            if self.done:
                break
            now = time.perf_counter()
            if now - t_ckpt >= self.checkpoint_every_s:
                checkpoint.save(self, self.ckpt_path)
                t_ckpt = now
            if self._stop_signal is not None:
                checkpoint.save(self, self.ckpt_path)
                raise RunInterrupted(
                    f"stopped by {signal.Signals(self._stop_signal).name} at step {O.iter} (load, "
                    f"y_I = {1e3 * self.y_prev:.3f} mm); checkpoint {self.ckpt_path}: run it again to resume")

    def _recorder(self, ref_pos, ref_theta):
        m, a = self.mesh, self.mesh["attrs"]
        pile = dict(porosity=float(a["porosity"]), friction=float(a.get("pile_friction", math.nan)),
                    n_blocks=int(len(self.blocks)), keel_top_y=float(a["keel_top_y"]),
                    keel_bottom_y=float(a["keel_bottom_y"]), keel_x_min=float(a["keel_x_min"]),
                    keel_x_max=float(a["keel_x_max"]), mesh_file=self.mesh_path)
        rec = RunRecorder(dict(self.params, dt=self.dt), dict(nodes=m["nodes"], triangles=m["triangles"],
                                                                body=m["body"], body_kind=self.sc["body_kind"]),
                          self.sc["bond_points"], pile, self.meta)
        # every mesh point moves with its body: the settled mesh is the reference
        self.ref = (ref_pos, ref_theta)
        rec.set_reference(self._posed_nodes(ref_pos, ref_theta, self.body0))
        rec.centroid0 = self._posed_corners(ref_pos, ref_theta, self.body0).mean(axis=1)
        return rec

    def _posed_corners(self, pos, theta, start):
        """Each triangle's corners moved with its body from pose `start` to (pos, theta): (M, 3, 2)."""
        p0, th0 = start
        tri, body = np.asarray(self.mesh["triangles"]), np.asarray(self.mesh["body"])
        X = np.asarray(self.mesh["nodes"], float)[tri] - p0[body][:, None, :]
        d = (theta - th0)[body]
        c, s = np.cos(d)[:, None], np.sin(d)[:, None]
        return pos[body][:, None, :] + np.stack([c * X[..., 0] - s * X[..., 1], s * X[..., 0] + c * X[..., 1]], axis=-1)

    def _posed_nodes(self, pos, theta, start):
        """Each mesh node moved with the body of the first triangle that uses it."""
        tri = np.asarray(self.mesh["triangles"])
        corners = self._posed_corners(pos, theta, start).reshape(-1, 2)
        out = np.zeros((len(self.mesh["nodes"]), 2))
        flat = tri.reshape(-1)
        first = np.unique(flat[::-1], return_index=True)[1]
        idx = len(flat) - 1 - first
        out[flat[idx]] = corners[idx]
        return out

    def _snapshot(self, rec, y):
        pos, theta = self._poses()
        corners = self._posed_corners(pos, theta, self.body0)
        nodes = self._posed_nodes(pos, theta, self.body0)
        m = len(corners)
        # the recorder averages triangles' corners: give it each triangle's own (rigid) corners
        x = np.vstack([nodes, corners.reshape(-1, 2)])
        tri = len(nodes) + np.arange(3 * m).reshape(m, 3)
        rec.snapshot(O.time - self.t_load, y, x, tri)

    def _bond_events(self, rec, samples):
        """Per bond point: split when its first pair opened, failed when its last pair broke."""
        b = self.coupling.bonds
        point = self.sc["bond_point"]
        n = len(self.sc["bond_points"])
        t_init, t_fail, mode = np.asarray(b.t_initiated), np.asarray(b.t_failed), np.asarray(b.mode)
        split = np.full(n, np.nan)
        fail = np.full(n, -np.inf)
        modes = np.zeros(n, np.int8)
        for k, pt in enumerate(point):
            if np.isfinite(t_init[k]):
                split[pt] = np.nanmin([split[pt], t_init[k]])
            fail[pt] = max(fail[pt], t_fail[k] if np.isfinite(t_fail[k]) else np.inf)
            if np.isfinite(t_fail[k]) and t_fail[k] >= fail[pt]:
                modes[pt] = mode[k]
        fail[~np.isfinite(fail)] = np.nan
        modes[np.isnan(fail)] = 0
        t_rel_split, t_rel_fail = split - self.t_load, fail - self.t_load

        def travel(t):
            return np.interp(t, samples[:, 0], samples[:, 1]) if len(samples) else np.full_like(t, np.nan)
        # split_tn, split_tt stay NaN (the recorder's fill): the rigid bonds keep no
        # traction at initiation, and the analyses then report no initiation count
        rec.bond_events(dict(t_split=t_rel_split, y_I_split=np.where(np.isfinite(t_rel_split), travel(t_rel_split), np.nan),
                             t_fail=t_rel_fail, y_I_fail=np.where(np.isfinite(t_rel_fail), travel(t_rel_fail), np.nan),
                             mode=modes))
