"""The GPU backend (docs/gpu.md), as far as it is built: the body-force stage
of a step (elements, buoyancy and drag, the node gather) on one CUDA GPU, from
the same per-triangle, per-body and per-node functions the CPU engine runs.

    from icerubble.engine import gpu
    if gpu.available():
        stage = gpu.BodyForces(model)     # copies the mesh and the state
        stage.run(); fields = stage.fields()

`compare(model)` checks it against the CPU: the element and buoyancy fields
bit for bit; quadratic drag's body constants and the energy sum, which the
GPU sums in another (fixed) order, to round-off.
"""
import os

import numpy as np

from .. import _engine

# A build without a CUDA toolkit has the backend on the CPU emulation of the
# CUDA runtime (engine/src/cuda/emulation/): the backend's own code, run on
# one CPU thread, slowly, for its tests where no GPU is. It is reached only
# with this variable set to 1, so that device='cuda' is never a slow CPU run
# by surprise.
EMULATION_ENV = "ICERUBBLE_GPU_EMULATION"

# Per-node and per-triangle fields the stage writes with the CPU's arithmetic
# in the CPU's order: each must equal the CPU's bits.
EXACT_FIELDS = ("f_int_x", "f_int_y", "f_visc_x", "f_visc_y", "f_buoy_y", "stress", "energy")
# ... and those summed per body in another order on the GPU (quadratic drag:
# a warp per body): to round-off, relative to the field's largest entry.
SUMMED_FIELDS = ("drag_k",)
FIELDS = EXACT_FIELDS + SUMMED_FIELDS
ROUND_OFF = 1e-12
# the stage's kernels, in launch order (BodyForces.stage_seconds)
STAGES = ("drag", "triangles", "gather", "energy_sum")


def built():
    """Whether this build of the engine has the GPU backend (a CUDA toolkit was found)."""
    return bool(_engine.cuda_built())


def emulation_built():
    """Whether this build has the backend on the CPU emulation of the CUDA runtime."""
    return bool(_engine.cuda_emulated())


def emulated():
    """Whether the backend runs here on the CPU emulation (built so, and EMULATION_ENV=1)."""
    return emulation_built() and os.environ.get(EMULATION_ENV) == "1"


def device_name():
    """The GPU the backend sees ('' when there is none or the build has no backend;
    the emulation's name where it runs)."""
    return _engine.cuda_device() if built() or emulated() else ""


def available():
    """Whether the GPU backend can run here: built with it, and a GPU visible."""
    return bool(device_name())


def why_unavailable():
    """A sentence saying why the GPU backend cannot run here ('' if it can)."""
    if emulated():
        return ""
    if not built():
        why = "this build has no GPU backend (no CUDA toolkit was found when it was built)"
        if emulation_built():
            why += f"; its CPU emulation, a test bench, runs with {EMULATION_ENV}=1"
        return why
    if not device_name():
        return "no CUDA GPU is visible"
    return ""


def memory_counts():
    """The GPU memory blocks of this process (engine/src/cuda/device_memory.hpp):
    'allocations' (fresh, cudaMalloc'd), 'reuses' (from the cache of blocks
    given back), 'waits' (device waits before a reuse), 'cached_bytes',
    'used_bytes'; all zero in a build without the backend."""
    return dict(_engine.device_memory_counts())


def _require():
    """Raise RuntimeError saying why, unless the GPU backend can run here."""
    reason = why_unavailable()
    if reason:
        raise RuntimeError(f"the GPU backend cannot run: {reason}")


class _Stage:
    """One stage of the step on the GPU, made from `model` (an engine.Model):
    DEVICE names its class in the compiled module."""
    DEVICE = None

    def __init__(self, model):
        _require()
        self._model = model
        self._d = getattr(_engine, self.DEVICE)(model._m)

    def run(self):
        self._d.run()

    def seconds_per_run(self, repeats=1000):
        """Mean GPU time of one run [s] (device events, after three warm-ups)."""
        return self._d.time_per_run(int(repeats))

    def fields(self):
        return self._d.fields()


def differences(cpu, gpu, keys):
    """{key: (entries whose bits differ, largest difference relative to the
    CPU field's largest entry)}; (-1, inf) where the shapes differ."""
    out = {}
    for k in keys:
        a = np.atleast_1d(np.ascontiguousarray(cpu[k], float))
        b = np.atleast_1d(np.ascontiguousarray(gpu[k], float))
        if a.shape != b.shape:
            out[k] = (-1, np.inf)
            continue
        scale = max(float(np.abs(a).max(initial=0.0)), 1e-300)
        out[k] = (int(np.count_nonzero(a.view(np.uint64) != b.view(np.uint64))),
                  float(np.abs(a - b).max(initial=0.0)) / scale)
    return out


