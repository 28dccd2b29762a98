"""A rigid punch-through of the tiny ridge stopped by a scheduler's signal
while loading, and resumed from its checkpoint (tests/rigid_dem/test_rigid_resume.py).
Run inside YADE, one thread: `yade -n -x tests/rigid_dem/yade_resume_scene.py`
with in the environment MESH (the ridge's mesh file), OUT (the result file),
RUN_ID, and SIGNAL_AFTER (load steps after which the run sends itself SIGTERM;
absent: resume) or SIGNAL_SETTLING (a step of the settle to send it at), and
RESAVE (resuming: a path to write the restored state to as a checkpoint
again, before the first step), SAVED_STATE (an .npz of every body's state and
the friction history, written with each checkpoint) and STATE_AT / STATE_OUT
(the same .npz after that load step). The parameters are those of the table line
`'tiny' 'rigid-dem' 0.3` (conftest.TINY_TABLE). Exit 75 when stopped, as
yade_scripts/punch_through.py."""
import os
import signal
import sys

import numpy as np

sys.path.insert(0, os.getcwd())  # the repository: run from its root

from yade.wrapper import O  # noqa: E402

from icerubble import parameters as P  # noqa: E402
from icerubble.rigid_dem import checkpoint  # noqa: E402
from icerubble.rigid_dem.punch_through import RigidPunchThrough  # noqa: E402
from icerubble.run.presets import scene  # noqa: E402
from icerubble.run.driver import RunInterrupted  # noqa: E402

params = P.validate(dict(scene("tiny")["params"], mu=0.3))
after, settling = os.environ.get("SIGNAL_AFTER"), os.environ.get("SIGNAL_SETTLING")
run = RigidPunchThrough(os.environ["MESH"], os.environ["OUT"], params, meta=dict(run_id=os.environ["RUN_ID"]))


def dump_state(path):
    """Every body's state and the friction history: what YADE's scene string
    carries beside the shapes (whose colours YADE draws at random)."""
    s = [b.state for b in O.bodies]
    np.savez(path, pos=[tuple(x.pos) for x in s], vel=[tuple(x.vel) for x in s], ori=[tuple(x.ori) for x in s],
             ang_vel=[tuple(x.angVel) for x in s], iter=O.iter, time=O.time,
             friction_keys=np.asarray(run.coupling.friction.keys, np.uint64),
             friction_forces=np.asarray(run.coupling.friction.forces, float))


if os.environ.get("SAVED_STATE"):
    saved = checkpoint.save

    def save(r, path):
        saved(r, path)
        dump_state(os.environ["SAVED_STATE"])
    checkpoint.save = save
state_at = os.environ.get("STATE_AT")
if after or settling or state_at:
    step = run.each_step

    def each_step():   # the scheduler: one SIGTERM, mid-chunk
        step()
        if state_at and run.loading and O.iter - run.iter_load == int(state_at):
            dump_state(os.environ["STATE_OUT"])
        if (after and run.loading and O.iter - run.iter_load == int(after)) or (
                settling and not run.loading and O.iter == int(settling)):
            os.kill(os.getpid(), signal.SIGTERM)
    run.each_step = each_step
resave = os.environ.get("RESAVE")
if resave:
    restored = run.resume

    def resume(path):   # the state as restored, before it takes a step
        restored(path)
        checkpoint.save(run, resave)
    run.resume = resume
try:
    run.run(resume=not (after or settling))
except RunInterrupted as e:
    print("STOPPED", e, flush=True)
    sys.exit(75)
except ValueError as e:
    print("REFUSED", e, flush=True)
    sys.exit(1)
