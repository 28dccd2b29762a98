"""Python API of the FEM-DEM engine (compiled module ``icerubble._engine``).

Deformable ice blocks as plane-strain constant-strain triangles (total
Lagrangian, St Venant-Kirchhoff: objective under any rotation), potential
contact with Coulomb friction between bodies, gravity, buoyancy and water
drag (linear or quadratic), explicit central-difference time stepping
(Polojärvi & Tuhkuri 2013, section 3; docs/model.md §3). Units SI, forces and energies per m width.

Example::

    from icerubble import engine
    m = engine.Model(nodes, triangles, body,
                   materials=dict(E=2e9, nu=0.3, rho=920.0, damping=0.0),
                   node_sets={"top": top_ids})
    m.set(dt=1e-6, gravity=True, buoyancy=True, drag=True, y_w=0.0)
    m.prescribe_velocity("top", direction=(0, -1), v_final=0.1, ramp_time=2.0)
    m.step(1000)
    Fx, Fy = m.reaction("top")

See docs/engine_api.md.
"""
import numbers
import time

import numpy as np

# OpenMP waiting: the runtime's default (spin briefly, then sleep) is the
# fastest on a workstation (5,400 triangles, 2 threads: 23 M triangle-steps/s;
# forced passive waiting: 10 M, slower than one thread). On a machine whose
# cores are busy with other work, spinning threads waiting for a descheduled
# partner make steps 10-100x slower: there, export OMP_WAIT_POLICY=passive or
# run with threads=1.

from icerubble import _engine  # noqa: E402
from icerubble import code_identity  # noqa: E402
from icerubble.openmp_threads import default_threads  # noqa: E402
from icerubble import parameters as P  # noqa: E402

from .bond_pairs import bond_pairs  # noqa: E402

# Which code computes is fixed as the compiled module is loaded: a checkout
# rebuilt while a run goes on (its module file replaced on disk) does not
# change what the run's files say computed them (code_identity)
code_identity.source_hash()
code_identity.code_version()

InstabilityError = _engine.InstabilityError
# Where a model's steps run (Model(device=...), a study table's device
# column): the CPU engine, or whole steps on one CUDA GPU (icerubble/engine/gpu.py,
# docs/gpu.md).
DEVICES = ("cpu", "cuda")


def check_device(device):
    """`device` checked: one of DEVICES, and 'cuda' only where the GPU backend
    can run (ValueError saying why not, before any work)."""
    if device not in DEVICES:
        raise ValueError(f"device={device!r} is unknown: valid values are {', '.join(DEVICES)}")
    if device == "cuda":
        from . import gpu
        why = gpu.why_unavailable()
        if why:
            raise ValueError(f"device='cuda': the GPU backend cannot run here: {why} (device='cpu' runs "
                             "on the CPU engine; docs/gpu.md)")
    return device
# The indenter's smooth speed ramp, the one the smooth_ramp boundary condition runs.
ramp_velocity = _engine.ramp_velocity

MATERIAL_KEYS = ("E", "nu", "rho", "damping", "viscosity")
# nu: Table 1 has none, the registry's; damping (a time here) and viscosity: off
MATERIAL_DEFAULTS = {"nu": P.REGISTRY["nu"].default, "damping": 0.0, "viscosity": 0.0}
DRAG_MODELS = P.DRAG_MODELS

# Parameter name -> (default, description) for Model.set(): the registry's
# engine parameters (icerubble/parameters.py, engine=True); the engine checks
# each value against the registry's ranges (the build writes them into it).
# The engine starts without a time step (step() refuses to run until dt or
# dt_fraction is set), whatever Table 1's dt.
START_UNSET = ("dt", "dt_fraction")
PARAMETERS = {k: (None if k in START_UNSET else p.default,
                  f"{p.doc} [{p.unit}], {p.range_text()}") for k, p in P.ENGINE.items()}
SLEEP_PARAMETERS = ("sleeping", "sleep_velocity", "sleep_force", "sleep_quiet_steps")
# What the engine takes as one struct (Model.set_parameters): the rest.
STRUCT = tuple(k for k in PARAMETERS if k not in START_UNSET)


def _ids(name, ids, n):
    """Node ids as int32, checked against [0, n)."""
    a = np.asarray(ids)
    if a.ndim != 1 or a.size == 0:
        raise ValueError(f"node set '{name}' must be a non-empty 1-D array of node ids")
    if not np.issubdtype(a.dtype, np.integer):
        if not np.all(np.isfinite(a)) or np.any(a != np.round(a)):
            raise ValueError(f"node set '{name}' must contain integer node ids")
    a = a.astype(np.int64)
    if a.min() < 0 or a.max() >= n:
        raise ValueError(f"node set '{name}': node ids must be in [0, {n - 1}] "
                         f"(got {a.min()}..{a.max()})")
    return a.astype(np.int32)