class BodyForces(_Stage):
    """The body-force stage of `model` (an engine.Model) on the GPU; its
    seconds_per_run replays the stage's launches as one CUDA graph."""
    DEVICE = "DeviceBodyForces"

    def upload_state(self):
        """Copy the model's positions and velocities now."""
        self._d.upload_state(self._model._m)

    def stage_seconds(self, repeats=200):
        """Mean GPU time of each stage [s], launched one by one: quadratic
        drag, triangles (elements, water, energy partials), node gather,
        energy sum."""
        return dict(zip(STAGES, self._d.stage_times(int(repeats))))


def cpu_fields(model):
    """The CPU's fields of the same stage, from the model's last evaluation."""
    return _engine.body_force_fields(model._m)


def compare(model):
    """Evaluate `model` on the CPU and its body-force stage on the GPU at the
    same state. Returns {field: (entries whose bits differ, largest difference
    relative to the field's largest entry)} for FIELDS and 'elastic_energy',
    and 'ok': the EXACT_FIELDS equal, the others within ROUND_OFF."""
    model.evaluate()
    cpu = cpu_fields(model)
    stage = BodyForces(model)
    stage.run()
    gpu = stage.fields()
    out = differences(cpu, gpu, FIELDS + ("elastic_energy",))
    out["ok"] = (all(out[k][0] == 0 for k in EXACT_FIELDS)
                 and all(out[k][1] <= ROUND_OFF for k in SUMMED_FIELDS + ("elastic_energy",)))
    return out


# NodeUpdate's sums, in the order the GPU returns them (model/update_kernel.hpp NodeWork)
UPDATE_TERMS = ("kinetic2_new", "kinetic2_old", "viscous", "local_damping", "contact", "friction", "cohesive",
                "gravity", "buoyancy", "drag", "boundary", "elastic_new", "elastic_old")


class NodeUpdate(_Stage):
    """The central-difference update of `model` (an engine.Model) on the GPU,
    from the node state and the forces of the model's last evaluation (timed
    runs repeat the update in place)."""
    DEVICE = "DeviceNodeUpdate"

    def fields(self):
        f = self._d.fields()
        f["sums"] = dict(zip(UPDATE_TERMS, np.asarray(f["sums"]).tolist()))
        return f


def ledger_of_one_step(sums, dt):
    """The ledger terms one step adds from its sums (Model::update_positions),
    as engine.Model.energies() names them, for a ledger reset just before."""
    s = sums
    return dict(kinetic=0.5 * s["kinetic2_new"], damping=-dt * (s["viscous"] + s["local_damping"]),
                contact=-dt * s["contact"], friction=-dt * s["friction"], work_gravity=dt * -s["gravity"],
                work_buoyancy=dt * s["buoyancy"], drag=dt * s["drag"], work_boundary=dt * s["boundary"])


def compare_update(model):
    """One step of `model` on the CPU against its update on the GPU from the
    same forces (the model's evaluation at the step's start). Returns
    {field: (entries whose bits differ, largest difference relative to the
    field's largest entry)} for x, y, vx, vy, and the ledger terms' largest
    difference relative to the largest of them ('ledger'), and 'ok': the
    node fields equal, the ledger within ROUND_OFF; None when a bond point
    split in that step (the CPU's step then has other forces)."""
    model.evaluate()
    stage = NodeUpdate(model)
    stage.run()
    gpu = stage.fields()
    n = model.n_nodes
    model.reset_energy()
    model.step(1)
    if model.n_nodes != n:
        return None
    xy, v = model.positions, model.velocities
    cpu = dict(x=xy[:, 0], y=xy[:, 1], vx=v[:, 0], vy=v[:, 1])
    out = differences(cpu, gpu, ("x", "y", "vx", "vy"))
    e = model.energies()
    ledger = ledger_of_one_step(gpu["sums"], model.dt)
    scale = max(max(abs(e[k]) for k in ledger), 1e-300)
    out["ledger"] = max(abs(ledger[k] - e[k]) for k in ledger) / scale
    out["ok"] = all(out[k][0] == 0 for k in ("x", "y", "vx", "vy")) and out["ledger"] <= ROUND_OFF
    return out


