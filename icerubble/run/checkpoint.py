"""Checkpoints of a punch-through run: the engine state (including split
nodes and bond states), what has been recorded, and the driver's phase.

Written atomically (icerubble.files.h5io.AtomicH5), so a checkpoint on disk is
always a complete one; a run killed while writing keeps the previous one.
Only the code that wrote a checkpoint continues it (same source_hash,
icerubble/code_identity.py): any other is refused, saying which wrote it.
"""
import json
import os

import h5py
import numpy as np

from ..code_identity import refuse_other_code
from ..files.h5io import AtomicH5, open_complete, read_checked, read_tree, write_tree
from ..files.recorder import ENERGY_TERMS, read_recorder_state, snapshot_travels, write_recorder_state
from ..parameters import settle_free
from .run_identity import PHYSICS_VERSION

CHECKPOINT_FORMAT = "icerubble-checkpoint"


def checkpoint_path(out_path):
    """Where the run writing result `out_path` (NAME.h5) keeps its checkpoint."""
    out_path = os.fspath(out_path)
    return (out_path[:-3] if out_path.endswith(".h5") else out_path) + ".checkpoint.h5"


def save(run, path, driver_attrs=None, shared=False):
    """driver_attrs: more attributes of /driver (a shared rest state's settle
    identity); shared: a file other runs may be writing at the same time."""
    with AtomicH5(path, CHECKPOINT_FORMAT, writer_part=shared) as f:
        d = f.create_group("driver")
        for k, v in (driver_attrs or {}).items():
            d.attrs[k] = v
        for k, v in run.state.to_attrs().items():
            d.attrs[k] = v
        if run.recorder.meta.get("rest_state_shared"):   # the result names it after a resume too
            d.attrs["rest_state_shared_from"] = run.recorder.meta["rest_state_from"]
        # the code that settled a shared rest state or another run's rest state this run loaded from
        for k in ("rest_state_code_version", "rest_state_source_hash"):
            if k in run.recorder.meta:
                d.attrs[k] = run.recorder.meta[k]
        d.attrs["params"] = json.dumps(run.params)
        d.attrs["physics_version"] = PHYSICS_VERSION
        write_tree(f.create_group("engine"), run.model.checkpoint())
        write_recorder_state(f.create_group("recorder"), run.recorder.state())


def _text(v):
    """A string attribute as h5py returns it (bytes or str) as str."""
    return v.decode() if isinstance(v, bytes) else str(v)


def check(f):
    """Everything restore() reads, checked before any of it is used: groups,
    shapes, dtypes, finiteness and ids in range. Raises ValueError naming the
    file and the dataset or attribute (a checkpoint is written atomically, so
    this catches files from elsewhere: another version, another run, damage)."""
    what = "checkpoint"
    where = f"{what} {f.filename!r}"
    for g in ("driver", "engine", "recorder", "engine/node_sets", "engine/bond_state", "engine/bond_input"):
        if g not in f or not isinstance(f[g], h5py.Group):
            raise ValueError(f"{where}: group {g!r} missing")
    d = f["driver"]
    for k in ("phase", "params", "vtu_entries"):
        if k not in d.attrs:
            raise ValueError(f"{where}: attribute driver/{k} missing")
    phase = _text(d.attrs["phase"])
    if phase not in ("settle", "load"):
        raise ValueError(f"{where}: driver/phase is {phase!r}, expected 'settle' or 'load'")
    for k in ("params", "vtu_entries"):
        try:
            json.loads(d.attrs[k])
        except (TypeError, ValueError) as e:
            raise ValueError(f"{where}: driver/{k} is not JSON ({e})") from None
    x0 = read_checked(f, "engine/reference_positions", shape=(None, 2), what=what)
    n = len(x0)
    read_checked(f, "engine/positions", shape=(n, 2), what=what)
    read_checked(f, "engine/velocities", shape=(n, 2), what=what)
    if "engine/mass_floor" in f:
        floor = read_checked(f, "engine/mass_floor", shape=(n,), what=what)
        if (floor < 0).any():
            raise ValueError(f"{where}, dataset 'engine/mass_floor': negative masses")
    tri = read_checked(f, "engine/triangles", shape=(None, 3), kind="i", what=what)
    read_checked(f, "engine/body", shape=(len(tri),), kind="i", what=what)
    if tri.size and (tri.min() < 0 or tri.max() >= n):
        raise ValueError(f"{where}, dataset 'engine/triangles': node ids {tri.min()}..{tri.max()} "
                         f"outside [0, {n - 1}]")
    for name in f["engine/node_sets"]:
        ids = read_checked(f, f"engine/node_sets/{name}", shape=(None,), kind="i", what=what)
        if ids.size and (ids.min() < 0 or ids.max() >= n):
            raise ValueError(f"{where}, dataset 'engine/node_sets/{name}': node ids outside [0, {n - 1}]")
    clock = f["engine/clock"].attrs if "engine/clock" in f else f["engine/bond_state"].attrs
    t, steps = clock.get("time"), clock.get("step_count")
    if t is None or not np.isfinite(t) or steps is None or int(steps) < 0:
        raise ValueError(f"{where}: engine/clock time={t!r}, step_count={steps!r}: expected a finite "
                         "time and a step count >= 0")
    read_checked(f, "recorder/force_rows", shape=(None, 4), what=what)
    read_checked(f, "recorder/energy_rows", shape=(None, 1 + len(ENERGY_TERMS)), what=what)