def _flag(name, value):
    if not isinstance(value, (bool, np.bool_)):
        raise ValueError(f"{name} must be True or False (got {value!r})")
    return bool(value)


def _number(name, value):
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise ValueError(f"{name} must be a number (got {value!r})")
    return float(value)


class Model:
    """A FEM-DEM model built from numpy arrays.

    nodes: (N, 2) reference positions [m]; triangles: (M, 3) node ids,
    counter-clockwise; body: (M,) body id per triangle (0..B-1);
    materials: one dict {E, nu, rho, damping} for every body, or a mapping
    body id -> dict, or a sequence of dicts indexed by body id. ``damping`` is
    the strain-rate damping time [s] (viscous stress = damping x elastic
    tensor : rate of Green strain; a mode of angular frequency w is damped at
    ratio w*damping/2), default 0. ``viscosity`` [Pa s] adds a viscous stress
    viscosity x rate of Green strain (~ eta D), default 0. nu defaults to 0.3
    (not given in the paper).
    node_sets: optional mapping name -> node ids.
    device: where ``step`` runs, 'cpu' (the default) or 'cuda': whole steps
    on one GPU (docs/gpu.md), the model's own state read and written as on
    the CPU between calls; refused where the GPU backend cannot run.
    """

    def __init__(self, nodes, triangles, body, materials, node_sets=None, device="cpu"):
        self._device = check_device(device)   # before any work
        self._gpu_timings = dict(steps=0, element_steps=0, total=0.0, makes=0, make_seconds=0.0,
                                 list_rebuilds=0, list_seconds=0.0, host_steps=0, host_step_seconds=0.0)
        self._gpu_steps = None   # device 'cuda': the GPU's steps, kept between calls (step)
        nodes = np.asarray(nodes, dtype=float)
        if nodes.ndim != 2 or nodes.shape[1] != 2 or nodes.shape[0] < 3:
            raise ValueError(f"nodes must be an (N, 2) array with N >= 3 (got shape {nodes.shape})")
        if not np.all(np.isfinite(nodes)):
            raise ValueError("nodes must be finite")
        tri = np.asarray(triangles)
        if tri.ndim != 2 or tri.shape[1] != 3 or tri.shape[0] < 1:
            raise ValueError(f"triangles must be an (M, 3) array with M >= 1 (got shape {tri.shape})")
        tri = _ids("triangles", tri.ravel(), len(nodes)).reshape(-1, 3)
        body = np.asarray(body)
        if body.shape != (len(tri),):
            raise ValueError(f"body must have one id per triangle, shape ({len(tri)},) (got {body.shape})")
        if not np.issubdtype(body.dtype, np.integer) and np.any(body != np.round(body)):
            raise ValueError("body ids must be integers")
        if body.min() < 0:
            raise ValueError("body ids must be >= 0")
        self._m = _engine.Model(nodes, tri, body.astype(np.int32))
        self._set_materials(materials)
        missing = sorted(set(np.unique(body).tolist()) - set(self.materials))
        if missing:
            raise ValueError(f"materials: no material for body id(s) {missing} "
                             f"(E, nu, rho, damping per body)")
        self.node_sets = {}
        for name, ids in (node_sets or {}).items():
            self.add_node_set(name, ids)
        self._params = {k: v for k, (v, _) in PARAMETERS.items()}
        self.set(**{k: v for k, v in self._params.items() if v is not None})

    # ------------------------------------------------------------- setup
    def _set_materials(self, materials):
        nb = self._m.n_bodies
        self._drop_gpu_steps()
        if isinstance(materials, dict) and materials and all(isinstance(k, str) for k in materials):
            per_body = {b: materials for b in range(nb)}
        elif isinstance(materials, dict):
            per_body = dict(materials)
        elif isinstance(materials, (list, tuple)):
            per_body = dict(enumerate(materials))
        else:
            raise ValueError("materials must be a dict {E, nu, rho, damping}, a mapping "
                             "body id -> dict, or a list of dicts")
        for b, mat in per_body.items():
            if not isinstance(b, numbers.Integral) or not 0 <= b < nb:
                raise ValueError(f"materials: body id must be in [0, {nb - 1}] (got {b!r})")
            unknown = set(mat) - set(MATERIAL_KEYS)
            if unknown:
                raise ValueError(f"materials: unknown key(s) {sorted(unknown)}; valid: {MATERIAL_KEYS}")
            full = dict(MATERIAL_DEFAULTS, **mat)
            for k in ("E", "rho"):
                if k not in full:
                    raise ValueError(f"materials: body {b} needs {k}")
            self._m.set_material(int(b), *(_number(k, full[k]) for k in MATERIAL_KEYS))
        self.materials = per_body

    def set(self, **params):
        """Set run parameters (see PARAMETERS); each bad value raises ValueError.

        ``water=False`` is a shorthand for buoyancy=False, drag=False.
        """
        self._drop_gpu_steps()
        if "water" in params:
            w = _flag("water", params.pop("water"))
            params.setdefault("buoyancy", w)
            params.setdefault("drag", w)
        unknown = set(params) - set(PARAMETERS)
        if unknown:
            raise ValueError(f"unknown parameter(s) {sorted(unknown)}; valid: {sorted(PARAMETERS)}")
        if "dt" in params and "dt_fraction" in params:
            raise ValueError("give dt or dt_fraction, not both")
        p = dict(self._params, **{k: v for k, v in params.items() if k not in START_UNSET})
        # one struct, checked once by the engine against the registry's ranges;
        # threads 0 is resolved here, not by the engine from OpenMP's live
        # setting, which gmsh and others change for the whole process
        # (openmp_threads.py)
        self._m.set_parameters(dict({k: p[k] for k in STRUCT}, threads=p["threads"] or default_threads()))
        self._params = p
        if "dt" in params:
            self._m.set_dt(_number("dt", params["dt"]))
        # after the struct: masses, materials and penalty move the stable step
        if "dt_fraction" in params:
            self._m.set_dt_fraction(_number("dt_fraction", params["dt_fraction"]))
        return self

    @property
    def params(self):
        """The parameters as set; dt and dt_fraction as the engine holds them."""
        c = self._m.dt_control()
        return dict(self._params, dt=c["dt"] if c["source"] != "unset" else None,
                    dt_fraction=c["fraction"])

    @property
    def dt(self):
        """The time step in force [s] (explicit, or dt_fraction x the stable step)."""
        return self._m.dt

    def add_node_set(self, name, ids):
        self.node_sets[name] = _ids(name, ids, self._m.n_nodes)

    def _set(self, name_or_ids):
        if isinstance(name_or_ids, str):
            if name_or_ids not in self.node_sets:
                raise ValueError(f"no node set named '{name_or_ids}'; known: {sorted(self.node_sets)}")
            return self.node_sets[name_or_ids]
        return _ids("nodes", name_or_ids, self._m.n_nodes)

    def fix(self, name, x=True, y=True):
        """Hold the nodes of node set ``name`` at rest in x and/or y."""
        self._drop_gpu_steps()
        ids = self._set(name)
        self._m.add_boundary_condition(name, ids, _flag("x", x), _flag("y", y), 0.0, 0.0,
                                       "constant", 0.0, 0.0, np.zeros(0), np.zeros(0))

    def prescribe_velocity(self, name, direction, v_final=None, ramp_time=None, table=None,
                           x=True, y=True):
        """Drive node set ``name`` at velocity direction * s(t).

        Either ``v_final`` [m/s] with ``ramp_time`` [s] (smooth ramp
        s = v_f (t/T - sin(2 pi t/T)/(2 pi)), zero acceleration at both ends;
        ramp_time=0 means a constant speed from the start), or ``table`` =
        (times, speeds): piecewise linear, held constant outside. The
        direction is normalised. x/y choose the prescribed components.
        """
        self._drop_gpu_steps()
        d = np.asarray(direction, dtype=float)
        if d.shape != (2,) or not np.all(np.isfinite(d)) or np.hypot(*d) == 0.0:
            raise ValueError(f"direction must be a finite, non-zero 2-vector (got {direction!r})")
        d = d / np.hypot(*d)
        ids = self._set(name)
        empty = np.zeros(0)
        if table is not None:
            if v_final is not None or ramp_time is not None:
                raise ValueError("give either table or v_final/ramp_time, not both")
            t, v = (np.asarray(c, dtype=float) for c in table)
            self._m.add_boundary_condition(name, ids, _flag("x", x), _flag("y", y), d[0], d[1],
                                           "table", 0.0, 0.0, t, v)
            return
        if v_final is None:
            raise ValueError("prescribe_velocity needs v_final (with ramp_time) or table")
        v_final = _number("v_final", v_final)
        ramp_time = 0.0 if ramp_time is None else _number("ramp_time", ramp_time)
        if ramp_time < 0.0:
            raise ValueError(f"ramp_time must be >= 0 s (got {ramp_time})")
        kind = "smooth_ramp" if ramp_time > 0.0 else "constant"
        self._m.add_boundary_condition(name, ids, _flag("x", x), _flag("y", y), d[0], d[1],
                                       kind, v_final, ramp_time, empty, empty)

    def clear_boundary_conditions(self):
        self._m.clear_boundary_conditions()
        self._drop_gpu_steps()

    def set_positions(self, xy):
        """Current node positions (N, 2); restarts the energy bookkeeping."""
        self._drop_gpu_steps()
        xy = self._node_pairs("positions", xy)
        self._m.set_positions(xy[:, 0], xy[:, 1])

    def set_velocities(self, v):
        """Node velocities (N, 2) [m/s]; restarts the energy bookkeeping."""
        self._drop_gpu_steps()
        v = self._node_pairs("velocities", v)
        self._m.set_velocities(v[:, 0], v[:, 1])

    def _node_pairs(self, name, a):
        a = np.asarray(a, dtype=float)
        if a.shape != (self._m.n_nodes, 2):
            raise ValueError(f"{name} must have shape ({self._m.n_nodes}, 2) (got {a.shape})")
        if not np.all(np.isfinite(a)):
            raise ValueError(f"{name} must be finite")
        return a

    # ------------------------------------------------------------- running
    @property
    def device(self):
        """Where ``step`` runs: 'cpu' or 'cuda' (settable; Model's device)."""
        return self._device

    @device.setter
    def device(self, device):
        self._device = check_device(device)
        self._drop_gpu_steps()

    def _drop_gpu_steps(self):
        """Forget the GPU's steps: the model is changed here (its state, its
        parameters, its boundary conditions, bonds or ledger), so the next
        step on device 'cuda' copies it to the GPU again. The model holds the
        GPU's state already (step downloads it after each call)."""
        self._gpu_steps = None

    def set_reach_origin(self, xy):
        """Where the contact reach guard measures each node's move from (N, 2)
        [m] (a run resumed from another run's rest state: its rest)."""
        xy = self._node_pairs("reach origin", xy)
        self._drop_gpu_steps()
        self._m.set_reach_origin(xy[:, 0], xy[:, 1])

    def step(self, n=1):
        """Advance n time steps. Raises ValueError before stepping if dt is
        above the stable step, InstabilityError if the run goes unstable.
        On device 'cuda' the n steps run on the GPU, and the model holds
        their state when this returns (with the last step's reactions and
        the stresses at the state they ended in). The GPU keeps the state
        between calls: the mesh and state are copied to it on the first call
        and again only after the model is changed here (_drop_gpu_steps), so
        a run's chunks of steps cost only the copy back."""
        if not isinstance(n, numbers.Integral) or n < 0:
            raise ValueError(f"n must be an integer >= 0 (got {n!r})")
        if self._device == "cuda" and n > 0:
            from . import gpu
            t0 = time.perf_counter()
            steps = self._gpu_steps
            made = steps is None or steps.step_count != self._m.step_count
            if made:
                steps = self._gpu_steps = gpu.Steps(self)
            host_before, remakes_before = int(steps.host_steps), int(steps.remakes)
            made_before = 0.0 if made else float(steps.make_seconds)
            hosted_before = float(steps.host_step_seconds)
            lists_before, listed_before = int(steps.list_rebuilds), float(steps.list_seconds)
            try:
                steps.step(int(n))
            except BaseException:
                self._gpu_steps = None   # the model holds the last call's state
                raise
            steps.download()
            # the steps the GPU took (the model's own are in its timings already)
            on_gpu = int(n) - (int(steps.host_steps) - host_before)
            g = self._gpu_timings
            g["steps"] += on_gpu
            g["makes"] += int(steps.remakes) - remakes_before + (1 if made else 0)
            g["make_seconds"] += float(steps.make_seconds) - made_before
            g["list_rebuilds"] += int(steps.list_rebuilds) - lists_before
            g["list_seconds"] += float(steps.list_seconds) - listed_before
            g["host_steps"] += int(steps.host_steps) - host_before
            g["host_step_seconds"] += float(steps.host_step_seconds) - hosted_before
            g["element_steps"] += on_gpu * self.n_triangles
            g["total"] += time.perf_counter() - t0
        else:
            self._m.step(int(n))
        self._follow_splits()

    def evaluate(self):
        """Compute all forces, stresses and reactions at the current state without moving."""
        self._drop_gpu_steps()
        self._m.evaluate()

    def stable_time_step(self):
        """The stable step and its limits (element, contact, drag) as a dict."""
        return self._m.stable_step()

    def reset_contact_masses(self):
        """Back from a larger mass-scaling step (set mass_scaling_dt and dt back
        first): the larger step's mass raises dropped, the current target's
        masses, the raises the present configuration needs; returns how many."""
        self._drop_gpu_steps()
        return self._m.reset_contact_masses()

    def reset_energy(self):
        """Restart the energy bookkeeping (e.g. after settling, before loading)."""
        self._drop_gpu_steps()
        self._m.reset_energy()

    # ------------------------------------------------------------- results
    def _nodes(self, name):
        a = self._m.node_array(name)
        a.flags.writeable = False
        return a

    def _tris(self, name):
        a = self._m.triangle_array(name)
        a.flags.writeable = False
        return a

    @property
    def n_nodes(self):
        return self._m.n_nodes

    @property
    def n_triangles(self):
        return self._m.n_triangles

    @property
    def time(self):
        return self._m.time

    @property
    def step_count(self):
        return self._m.step_count

    @property
    def x(self):
        """Read-only view of node x [m] (valid until nodes are split)."""
        return self._nodes("x")

    @property
    def y(self):
        return self._nodes("y")

    @property
    def positions(self):
        """(N, 2) copy of the current node positions [m]."""
        return np.column_stack((self._nodes("x"), self._nodes("y")))

    @property
    def reference_positions(self):
        return np.column_stack((self._nodes("x0"), self._nodes("y0")))

    @property
    def displacements(self):
        return self.positions - self.reference_positions

    @property
    def velocities(self):
        """(N, 2) node velocities at t - dt/2 of the next step [m/s] (copy)."""
        return np.column_stack((self._nodes("vx"), self._nodes("vy")))

    @property
    def mass(self):
        """Inertial node masses [kg per m width] (view): the lumped masses, raised at
        the nodes that limit the stable step when mass_scaling_dt > 0 (the weight
        always uses the physical lumped mass)."""
        self._m.prepare()
        return self._nodes("mass")

    @property
    def mass_phys(self):
        """Physical lumped node masses [kg per m width] (view): what weighs."""
        self._m.prepare()
        return self._nodes("mass_phys")

    @property
    def triangles(self):
        return self._tris("triangles")

    @property
    def body(self):
        return self._tris("body")

    @property
    def stress(self):
        """(M, 3) view: elastic Cauchy stress sxx, syy, sxy [Pa] per triangle
        at the last force evaluation (tension positive)."""
        return self._tris("stress")

    @property
    def area0(self):
        return self._tris("area0")

    def forces(self, kind="total"):
        """(N, 2) node forces [N/m] of the last step (copy): 'total' (all but
        the boundary reaction), 'internal' (elastic + viscous), 'viscous',
        'contact' (normal), 'cohesive', 'buoyancy', 'reaction'."""
        names = {"total": ("f_x", "f_y"), "internal": ("f_int_x", "f_int_y"),
                 "viscous": ("f_visc_x", "f_visc_y"), "contact": ("f_con_x", "f_con_y"),
                 "cohesive": ("f_coh_x", "f_coh_y"), "reaction": ("r_x", "r_y")}
        if kind == "buoyancy":
            fy = self._nodes("f_buoy_y")
            return np.column_stack((np.zeros_like(fy), fy))
        if kind not in names:
            raise ValueError(f"kind must be one of {sorted(names) + ['buoyancy']} (got {kind!r})")
        a, b = names[kind]
        return np.column_stack((self._nodes(a), self._nodes(b)))

    def reaction(self, nodes):
        """Force [N/m] the boundary conditions exert on a node set (name or
        ids) in the last step: what the boundary pushes with."""
        return np.array(self._m.reaction(self._set(nodes)))

    def energies(self):
        """Energy terms [J/m] (docs/results_format.md names) and the balance residual:
        kinetic + elastic + contact + friction + damping + drag + cohesive
        - initial - work_gravity - work_buoyancy - work_boundary."""
        e = self._m.energy()
        e.pop("started")   # bookkeeping for checkpoints, not an energy
        return e

    def timings(self):
        """Cumulative wall time [s] of the parts of the step, the step count and
        the element-steps (triangles computed, summed over the steps);
        'element_busy' and 'element_wait' [s], one per thread of the element
        pass's team: each thread's time in its own triangles, and waiting at
        the pass's barrier for the others (their spread shows a pass held back
        by one thread). On
        device 'cuda': 'gpu_steps' and 'gpu_total' [s, wall, copies included]
        are the GPU's, added to 'steps', 'element_steps' and 'total'; the
        parts are the CPU's own steps; 'gpu_makes' counts the copies of the
        mesh and state to the GPU (the first, those after a change to the
        model, and the stages made again within the steps) and
        'gpu_make_seconds' is their wall time, part of 'gpu_total';
        'gpu_list_rebuilds' counts the candidate lists rebuilt at the GPU's
        positions and put into its stages in place, 'gpu_list_seconds' their
        wall time (part of 'gpu_total'); 'gpu_host_steps' counts the steps
        the model took itself (bond points split there), 'gpu_host_step_seconds'
        their wall time (the state to the model, its step, its list on the split
        mesh; part of 'gpu_total', the stages then made again in
        'gpu_make_seconds')."""
        t = self._m.timings()
        g = self._gpu_timings
        t.update(steps=t["steps"] + g["steps"], element_steps=t["element_steps"] + g["element_steps"],
                 total=t["total"] + g["total"], gpu_steps=g["steps"], gpu_total=g["total"],
                 gpu_makes=g["makes"], gpu_make_seconds=g["make_seconds"],
                 gpu_list_rebuilds=g["list_rebuilds"], gpu_list_seconds=g["list_seconds"],
                 gpu_host_steps=g["host_steps"], gpu_host_step_seconds=g["host_step_seconds"])
        return t

    def sleep_counts(self):
        """Sleeping far field now: nodes asleep, triangles the next step computes, of all."""
        return dict(asleep_nodes=self._m.asleep_nodes(), awake_triangles=self._m.awake_triangles(),
                    nodes=self.n_nodes, triangles=self.n_triangles)

    @property
    def surface_triangles(self):
        """Ids of triangles with a node on their body's boundary (contact candidates)."""
        self._m.prepare()
        return self._m.surface_triangles()

    @property
    def touching_pairs(self):
        return self._m.touching_pairs

    @property
    def thread_count(self):
        """The threads a step's sums are split over (threads, or for 0 the
        process's OpenMP default, openmp_threads.default_threads): results
        agree across counts only to round-off."""
        return self._m.thread_count()

    def memory_bytes(self):
        """Bytes held by the engine's arrays."""
        return self._m.memory_bytes()

    # ------------------------------------------------------------- freeze bonds
    # Initially rigid cohesive freeze bonds (paper section 2.3, docs/model.md §3.3,
    # docs/freeze_bonds.md): the engine splits a bond point when eq 5 holds and
    # then applies the cohesive pair forces of eqs 8-12.

    def set_bond_points(self, bond_points, *, direction="paper", check_failure=True, mu=None,
                        screen_interval=8, screen_fraction=0.5):
        """Freeze bonds at the bond points of ``bond_points`` (a
        bond_points.BondPoints from find_bond_points on this model's mesh).

        direction: 'paper' (eq 11 as printed) or 'work_conjugate';
        check_failure: False while the scene settles (bonds hold, none splits);
        mu: friction coefficient of the compressive branch of eq 6, None = the
        contact mu (set(mu=...)); screen_interval/screen_fraction: pre-screening
        (docs/freeze_bonds.md), screen_interval=1 checks every point every step.
        """
        self._drop_gpu_steps()
        pairs = bond_pairs(bond_points, self.reference_positions)
        self._m.set_bonds(np.asarray(bond_points.node, dtype=np.int32),
                          np.asarray(bond_points.sigma_cr, dtype=float),
                          np.asarray(bond_points.tau_cr, dtype=float),
                          np.asarray(bond_points.G, dtype=float),
                          pairs["point"], pairs["body_minus"], pairs["body_plus"],
                          pairs["normal"][:, 0].copy(), pairs["normal"][:, 1].copy(),
                          pairs["length"], pairs["frame_p"], pairs["frame_q"])
        self.set_bond_params(direction=direction, check_failure=check_failure, mu=mu,
                             screen_interval=screen_interval, screen_fraction=screen_fraction)

    def set_bond_params(self, **params):
        """Change direction, check_failure, mu, screen_interval, screen_fraction
        (see set_bond_points); ValueError on a bad value."""
        self._drop_gpu_steps()
        valid = ("direction", "check_failure", "mu", "screen_interval", "screen_fraction")
        unknown = set(params) - set(valid)
        if unknown:
            raise ValueError(f"unknown bond parameter(s) {sorted(unknown)}; valid: {valid}")
        p = dict(self._m.bond_params(), **params)
        if p["direction"] not in P.FORCE_DIRECTIONS:
            raise ValueError(f"direction must be {' or '.join(repr(d) for d in P.FORCE_DIRECTIONS)} "
                             f"(got {p['direction']!r})")
        si = p["screen_interval"]
        if isinstance(si, (bool, np.bool_)) or not isinstance(si, numbers.Integral) or si < 1:
            raise ValueError(f"screen_interval must be an integer >= 1 (got {si!r})")
        mu = float("nan") if p["mu"] is None else _number("mu", p["mu"])
        self._m.set_bond_params(mu, p["direction"], _flag("check_failure", p["check_failure"]),
                                int(si), _number("screen_fraction", p["screen_fraction"]))

    @property
    def bond_params(self):
        return self._m.bond_params()

    @property
    def bonds(self):
        """Bond state, events and energy: see BondsView."""
        return BondsView(self._m)

    def _follow_splits(self):
        """Add the nodes split off a node to every node set holding that node,
        so reactions and node-set lookups keep covering both sides."""
        parents = self._m.bond_parents()
        seen = getattr(self, "_parents_seen", 0)
        if len(parents) == seen:
            return
        base = self._m.n_nodes - len(parents)
        for name, ids in self.node_sets.items():
            members = set(ids.tolist())
            new = [base + j for j in range(seen, len(parents)) if parents[j] in members]
            if new:
                self.node_sets[name] = np.concatenate([ids, np.array(new, dtype=np.int32)])
        self._parents_seen = len(parents)

    def checkpoint(self):
        """Everything needed to continue this run bit-identically: the mesh as it
        is now (reference positions, triangles with split nodes, bodies), node
        positions and velocities, node sets, the bond input and bond state
        (which points split, their new nodes, f0, delta_f, delta_m, events) and
        the clock and the energy ledger. Rebuild with
        Model.from_checkpoint(cp, materials), set the same parameters and
        boundary conditions, then restore_checkpoint(cp)."""
        self._follow_splits()
        return {
            "reference_positions": self.reference_positions,
            "triangles": np.array(self.triangles),
            "body": np.array(self.body),
            "positions": self.positions,
            "velocities": self.velocities,
            "node_sets": {k: v.copy() for k, v in self.node_sets.items()},
            "bond_input": self._m.bond_input(),
            "bond_params": self._m.bond_params(),
            "bond_state": self._m.bond_state(),
            "clock": {"time": self._m.time, "step_count": self._m.step_count},
            "energy": self._m.energy(),
            "contact_warm_start": {k: np.asarray(v) for k, v in
                                   zip(("keys", "forces"), self._m.contact_warm_start())},
            "sleep_state": dict(self._m.sleep_state(),
                                **{k: self._params[k] for k in SLEEP_PARAMETERS}),
            # masses the contact reach guard raised mid-run (0: none), and where
            # it measures moves from (a resumed run re-checks at the same steps)
            "mass_floor": np.asarray(self._m.mass_floor()),
            "reach_origin": dict(zip(("x", "y"), self._m.reach_origin())),
        }

    @classmethod
    def from_checkpoint(cls, cp, materials, device="cpu"):
        """A model on the checkpoint's mesh (split nodes included) and node sets."""
        return cls(cp["reference_positions"], cp["triangles"], cp["body"], materials,
                   node_sets=cp["node_sets"], device=device)

    def restore_checkpoint(self, cp):
        """Positions, velocities, bonds and clock of checkpoint ``cp`` into a
        model built by from_checkpoint (boundary conditions and parameters are
        the caller's, as when the run was started)."""
        self._drop_gpu_steps()
        b = cp["bond_input"]
        if len(b["node"]):
            self._m.set_bonds(b["node"], b["sigma_cr"], b["tau_cr"], b["G"], b["pair_point"],
                              b["body_minus"], b["body_plus"], b["nx"], b["ny"], b["length"],
                              b["frame_p"], b["frame_q"], for_restore=True)
            self.set_bond_params(**cp["bond_params"])
        self.set_positions(cp["positions"])
        self.set_velocities(cp["velocities"])
        self._m.restore_bond_state(cp["bond_state"])
        clock = cp.get("clock", cp["bond_state"])  # checkpoints before "clock" kept it there
        self._m.restore_clock(clock["time"], clock["step_count"])
        self._parents_seen = len(self._m.bond_parents())
        if "energy" in cp:
            self._m.restore_energy(cp["energy"])
        if "contact_warm_start" in cp:
            w = cp["contact_warm_start"]
            self._m.set_contact_warm_start(np.asarray(w["keys"], dtype=np.uint64),
                                           np.asarray(w["forces"], dtype=float))
        if "mass_floor" in cp:
            self._m.set_mass_floor(np.asarray(cp["mass_floor"], dtype=float))
        if "reach_origin" in cp:
            r = cp["reach_origin"]
            self._m.set_reach_origin(np.asarray(r["x"], dtype=float), np.asarray(r["y"], dtype=float))
        if "sleep_state" in cp:  # after positions and velocities, which wake every node
            z = cp["sleep_state"]
            self.set(sleeping=bool(np.asarray(z["sleeping"])), sleep_velocity=float(z["sleep_velocity"]),
                     sleep_force=float(z["sleep_force"]), sleep_quiet_steps=int(z["sleep_quiet_steps"]))
            if "f_ref_x" not in z:
                raise ValueError("checkpoint holds the node-level sleep state of physics version 2 "
                                 "(no f_ref_x): it cannot continue under body-level sleeping; start the "
                                 "run again")
            self._m.restore_sleep_state(
                np.asarray(z["sleep"], dtype=np.uint8), np.asarray(z["quiet"], dtype=np.int32),
                np.asarray(z["f_ref_x"], dtype=float), np.asarray(z["f_ref_y"], dtype=float),
                int(np.asarray(z["window_start_step"])), float(np.asarray(z["window_start_time"])),
                *(np.asarray(z["window_" + k], dtype=float) for k in ("cx", "cy", "px", "py", "l")))