class ContactNormal(_Stage):
    """The normal contact pass of `model` (an engine.Model) on the GPU: the
    pair kernel over the candidate list of the model's last contact pass."""
    DEVICE = "DeviceContactNormal"

    @property
    def candidates(self):
        return self._d.candidates


def compare_contact(model):
    """Evaluate `model` on the CPU and its normal contact pass on the GPU at
    the same state (the CPU's candidate list). Returns {'f_con_x', 'f_con_y':
    (entries whose bits differ, largest difference relative to the field's
    largest entry)}, 'touching' (CPU, GPU), 'energy_rel' (summed in another
    order on the GPU) and 'ok'."""
    model.evaluate()
    cpu = _engine.contact_fields(model._m)
    stage = ContactNormal(model)
    stage.run()
    gpu = stage.fields()
    out = differences(cpu, gpu, ("f_con_x", "f_con_y"))
    out["touching"] = (int(cpu["touching"]), int(gpu["touching"]))
    out["energy_rel"] = abs(gpu["energy"] - cpu["energy"]) / max(abs(cpu["energy"]), 1e-300)
    out["ok"] = (out["f_con_x"][0] == 0 and out["f_con_y"][0] == 0 and out["touching"][0] == out["touching"][1]
                 and out["energy_rel"] <= ROUND_OFF)
    return out


def compare_broad_phase(model):
    """The contact candidates searched on the GPU at `model`'s positions
    (cuda/broad_phase.cu) against the CPU's search there, both laid out as the
    contact stages read them (the nodes, keys and each node's entries):
    {'same': every array and the skin equal, 'candidates': (CPU, GPU),
    'skin': (CPU, GPU)}."""
    _require()
    model._m.prepare()
    gpu = _engine.DeviceBroadPhase(model._m).search(model._m)
    cpu = _engine.broad_phase_layout(model._m)
    same = all(np.array_equal(cpu[k], gpu[k]) for k in ("node", "key", "start", "entry")) and cpu["skin"] == gpu["skin"]
    return dict(same=bool(same), candidates=(len(cpu["key"]), len(gpu["key"])), skin=(cpu["skin"], gpu["skin"]))


class BondCheck(_Stage):
    """The bond check (eqs 5-7) of `model` (an engine.Model) on the GPU, every
    intact bond point at the model's state (stresses of its last evaluation)."""
    DEVICE = "DeviceBondCheck"


def compare_bond_check(model):
    """Evaluate `model` on the CPU, then check its intact bond points on the CPU
    and on the GPU with the same kernel. Returns {'ratio', 'tn', 'tt': entries
    whose bits differ}, 'plan' (points in the CPU's plan, in the GPU's),
    'same_plan' and 'ok' (every field the CPU's bits, the same plan)."""
    model.evaluate()
    cpu = _engine.bond_check_fields(model._m)
    stage = BondCheck(model)
    stage.run()
    gpu = stage.fields()
    # NaN where a point is not checked (split): the same bits on both
    out = {k: n for k, (n, _) in differences(cpu, gpu, ("ratio", "tn", "tt")).items()}
    out["plan"] = (len(cpu["plan"]), len(gpu["plan"]))
    out["same_plan"] = bool(np.array_equal(cpu["plan"], gpu["plan"]))
    out["ok"] = out["same_plan"] and out["ratio"] == out["tn"] == out["tt"] == 0
    return out


class CohesiveForces(_Stage):
    """The cohesive forces (eqs 8-12) of `model`'s opened pairs on the GPU,
    at the model's state (its forces of the last evaluation); the pairs'
    history is not advanced."""
    DEVICE = "DeviceCohesiveForces"


# per opened pair and per node, with the CPU's arithmetic in the CPU's order
COHESIVE_EXACT = ("f_coh_x", "f_coh_y", "fpx", "fpy", "delta_m", "failed", "mode")
# summed over the pairs in a fixed tree on the GPU, one by one on the CPU
COHESIVE_SUMMED = ("work", "stored", "dissipation")