# What a run started from another run's rest state (restore(..., from_rest=True))
# may choose itself: the loading's step and how far it goes, and, as a run
# from a shared rest state (shared=True), what the settle never reads
# (parameters.settle_free: bond strengths where bonds were held while
# settling, the indenter's ramp), which are then this run's own.
LOADING_NUMERICS = ("dt", "target_travel")


def restore(run, path, from_rest=False, shared=False):
    """Continue the run saved in `path`. from_rest: start this run's loading
    from the rest state of another run of the same scene and parameters that
    may differ in LOADING_NUMERICS and what its settle never read (parameters.settle_free) only (a checkpoint written as loading
    starts, e.g. by a settle with other numerics): this run's masses and step
    replace the saved ones (bench/paper_peak.py compares loading numerics from
    one rest state). The rest state's positions, velocities, bond states,
    friction stick forces and settle record are kept: they are the rest.
    shared: start this run's loading from a shared rest state
    (rest_states.py), made by a settle with this run's numerics and threads:
    restored as saved, with this run's parameters its settle never read."""
    with open_complete(path, CHECKPOINT_FORMAT) as f:
        check(f)
        d = f["driver"]
        version = int(d.attrs.get("physics_version", 2))   # absent: written before it was recorded
        if version != PHYSICS_VERSION:
            raise ValueError(f"checkpoint {path} was written by physics version {version}, this code is "
                             f"version {PHYSICS_VERSION} (settling, sleeping or forces changed): it cannot "
                             "be continued; remove it to start the run again")
        if not from_rest:
            refuse_other_code(f.attrs, path)
        # from_rest: another run's rest state is this run's starting state, as
        # a mesh is, not a run this one continues, so the code that settled it
        # may differ (a rest state made on the CPU's build, loaded on a GPU
        # machine's own build); the run names that code beside the rest state
        saved = json.loads(d.attrs["params"])
        diff = sorted(k for k in set(saved) | set(run.params) if saved.get(k) != run.params.get(k))
        if from_rest or shared:
            free = settle_free(run.params) + (LOADING_NUMERICS if from_rest else ())
            diff = [k for k in diff if k not in free]
            phase = _text(d.attrs["phase"])
            if phase != "load" or int(d.attrs.get("load_steps", -1)) != 0:
                raise ValueError(f"checkpoint {path} is not at the start of loading (phase {phase}, "
                                 f"load steps {d.attrs.get('load_steps')}): from_rest needs a rest state")
        if diff:
            raise ValueError(f"checkpoint {path} was written with other parameters ({', '.join(diff)}); "
                             "remove it or run with the same parameters")
        if from_rest:
            run.recorder.meta.update(rest_state_code_version=_text(f.attrs.get("code_version", "")),
                                     rest_state_source_hash=_text(f.attrs.get("source_hash", "")))
        elif "rest_state_source_hash" in d.attrs:   # this run's own checkpoint of a load from a rest state
            run.recorder.meta.update(rest_state_code_version=_text(d.attrs["rest_state_code_version"]),
                                     rest_state_source_hash=_text(d.attrs["rest_state_source_hash"]))
        run.state.restore(d.attrs)   # checkpoints written before a field existed keep its default
        if "rest_state_shared_from" in d.attrs and not (from_rest or shared):
            run.rest_state = _text(d.attrs["rest_state_shared_from"])
            run.recorder.meta.update(rest_state_from=_text(d.attrs["rest_state_shared_from"]), rest_state_shared=1,
                                     rest_state_code_version=_text(d.attrs.get("rest_state_code_version", "")))
        engine_state = read_tree(f["engine"])
        if (from_rest or shared) and run.params["settle_bonds"] == "held":
            # checked while settling: the strengths are the rest state's (in its key)
            _own_bonds(run, engine_state, path)
        run.model = run.scene.restore(engine_state)
        run._configure_numerics(run.model)
        if from_rest:
            # the saved masses and step are the other run's: this run's instead
            # (mass scaling off included), as its own settle would have ended
            m = run.model
            m.set(mass_scaling_dt=run.options.mass_scaling_dt or 0.0)
            m.set(dt=run.params["dt"])
            m.reset_contact_masses()
            # the reach guard measures from the rest, as after this run's own settle
            m.set_reach_origin(m.positions)
            m.reset_energy()   # the ledger starts with the loading, as after a settle
        run.apply_boundary_conditions()
        s = read_recorder_state(f["recorder"])
        if from_rest or shared:   # no snapshot taken yet: this run's own travels
            s["pending_snaps"] = snapshot_travels(run.params["target_travel"])
        run.recorder.restore(s)


def _own_bonds(run, cp, path):
    """A rest state's bonds with this run's strengths, fracture energies and
    force direction: the settle held every bond and read none of them
    (rest_states.SETTLE_FREE), so the rest is this run's own but for these."""
    b, own = cp["bond_input"], run.scene.bond_points
    if not np.array_equal(b["node"], own.node):
        raise ValueError(f"checkpoint {path}: its bond points are not this run's (split, or another mesh): "
                         "not a rest state of this scene")
    for k in ("sigma_cr", "tau_cr", "G"):
        b[k] = np.asarray(getattr(own, k), dtype=float)
    cp["bond_params"]["direction"] = run.params["force_direction"]
