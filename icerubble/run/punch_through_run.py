"""The punch-through run (paper section 2.4; docs/model.md §1, 4).

    settle  - gravity and buoyancy on, layer top held, indenter free, bond
              failure off: damped motion until the system is at rest; then the
              indenter is held and its force at rest checked (~0);
    load    - the indenter top is driven down with a smooth ramp to v_final
              over ramp_time, until the travel y_I reaches target_travel;
              F(y_I) every <= 0.05 mm, u snapshots at 1, 5, 10, 20, ... mm,
              energies, bond events;
    write   - one self-describing HDF5 result (docs/results_format.md) and
              ParaView snapshots (VTU + PVD) beside it.

Each phase has a module of its own: run/settle.py, run/loading.py,
run/output.py; the shared rest states run/rest_states.py; the run's progress
(what a checkpoint saves) run/run_state.py. This driver holds the run's
scene, parameters and options, its entry points (run, settle_only,
run_from_rest; run's order of phases is run/driver.py's, which the rigid-block
model's run shares), the boundary conditions of each phase and the checkpoints.

A checkpoint written every ``checkpoint_every_s`` wall seconds lets an
interrupted run resume (``resume=True``); the result file appears only when
the run is complete. A run sent SIGTERM or SIGUSR1 (what a scheduler sends
before it stops a job) or SIGINT (Ctrl-C) writes its checkpoint at once and
stops with RunInterrupted (the YADE script then exits 75).
"""
import json
import math
import os
import signal
import time

import h5py
import numpy as np

from . import checkpoint as ckpt
from . import rest_states as RS
from . import run_identity as RI
from ..files.mesh_file import mesh_geometry, read_mesh
from .. import engine
from .. import parameters as P
from .presets import SCENES
from ..files.recorder import RunRecorder
from .run_state import RunState
from .settle import SETTLE_LOCAL_DAMPING, Settle
from .driver import Driver, RunInterrupted, catching_stop_signals
from .loading import Loading, smooth_ramp_table
from .output import Output
from .scene import Scene

_SETTLE = {k: P.REGISTRY[k].default for k in P.SETTLE_OPTIONS}


class RunOptions:
    """How to run, as opposed to what to simulate (the parameters)."""

    def __init__(self, settle_max_time=_SETTLE["settle_max_time"], settle_min_time=_SETTLE["settle_min_time"],
                 settle_velocity=_SETTLE["settle_velocity"], settle_accel=_SETTLE["settle_accel"],
                 settle_hold_time=_SETTLE["settle_hold_time"],
                 checkpoint_every_s=600.0, progress_every_s=10.0, threads=0, vtu=True,
                 stop_after_steps=None, dt_fraction=None, mass_scaling_dt=None, sleep=None,
                 contact_reach=math.inf, numerics="", settle_mass_scaling_dt=None, device="cpu"):
        # the settle's options: the registry's (icerubble/parameters.py, group settle)
        for k in P.SETTLE_OPTIONS:
            setattr(self, k, P.check_value(k, locals()[k]))
        if not settle_min_time <= settle_max_time:
            raise ValueError(f"settle_min_time={settle_min_time} must be in [0, settle_max_time={settle_max_time}] s")
        self.checkpoint_every_s = checkpoint_every_s
        self.progress_every_s = progress_every_s
        self.threads = threads
        self.vtu = vtu
        self.stop_after_steps = stop_after_steps   # for tests of interrupted runs
        if dt_fraction is not None and not 0.0 < dt_fraction <= 1.0:
            raise ValueError(f"dt_fraction={dt_fraction} must be in (0, 1]: the time step as a "
                             "fraction of the mesh's stable step")
        self.dt_fraction = dt_fraction             # None: use params['dt'] as given
        if mass_scaling_dt is not None and not mass_scaling_dt > 0.0:
            raise ValueError(f"mass_scaling_dt={mass_scaling_dt} must be > 0 s (or None: no mass scaling)")
        self.mass_scaling_dt = mass_scaling_dt     # selective mass scaling target step
        self.sleep = check_sleep(sleep)            # sleeping far field while loading (None: off)
        if not contact_reach > 0.0:
            raise ValueError(f"contact_reach={contact_reach} must be > 0 m (inf: the whole mesh)")
        self.contact_reach = float(contact_reach)  # local contact step bound (engine set(contact_reach))
        if settle_mass_scaling_dt is not None and not (
                settle_mass_scaling_dt > 0.0 and settle_mass_scaling_dt > (mass_scaling_dt or 0.0)):
            raise ValueError(f"settle_mass_scaling_dt={settle_mass_scaling_dt} must be > 0 s and above "
                             f"mass_scaling_dt={mass_scaling_dt} (or None: settle at the loading's step)")
        # the settle's own, larger mass-scaling step (dynamic relaxation: inertia
        # only, the weight stays physical, so the rest it reaches is a balance of
        # the same loads); None: the loading's
        self.settle_mass_scaling_dt = settle_mass_scaling_dt
        self.numerics = str(numerics)              # the preset these came from, for the record
        # where the steps run (engine.DEVICES): refused here where it cannot, before any work
        self.device = engine.check_device(device)

    @classmethod
    def from_numerics(cls, settings, name="", **kw):
        """Options from a scene's numerical preset (presets.numerics)."""
        return cls(dt_fraction=settings.get("dt_fraction"), mass_scaling_dt=settings.get("mass_scaling_dt"),
                   sleep=settings.get("sleep"), contact_reach=settings.get("contact_reach", math.inf),
                   settle_mass_scaling_dt=settings.get("settle_mass_scaling_dt"), numerics=name, **kw)