class BondsView:
    """Read access to the freeze bonds of a Model (docs/freeze_bonds.md).

    Points are the bond points as passed to set_bond_points; pairs are their
    cohesive pairs (one per ordinary point, one per body pair at a junction).
    """

    def __init__(self, m):
        self._m = m

    @property
    def counts(self):
        """points, pairs, split (points), failed (pairs), late_detections, checks."""
        return self._m.bond_counts()

    def state(self):
        """The full bond state as numpy arrays (checkpoint content)."""
        return self._m.bond_state()

    def energy(self):
        """work done against the cohesive forces, stored (recoverable),
        dissipated = work - stored, dissipation_effective = sum 1/2 f0 delta_m
        (G l per fully failed pair) [J/m], since the bonds were set."""
        return self._m.bond_energy()

    def tractions(self):
        """(t_n, t_t) per pair at its last check [Pa] (eq 7)."""
        return self._m.bond_tractions()

    def pairs(self):
        """Static pair data: point, body_minus, body_plus, normal, length."""
        b = self._m.bond_input()
        return {"point": b["pair_point"], "body_minus": b["body_minus"], "body_plus": b["body_plus"],
                "normal": np.column_stack((b["nx"], b["ny"])), "length": b["length"]}

    def events(self):
        """Event log (docs/results_format.md /bonds): per bond point t_split,
        x_split, y_split, t_fail (when its last pair failed fully),
        delta_n_fail, delta_t_fail and mode of that pair (0 intact or still
        cohesive, 1 tensile, 2 shear; NaN times if it has not happened); per
        pair the same with the prefix pair_, and pair_point, pair_f0,
        pair_delta_f, pair_split_tn, pair_split_tt (traction at the split)."""
        s = self._m.bond_state()
        b = self._m.bond_input()
        point = b["pair_point"]
        P = len(b["node"])
        ev = {"t_split": s["t_split"], "x_split": s["x_split"], "y_split": s["y_split"]}
        t_fail = np.full(P, np.nan)
        dn = np.full(P, np.nan)
        dt = np.full(P, np.nan)
        x = np.full(P, np.nan)
        y = np.full(P, np.nan)
        mode = np.zeros(P, dtype=np.int8)
        done = np.ones(P, dtype=bool)
        np.logical_and.at(done, point, s["pair_state"] == int(_engine.PairState.failed))
        for k in np.argsort(s["t_fail"], kind="stable"):
            p = point[k]
            if done[p] and np.isfinite(s["t_fail"][k]):
                t_fail[p], dn[p], dt[p] = s["t_fail"][k], s["dn_fail"][k], s["dt_fail"][k]
                x[p], y[p], mode[p] = s["x_fail"][k], s["y_fail"][k], s["mode"][k]
        ev.update(t_fail=t_fail, x_fail=x, y_fail=y, delta_n_fail=dn, delta_t_fail=dt, mode=mode)
        ev.update(pair_point=point, pair_t_fail=s["t_fail"], pair_x_fail=s["x_fail"],
                  pair_y_fail=s["y_fail"], pair_delta_n_fail=s["dn_fail"],
                  pair_delta_t_fail=s["dt_fail"], pair_mode=s["mode"], pair_f0=s["f0"],
                  pair_delta_f=s["delta_f"], pair_split_tn=s["split_tn"],
                  pair_split_tt=s["split_tt"])
        return ev


def rectangle_mesh(nx, ny, hx, hy=None, origin=(0.0, 0.0)):
    """Structured mesh of an nx-by-ny grid of hx-by-hy cells, each cut into two
    counter-clockwise triangles along the diagonal from lower left to upper
    right. Returns nodes (N, 2) and triangles (2 nx ny, 3); node j*(nx+1)+i
    is at origin + (i hx, j hy)."""
    hy = hx if hy is None else hy
    i, j = np.meshgrid(np.arange(nx + 1), np.arange(ny + 1), indexing="xy")
    nodes = np.column_stack((origin[0] + i.ravel() * hx, origin[1] + j.ravel() * hy))
    ci, cj = np.meshgrid(np.arange(nx), np.arange(ny), indexing="xy")
    a = (cj * (nx + 1) + ci).ravel()
    b, c, d = a + 1, a + nx + 1, a + nx + 2
    tri = np.empty((2 * a.size, 3), dtype=np.int32)
    tri[0::2] = np.column_stack((a, b, d))
    tri[1::2] = np.column_stack((a, d, c))
    return nodes, tri