def compare_cohesive(model):
    """Evaluate `model`'s forces up to the cohesive pass on the CPU, then step
    its opened pairs' cohesive law on the CPU and on the GPU with the same
    kernel from the same state.
    Returns {field: (entries whose bits differ, largest relative difference)}
    for COHESIVE_EXACT and COHESIVE_SUMMED, 'pairs' (opened pairs) and 'ok'
    (the exact fields the CPU's bits, the sums within ROUND_OFF)."""
    model._m.evaluate_before_cohesive()   # the forces as the cohesive pass reads them
    cpu = _engine.cohesive_fields(model._m)
    stage = CohesiveForces(model)
    stage.run()
    gpu = stage.fields()
    model.evaluate()   # every stage's forces again
    out = differences(cpu, gpu, COHESIVE_EXACT + COHESIVE_SUMMED)
    out["pairs"] = len(cpu["fpx"])
    out["ok"] = (all(out[k][0] == 0 for k in COHESIVE_EXACT)
                 and all(out[k][1] <= ROUND_OFF for k in COHESIVE_SUMMED))
    return out


class Friction(_Stage):
    """Coulomb friction (eq 4) on the GPU over the candidate list of `model`'s
    last contact pass: which candidates touch (the pair kernel), their
    colouring, the sweeps colour by colour from the warm start the model
    holds, on the forces its last evaluation assembled before friction."""
    DEVICE = "DeviceFriction"

    @property
    def candidates(self):
        return self._d.candidates


def compare_friction(model, earlier_list=None, shared_nodes=None):
    """Evaluate `model` on the CPU (which leaves the friction's warm start as
    it was), then solve the same friction on the GPU from the same candidate
    list and warm start (the GPU finds the touching pairs itself).
    Returns {'lambda', 'f_x', 'f_y': (entries whose bits differ, largest
    relative difference)} (f_x, f_y where a component is not prescribed: the
    boundary conditions overwrite the others after friction), 'power_rel'
    (summed in another order: relative to the power's scale, sum |lambda| times
    the largest node speed), 'pairs' (touching: CPU, GPU), 'colours' (CPU, GPU), 'colour' (pairs
    the GPU's colouring put in another colour than the CPU's), 'rounds' (the
    GPU colouring's parallel rounds), 'again' (a second run from the same
    state gives the same bits), 'colourings' (made by the two runs: the
    second keeps the first's), 'local_nodes' and 'ok'. earlier_list: how many of a
    pair's earlier neighbours on each node the GPU's colouring keeps listed
    (None: its default; fewer makes more nodes walked, to test that walk).
    shared_nodes: how many of the touching pairs' nodes the sweeps may keep in
    shared memory (None: its default; fewer than they have: the sweeps read
    the nodes' arrays, to test that path); 'local_nodes' says how many they
    kept (-1: none)."""
    model.evaluate()
    cpu = _engine.friction_fields(model._m)
    stage = Friction(model)
    if earlier_list is not None:
        stage._d.set_earlier_list(int(earlier_list))
    if shared_nodes is not None:
        stage._d.set_shared_nodes(int(shared_nodes))
    stage.run()
    gpu = stage.fields()
    # run again from the same state: the touching pairs are the colouring's,
    # which is kept, and the forces are the same bits
    stage.run()
    again = stage.fields()
    free_x = (cpu["constrained"] & 1) == 0
    free_y = (cpu["constrained"] & 2) == 0
    out = differences(dict(lambda_=cpu["lambda"], f_x=cpu["f_x"][free_x], f_y=cpu["f_y"][free_y]),
                      dict(lambda_=gpu["lambda"], f_x=gpu["f_x"][free_x], f_y=gpu["f_y"][free_y]),
                      ("lambda_", "f_x", "f_y"))
    out["lambda"] = out.pop("lambda_")
    c_cpu, c_gpu = np.asarray(cpu["colour"]), np.asarray(gpu["colour"])
    out["colour"] = int(np.count_nonzero(c_cpu != c_gpu)) if c_cpu.shape == c_gpu.shape else -1
    out["rounds"] = int(gpu["rounds"])
    speed = float(np.abs(model.velocities).max(initial=0.0))
    scale = max(float(np.abs(cpu["lambda"]).sum()) * speed, abs(cpu["power"]), 1e-300)
    out["power_rel"] = abs(gpu["power"] - cpu["power"]) / scale
    out["pairs"] = (len(cpu["lambda"]), len(gpu["lambda"]))
    out["colours"] = (int(cpu["colours"]), int(gpu["colours"]))
    out["colourings"] = int(again["colourings"])
    out["local_nodes"] = int(gpu["local_nodes"])
    out["again"] = all(np.array_equal(gpu[k], again[k]) for k in ("lambda", "f_x", "f_y", "colour", "power"))
    out["ok"] = (all(out[k][0] == 0 for k in ("lambda", "f_x", "f_y")) and out["power_rel"] <= ROUND_OFF
                 and out["again"] and out["colourings"] == 1
                 and out["pairs"][0] == out["pairs"][1] and out["colours"][0] == out["colours"][1]
                 and out["colour"] == 0)
    return out