SLEEP_KEYS = {"velocity": "m/s", "force": "fraction of a body's (and a node's) weight", "quiet_time": "s"}


def check_sleep(sleep):
    """The sleeping far field of a run (engine sleeping.hpp), checked: None
    (off) or a dict with velocity [m/s] and force [fraction of the node's
    weight] >= 0 and quiet_time [s] > 0."""
    if sleep is None:
        return None
    if not isinstance(sleep, dict) or set(sleep) != set(SLEEP_KEYS):
        raise ValueError(f"sleep={sleep!r} must be None or a dict with keys {sorted(SLEEP_KEYS)}")
    out = {}
    for k, v in sleep.items():
        v = float(v)
        low_ok = v > 0.0 if k == "quiet_time" else v >= 0.0
        if not (low_ok and math.isfinite(v)):
            raise ValueError(f"sleep {k}={v!r} must be {'> 0' if k == 'quiet_time' else '>= 0'} "
                             f"and finite ({SLEEP_KEYS[k]})")
        out[k] = v
    return out


class PunchThrough(Driver):
    def __init__(self, mesh_path, out_path, params=None, options=None, meta=None, rest_dir=None):
        """rest_dir: a folder of shared rest states (rest_states.py): the run
        loads from the rest state of an earlier run that differs from it only
        in what the settle never reads, or settles and leaves its own there
        (None: every run settles itself)."""
        # everything that can be wrong with the input fails here, before any work
        self.params = P.validate(params or {}, scenes=SCENES)
        self.options = options or RunOptions()
        self.mesh = read_mesh(mesh_path)
        self.mesh_path = os.path.abspath(mesh_path)
        self.out_path = os.fspath(out_path)
        if not self.out_path.endswith(".h5"):
            raise ValueError(f"out_path={out_path!r} must end in .h5")
        self.ckpt_path = ckpt.checkpoint_path(self.out_path)
        self.meta = dict(ridge="", seed=-1, model="fem-dem")
        self.meta.update(meta or {})
        self.scene = Scene(self.mesh, self.params, threads=self.options.threads, device=self.options.device)
        # The geometry is the mesh's (never a run parameter: validate refuses
        # it): recorded as simulated (the analyses read keel_depth, indenter_width ...)
        self.params = P.recorded(self.params, mesh_geometry(self.mesh))
        self.scene.params = self.params
        self._configure_numerics(self.scene.model)
        if math.isfinite(self.options.contact_reach):
            self.meta.update(contact_reach=self.options.contact_reach)
        if self.options.numerics:
            self.meta.update(numerics=self.options.numerics)
        if self.options.mass_scaling_dt is not None:
            st = self.scene.model.stable_time_step()
            self.meta.update(mass_scaling_dt=self.options.mass_scaling_dt,
                             added_mass_fraction=st["added_mass_fraction"],
                             scaled_nodes=st["scaled_nodes"])
        if self.options.dt_fraction is not None:
            # the engine's stable step of this mesh (it carries a 0.9 safety factor);
            # recorded as the run's dt, which a resumed run sets explicitly
            self.scene.model.set(dt_fraction=self.options.dt_fraction)
            self.params["dt"] = self.scene.model.dt
            self.scene.params = self.params
        a = self.mesh["attrs"]
        # The friction phase 1 settled the pile at (the mesh records it; NaN
        # for piles that were not settled, e.g. constructed ones). Below it the
        # pile is not known to be at rest: loose blocks may slide a long way.
        self.pile_friction = float(a.get("pile_friction", math.nan))
        # ... or the lower friction its hold stage brought it to rest at
        self.pile_rest_friction = float(a.get("pile_hold_friction", self.pile_friction))
        if self.params["mu"] < self.pile_rest_friction:
            print(f"[punch-through] warning: mu = {self.params['mu']:g} is below the friction the pile "
                  f"was settled at ({self.pile_rest_friction:g}); loose blocks may slide for long "
                  "while settling (make the pile at the lowest mu it will be run at)", flush=True)
        pile_attrs = dict(porosity=float(a["porosity"]), friction=self.pile_friction,
                          **({"hold_friction": self.pile_rest_friction} if "pile_hold_friction" in a else {}),
                          n_blocks=int(np.sum(self.scene.body_kind == 0)),
                          keel_top_y=float(a["keel_top_y"]), keel_bottom_y=float(a["keel_bottom_y"]),
                          keel_x_min=float(a["keel_x_min"]), keel_x_max=float(a["keel_x_max"]),
                          mesh_file=self.mesh_path,
                          # a pile made here by phase 1 depends on this machine's
                          # processor; a shipped one is the same everywhere
                          made_on=str(a.get("pile_made_on", "not recorded")),
                          shipped=str(a.get("pile_shipped", "")))
        m = self.scene.model
        mesh_arrays = dict(nodes=self.mesh["nodes"], triangles=self.mesh["triangles"],
                           body=self.mesh["body"], body_kind=self.scene.body_kind)
        self.recorder = RunRecorder(self.params, mesh_arrays, self.scene.bond_points, pile_attrs, self.meta)
        self.settler = Settle(self)   # the settle (run/settle.py) and its node -> body maps
        self.loading = Loading(self)  # the loading (run/loading.py)
        self.output = Output(self)    # snapshots, bond events, the result (run/output.py)
        self.state = RunState()     # the run's progress: what a checkpoint saves of the driver
        self._stop_signal = None    # set by SIGTERM / SIGUSR1 / SIGINT while running
        self.rest_state = None      # run_from_rest: the rest state this run loaded from (its settle was that run's)
        self.model = m
        self.shared_rest = None     # (path, settle identity) of the shared rest state, rest_dir given
        self._shared_rest_damaged = False   # the file at its name could not be read: written again
        if rest_dir is not None:
            ident = RS.settle_identity(self.params, self.mesh, self.options, m.thread_count,
                                       model=self.meta.get("model", "fem-dem"))
            self.shared_rest = (RS.rest_state_path(rest_dir, self.mesh_path, ident), RI.to_json(ident))

    def _configure_numerics(self, m):
        """The contact step's reach and the loading's mass scaling, on a model
        just built or rebuilt from a checkpoint (a resumed run needs the same
        masses and bound, or its dt is above the unscaled stable step)."""
        if math.isfinite(self.options.contact_reach):
            # before the mass scaling, which bounds the contact step with it
            m.set(contact_reach=self.options.contact_reach)
        if self.options.mass_scaling_dt is not None:
            # the few light nodes of tiny elements get inertial mass (never
            # weight) so that the stable step reaches this target
            m.set(mass_scaling_dt=self.options.mass_scaling_dt)

    # ------------------------------------------------------------------
    def travel(self):
        return self.state.y_top0 - self.scene.indenter_top_y()

    # --- the phases, in the order run() (run/driver.py) takes them
    def resume(self, path):
        ckpt.restore(self, path)
        print(f"[punch-through] resumed from {path} at step {self.model.step_count}, "
              f"phase {self.state.phase}", flush=True)
        self._last_ckpt = self._wall_mark = time.perf_counter()

    def begin(self):
        if self.shared_rest is not None and os.path.exists(self.shared_rest[0]):
            RS.load_shared(self)
        self._last_ckpt = self._wall_mark = time.perf_counter()

    def settled(self):
        return self.state.phase != "settle"

    def settle(self):
        """To rest, then held; the loading starts (run/settle.py); the rest
        state is left for the runs that differ only in what the settle never
        read (rest_dir given)."""
        self.settler.run()
        if self.shared_rest is not None:
            RS.share(self)

    def load(self):
        self.loading.run()

    def write(self):
        self.book_wall_time()
        self.recorder.meta.update(wall_settle_s=self.state.wall_settle_s, wall_load_s=self.state.wall_load_s,
                                  step_timings=json.dumps(self.model.timings()))
        self.output.write()

    def book_wall_time(self):
        """Add the wall time since the last booking to the current phase's
        (RunState.wall_settle_s / wall_load_s): at each checkpoint, when the
        settle hands over to the loading, and at the end."""
        now = time.perf_counter()
        if self.state.phase == "settle":
            self.state.wall_settle_s += now - self._wall_mark
        else:
            self.state.wall_load_s += now - self._wall_mark
        self._wall_mark = now

    def settle_only(self, rest_path):
        """Settle (resuming this run's own checkpoint if there is one) and
        write the rest state, a checkpoint at the start of loading, to
        `rest_path`: runs that differ in their loading numerics alone start
        from it (run_from_rest)."""
        if os.path.abspath(rest_path) == os.path.abspath(self.ckpt_path):
            raise ValueError(f"rest_path={rest_path!r} is this run's own checkpoint, which it removes "
                             "when done: give the rest state another name")
        with catching_stop_signals(self):
            if os.path.exists(self.ckpt_path):
                ckpt.restore(self, self.ckpt_path)
            self._last_ckpt = self._wall_mark = time.perf_counter()
            if self.state.phase == "settle":
                self.settler.run()
        ckpt.save(self, rest_path)
        if os.path.exists(self.ckpt_path):
            os.remove(self.ckpt_path)
        return rest_path

    def run_from_rest(self, rest_path):
        """Load from the rest state of another run of this scene and these
        parameters but for the step and travel (settle_only; checkpoint.restore
        from_rest), with this run's masses and step, and write the result. An
        interrupted run resumes from its own checkpoint. The result names the
        rest state and the step it was settled at; its settle record
        (settle_time, F_at_rest ...) is the rest state's."""
        with catching_stop_signals(self):
            if os.path.exists(self.ckpt_path):
                ckpt.restore(self, self.ckpt_path)
                if self.state.phase != "load":
                    raise ValueError(f"{self.ckpt_path} is a checkpoint of a settle, not of a load from a "
                                     "rest state: remove it, or resume it with run()")
                print(f"[punch-through] resumed from {self.ckpt_path} at step {self.model.step_count}, "
                      f"phase {self.state.phase}", flush=True)
            else:
                ckpt.restore(self, rest_path, from_rest=True)
            with h5py.File(rest_path, "r") as f:
                rest_dt = json.loads(f["driver"].attrs["params"])["dt"]
            self.recorder.meta.update(rest_state_from=os.path.abspath(rest_path), rest_state_dt=rest_dt)
            self.rest_state = rest_path
            self._last_ckpt = self._wall_mark = time.perf_counter()
            self.loading.run()
            self.write()
        if os.path.exists(self.ckpt_path):
            os.remove(self.ckpt_path)
        return self.out_path

    def _maybe_checkpoint(self, force=False):
        now = time.perf_counter()
        if force or now - self._last_ckpt >= self.options.checkpoint_every_s:
            self.book_wall_time()
            ckpt.save(self, self.ckpt_path)
            self._last_ckpt = now
        if self._stop_signal is not None:
            self.book_wall_time()
            ckpt.save(self, self.ckpt_path)
            m = self.model
            raise RunInterrupted(
                f"stopped by {signal.Signals(self._stop_signal).name} at step {m.step_count} (phase "
                f"{self.state.phase}, t = {m.time:.4f} s"
                + (f", y_I = {1e3 * self.travel():.3f} mm" if self.state.y_top0 is not None else "") + "); "
                f"checkpoint {self.ckpt_path}: run it again to resume")
        stop = self.options.stop_after_steps
        if stop is not None and self.model.step_count >= stop:
            ckpt.save(self, self.ckpt_path)
            raise KeyboardInterrupt(f"stopped after {self.model.step_count} steps (stop_after_steps)")

    def apply_boundary_conditions(self):
        """Layer top held; in the load phase the indenter top is driven. Drag
        is off while settling (see settle)."""
        m = self.model
        loading = self.state.phase == "load"
        m.set(drag=loading, local_damping=0.0 if loading else SETTLE_LOCAL_DAMPING)
        # the far field sleeps while loading only: settling must see every node come to rest
        z = self.options.sleep
        if loading and z is not None:
            m.set(sleeping=True, sleep_velocity=z["velocity"], sleep_force=z["force"],
                  sleep_quiet_steps=max(1, math.ceil(z["quiet_time"] / m.dt)))
        else:
            m.set(sleeping=False)
        m.clear_boundary_conditions()
        self.scene.hold_boundaries(m)
        if self.state.phase == "load":
            t, s = smooth_ramp_table(self.state.t_load, self.params["v_final"], self.params["ramp_time"])
            m.prescribe_velocity("indenter_top", direction=(0.0, -1.0), table=(t, s))

    def block_moves(self):
        """(ids, distances [m]): how far each block's node centroid is from
        where the mesh put it (before loading: its move while settling)."""
        return self.settler.block_moves()

    def block_displacements(self):
        """(ids, u_x, u_y) [m] of each block's node centroid, as block_moves."""
        return self.settler.block_displacements()
