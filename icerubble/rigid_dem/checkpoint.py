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
import pickle

import numpy as np
from yade.wrapper import O

from ..code_identity import refuse_other_code
from ..files.h5io import AtomicH5, open_complete

FORMAT = "icerubble rigid-dem checkpoint"

# the driver's own attributes a checkpoint carries (the rest is rebuilt)
DRIVER_KEYS = ("t_load", "y0", "work", "y_prev", "F_prev", "y_sample", "t_sample", "done",
               "settle_time", "settle_speed", "F_at_rest", "ref", "body0", "iter_load", "wall_settle_s",
               "wall_load_s")


def save(run, path):
    c = run.coupling
    state = dict(driver={k: getattr(run, k) for k in DRIVER_KEYS},
                 recorder=run.rec.state(),
                 ledger=dict(vars(run.ledger)),
                 friction=(np.array(c.friction.keys), np.array(c.friction.forces)),
                 bonds=c.bonds.history(),
                 # (the bodies' start poses, the water's polygons and the bonds'
                 # anchors are build()'s, made again the same by the resumed run)
                 coupling=dict(dry=c.dry.copy(), degenerate=c.degenerate, keep_terms=c.keep_terms,
                               drag=c.water.drag),
                 newton_damping=run.newton.damping)
    with AtomicH5(path, FORMAT) as f:
        for k, v in _identity(run).items():
            f.attrs[k] = v
        f.attrs["iter"] = O.iter
        f.attrs["y_I"] = float(run.y_prev)
        f.create_dataset("yade_scene", data=np.void(O.sceneToString()))
        f.create_dataset("state", data=np.void(pickle.dumps(state, protocol=pickle.HIGHEST_PROTOCOL)))


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
        state = pickle.loads(f["state"][()].tobytes())
    # YADE rebuilds a loaded polyhedron's internal (CGAL) form from its vertices
    # in its own order, and its intersections then differ at round-off; the
    # shapes build() just made are the uninterrupted run's own: they are kept
    shapes = [b.shape for b in O.bodies]
    O.stringToScene(scene)
    for b, shape in zip(O.bodies, shapes):
        b.shape = shape
    c = run.coupling
    c.states = [b.state for b in O.bodies]          # the loaded scene's own objects
    c.dry[:] = state["coupling"]["dry"]
    c.degenerate = state["coupling"]["degenerate"]
    c.keep_terms = state["coupling"]["keep_terms"]
    c.water.drag = state["coupling"]["drag"]
    c.friction.restore(*state["friction"])
    c.bonds.restore_history(state["bonds"])
    run.newton = next(e for e in O.engines if type(e).__name__ == "NewtonIntegrator")
    run.newton.damping = state["newton_damping"]
    for k, v in state["driver"].items():
        setattr(run, k, v)
    run.ledger = run.make_ledger()
    vars(run.ledger).update(state["ledger"])
    run.rec = run._recorder(*run.ref)
    run.rec.restore(state["recorder"])
    run.loading = True      # checkpoints are written while loading