class Steps:
    """Whole steps of `model` (an engine.Model) on the GPU, as far as they are
    built (cuda/device_step.hpp): models without the sleeping far field. Copies the model's mesh, state, boundary
    conditions, clock, ledger, friction warm start and bonds' state;
    `step(n)` runs n steps of Model.step, on the GPU but for the steps whose
    bond check splits a point, which the model takes itself (`host_steps`
    counts them); where the candidate list is due, the model's broad phase
    builds it at the GPU's positions and the contact stages take it in place
    (`list_rebuilds` counts them); `download()` puts the
    state back into the model, which continues from there."""

    def __init__(self, model):
        _require()
        self._model = model
        self._d = _engine.DeviceStep(model._m)

    def step(self, n=1):
        self._d.step(int(n))
        self._model._follow_splits()   # splits are the model's own steps: its node sets follow

    def download(self):
        self._d.download(self._model._m)

    def reaction(self, nodes):
        """As engine.Model.reaction, from the last GPU step."""
        return np.array(self._d.reaction(self._model._set(nodes)))

    @property
    def time(self):
        return self._d.time

    @property
    def step_count(self):
        return self._d.step_count

    @property
    def host_steps(self):
        return self._d.host_steps

    @property
    def remakes(self):
        """Times the stages were made again from the model (each a copy of the mesh and state)."""
        return self._d.remakes

    @property
    def host_step_seconds(self):
        """Wall time [s] in the steps the model took itself (the state to it, its step)."""
        return self._d.host_step_seconds

    @property
    def list_rebuilds(self):
        return self._d.list_rebuilds

    @property
    def graph_instantiations(self):
        """A batch's graph captured and instantiated afresh (the first, and
        where its launches changed)."""
        return self._d.graph_instantiations

    @property
    def colourings(self):
        """Times friction coloured its touching pairs: a step whose touching
        pairs are those of the colouring before keeps it (cuda/friction.cu)."""
        return self._d.colourings

    @property
    def graph_updates(self):
        """A batch's graph captured again and put into the executable graph in
        place (cudaGraphExecUpdate: the same launches, other arrays or sizes)."""
        return self._d.graph_updates

    @property
    def list_seconds(self):
        """Wall time [s] in the candidate list's rebuilds (positions from the GPU, the broad phase, the copies back)."""
        return self._d.list_seconds

    @property
    def make_seconds(self):
        """Wall time [s] making the stages from the model (the first making too: allocations, copies)."""
        return self._d.make_seconds


# The bonds' totals the GPU sums over the pairs in another (fixed) order
BOND_SUMS = ("work", "stored", "dissipation_effective")


def compare_steps(make_model, n, nodes=None):
    """`n` steps of make_model() on the CPU against n steps of another
    make_model() on the GPU (Steps): returns {field: (entries whose bits
    differ, largest difference relative to the field's largest entry)} for
    x, y, vx, vy, 'ledger' (the ledger's terms' largest difference relative
    to the largest of them: the GPU sums in another fixed order), 'reaction'
    on node set `nodes` (the same, when given), 'time' (equal), 'host_steps'
    (steps the model took itself: bond points split), 'list_rebuilds' (the
    candidate list rebuilt in place), 'cpu_list_builds' (the CPU model's
    candidate lists built in its n steps, its first included),
    'graph_instantiations' and 'graph_updates' (Steps'), 'remakes' (times
    the GPU's stages were made again from the model: after those steps, a
    re-bound contact reach) and 'ok'. A
    bonded model adds 'bonds': the bond state's array fields whose bits
    differ anywhere (a list of names; the split and failure
    records, the pairs' history, the screening flags), 'bond_sums' (the
    largest relative difference of BOND_SUMS), 'bond_counts' ((split,
    failed) on the CPU, on the GPU) and 'checks' (points evaluated: equal)."""
    cpu_model, gpu_model = make_model(), make_model()
    builds = cpu_model._m.contact_list_builds
    cpu_model.step(n)
    builds = cpu_model._m.contact_list_builds - builds
    steps = Steps(gpu_model)
    steps.step(n)
    out = {}
    if nodes is not None:
        r_cpu, r_gpu = cpu_model.reaction(nodes), steps.reaction(nodes)
        out["reaction"] = float(np.abs(r_gpu - r_cpu).max() / max(np.abs(r_cpu).max(), 1e-300))
    steps.download()
    out["host_steps"] = steps.host_steps
    out["list_rebuilds"] = steps.list_rebuilds
    out["graph_instantiations"], out["graph_updates"] = steps.graph_instantiations, steps.graph_updates
    out["cpu_list_builds"] = builds
    out["remakes"] = steps.remakes
    out["colourings"] = steps.colourings

    def state(m):
        xy, v = m.positions, m.velocities
        return dict(x=xy[:, 0], y=xy[:, 1], vx=v[:, 0], vy=v[:, 1])
    out.update(differences(state(cpu_model), state(gpu_model), ("x", "y", "vx", "vy")))
    e_cpu, e_gpu = cpu_model.energies(), gpu_model.energies()
    terms = [k for k, v in e_cpu.items() if isinstance(v, float)]
    scale = max(max(abs(e_cpu[k]) for k in terms), 1e-300)
    out["ledger"] = max(abs(e_gpu[k] - e_cpu[k]) for k in terms) / scale
    out["time"] = cpu_model.time == gpu_model.time
    out["ok"] = (all(out[k][0] == 0 for k in ("x", "y", "vx", "vy")) and out["ledger"] <= ROUND_OFF
                 and out.get("reaction", 0.0) <= ROUND_OFF and out["time"])
    if cpu_model.bonds.counts["points"]:
        out.update(compare_bond_states(cpu_model, gpu_model))
        out["ok"] = (out["ok"] and not out["bonds"] and out["bond_sums"] <= ROUND_OFF and out["checks"]
                     and out["bond_counts"][0] == out["bond_counts"][1])
    return out


