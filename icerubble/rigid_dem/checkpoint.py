"""Checkpoints of a rigid punch-through (docs/model.md §6), written while it
loads: YADE's scene as it serialises it (bodies, interactions, engines, time)
and the state the project keeps beside it (friction and bond histories, the
energy ledger, the recorder, the driver's sampling). A run rebuilt from its
mesh and given both goes on as the uninterrupted run does, to round-off: YADE's
polyhedra intersections after a reload can differ in the last bits (on the
tiny ridge the resumed record is the uninterrupted one bit for bit; on small
ridge 1, F within 0.3 N/m), and the rubble amplifies such differences.

One HDF5 file (files/h5io.AtomicH5: written as .part, marked complete, then
renamed), so an interrupted write never leaves a file that looks like a
checkpoint. It is refused for a run of other parameters or another ridge,
or written by other code (code_identity.py), before anything is loaded.
"""
import json

import numpy as np
from yade.wrapper import O

from ..code_identity import refuse_other_code
from ..files.h5io import AtomicH5, open_complete, read_tree, write_tree
from ..files.recorder import read_recorder_state, write_recorder_state

FORMAT = "icerubble rigid-dem checkpoint"

# the driver's own attributes a checkpoint carries (the rest is rebuilt)
DRIVER_KEYS = ("t_load", "y0", "work", "y_prev", "F_prev", "y_sample", "t_sample", "done",
               "settle_time", "settle_speed", "F_at_rest", "ref", "body0", "iter_load", "wall_settle_s",
               "wall_load_s")


# the driver's attributes that are pose pairs (positions (n, 2), angles (n,))
POSE_KEYS = ("ref", "body0")


def save(run, path):
    """Every state as HDF5 groups, datasets and attributes (no pickled
    objects: a checkpoint is data, read back only as data)."""
    c = run.coupling
    driver = {k: getattr(run, k) for k in DRIVER_KEYS if k not in POSE_KEYS + ("t_sample",)}
    for k in POSE_KEYS:
        pos, theta = getattr(run, k)
        driver[k + "_pos"], driver[k + "_theta"] = np.asarray(pos, float), np.asarray(theta, float)
    driver["t_sample"] = np.array(run.t_sample, float).reshape(-1, 2)   # (t, y_I) of each force sample
    with AtomicH5(path, FORMAT) as f:
        for k, v in _identity(run).items():
            f.attrs[k] = v
        f.attrs["iter"] = O.iter
        f.attrs["y_I"] = float(run.y_prev)
        f.create_dataset("yade_scene", data=np.void(O.sceneToString()))
        write_tree(f.create_group("driver"), driver)
        write_recorder_state(f.create_group("recorder"), run.rec.state())
        write_tree(f.create_group("ledger"), _ledger_tree(run.ledger))
        fr = f.create_group("friction")
        fr.create_dataset("keys", data=np.asarray(c.friction.keys, np.uint64))
        fr.create_dataset("forces", data=np.asarray(c.friction.forces, float))
        if c.bonds is not None:
            write_tree(f.create_group("bonds"), c.bonds.history())
        # (the bodies' start poses, the water's polygons and the bonds'
        # anchors are build()'s, made again the same by the resumed run)
        write_tree(f.create_group("coupling"), dict(dry=np.asarray(c.dry, bool), degenerate=int(c.degenerate),
                                                    keep_terms=bool(c.keep_terms),
                                                    drag=c.water.drag if c.water is not None else None,
                                                    newton_damping=float(run.newton.damping)))


def _ledger_tree(ledger):
    """What a RigidLedger has counted (its masses and bodies are make_ledger()'s)."""
    t = dict(work=dict(ledger.work), initial=ledger.initial, spring0=ledger.spring0, bonds0=ledger.bonds0)
    if ledger.pending is not None:
        v0, w0, forces = ledger.pending
        t["pending"] = dict(vel=v0, omega=w0, forces={k: dict(fx=fx, fy=fy, tz=tz) for k, (fx, fy, tz) in forces.items()})
    return t


def _restore_ledger(ledger, t):
    ledger.work = {k: float(v) for k, v in t["work"].items()}
    ledger.initial, ledger.spring0, ledger.bonds0 = float(t["initial"]), float(t["spring0"]), float(t["bonds0"])
    p = t.get("pending")
    ledger.pending = None if p is None else (
        p["vel"], p["omega"], {k: (v["fx"], v["fy"], v["tz"]) for k, v in p["forces"].items()})


def _identity(run):
    """What a checkpoint must match to be this run's: its id, parameters and ridge."""
    return dict(run_id=str(run.meta.get("run_id", "")), parameters=json.dumps(run.params, sort_keys=True, default=str),
                n_bodies=len(run.sc["body_kind"]), n_bond_pairs=len(run.sc["bond_a"]))


def restore(run, path):
    """Into a run whose build() has just made its scene: YADE's scene and every
    state beside it as they were when `path` was written. ValueError for a
    file that is not this run's checkpoint."""
    with open_complete(path, FORMAT, what="rigid-dem checkpoint") as f:
        refuse_other_code(f.attrs, path, what="rigid-dem checkpoint")
        for k, mine in _identity(run).items():
            theirs = f.attrs.get(k)
            if theirs != mine:
                raise ValueError(f"{path} is the checkpoint of another run ({k}: {theirs!r}, this run: {mine!r}): "
                                 "move it away to start afresh")
        scene = f["yade_scene"][()].tobytes()
        driver = read_tree(f["driver"])
        recorder = read_recorder_state(f["recorder"])
        ledger = read_tree(f["ledger"])
        friction = (f["friction/keys"][...], f["friction/forces"][...])
        bonds = read_tree(f["bonds"]) if "bonds" in f else None
        coupling = read_tree(f["coupling"])
    # YADE rebuilds a loaded polyhedron's internal (CGAL) form from its vertices
    # in its own order, and its intersections then differ at round-off; the
    # shapes build() just made are the uninterrupted run's own: they are kept
    shapes = [b.shape for b in O.bodies]
    O.stringToScene(scene)
    for b, shape in zip(O.bodies, shapes):
        b.shape = shape
    c = run.coupling
    c.states = [b.state for b in O.bodies]          # the loaded scene's own objects
    c.dry[:] = coupling["dry"]
    c.degenerate = int(coupling["degenerate"])
    c.keep_terms = bool(coupling["keep_terms"])
    if c.water is not None:
        c.water.drag = bool(coupling["drag"])
    c.friction.restore(*friction)
    if bonds is not None:
        c.bonds.restore_history(bonds)
    run.newton = next(e for e in O.engines if type(e).__name__ == "NewtonIntegrator")
    run.newton.damping = float(coupling["newton_damping"])
    for k in POSE_KEYS:
        setattr(run, k, (driver.pop(k + "_pos"), driver.pop(k + "_theta")))
    run.t_sample = [(float(t), float(y)) for t, y in driver.pop("t_sample")]
    for k, v in driver.items():
        setattr(run, k, v)
    run.ledger = run.make_ledger()
    _restore_ledger(run.ledger, ledger)
    run.rec = run._recorder(*run.ref)
    run.rec.restore(recorder)
    run.loading = True      # checkpoints are written while loading