def compare_bond_states(cpu_model, gpu_model):
    """The bond states of two models stepped alike (compare_steps)."""
    a, b = cpu_model.bonds.state(), gpu_model.bonds.state()
    arrays = [k for k, v in a.items() if np.ndim(v) == 1]
    differ = [k for k in arrays
              if np.shape(a[k]) != np.shape(b[k])
              or not np.array_equal(np.ascontiguousarray(a[k]).view(np.uint8),
                                    np.ascontiguousarray(b[k]).view(np.uint8))]
    sums = max(abs(float(b[k]) - float(a[k])) / max(abs(float(a[k])), 1e-300) for k in BOND_SUMS)

    def counts(m):
        c = m.bonds.counts
        return (c["split"], c["failed"])
    return {"bonds": differ, "bond_sums": sums, "checks": int(a["checks"]) == int(b["checks"]),
            "bond_counts": (counts(cpu_model), counts(gpu_model))}


def compare_device(make_model, chunks, n, nodes=None, between=None):
    """A model of make_model() stepped on device 'cuda' (Model.step, the GPU's
    steps kept between calls) against another on the CPU, `chunks` calls of
    n steps each, as a run steps it; between(model, k), if given, changes
    both models after call k (the change must reach the GPU's next steps):
    {'same': positions, velocities, bond counts and, for node set `nodes`,
    the reaction equal after every call, 'gpu_steps': the steps the GPU took,
    'remade': how many times the GPU's steps were made from the model,
    'makes': Model.timings' gpu_makes, 'host_makes': the steps the model took
    (each followed by the stages made again), 'host_steps': Model.timings'
    gpu_host_steps (the same steps, as the GPU's steps counted them),
    'list_rebuilds': Model.timings' gpu_list_rebuilds}."""
    cpu, on_gpu = make_model(), make_model()
    on_gpu.device = "cuda"
    same, made, steps = True, 0, None
    for k in range(chunks):
        for m in (cpu, on_gpu):
            m.step(n)
        if on_gpu._gpu_steps is not steps:
            made, steps = made + 1, on_gpu._gpu_steps
        same = same and (np.array_equal(cpu.positions, on_gpu.positions)
                         and np.array_equal(cpu.velocities, on_gpu.velocities)
                         and cpu.bonds.counts == on_gpu.bonds.counts
                         and (nodes is None or np.array_equal(cpu.reaction(nodes), on_gpu.reaction(nodes))))
        if between is not None and k < chunks - 1:
            for m in (cpu, on_gpu):
                between(m, k)
    t = on_gpu.timings()
    return dict(same=bool(same), gpu_steps=t["gpu_steps"], remade=made, makes=t["gpu_makes"],
                host_makes=t["steps"] - t["gpu_steps"], host_steps=t["gpu_host_steps"],
                list_rebuilds=t["gpu_list_rebuilds"])
