"""A rigid punch-through of the tiny ridge stopped by a scheduler's signal
while loading, and resumed from its checkpoint (tests/rigid_dem/test_rigid_resume.py).
Run inside YADE, one thread: `yade -n -x tests/rigid_dem/yade_resume_scene.py`
with in the environment MESH (the ridge's mesh file), OUT (the result file),
RUN_ID, and SIGNAL_AFTER (load steps after which the run sends itself SIGTERM;
absent: resume) or SIGNAL_SETTLING (a step of the settle to send it at). The parameters are those of the table line
`'tiny' 'rigid-dem' 0.3` (conftest.TINY_TABLE). Exit 75 when stopped, as
yade_scripts/punch_through.py."""
import os
import signal
import sys

sys.path.insert(0, os.getcwd())  # the repository: run from its root

from yade.wrapper import O  # noqa: E402

from icerubble import parameters as P  # noqa: E402
from icerubble.rigid_dem.punch_through import RigidPunchThrough  # noqa: E402
from icerubble.run.presets import scene  # noqa: E402
from icerubble.run.driver import RunInterrupted  # noqa: E402

params = P.validate(dict(scene("tiny")["params"], mu=0.3))
after, settling = os.environ.get("SIGNAL_AFTER"), os.environ.get("SIGNAL_SETTLING")
run = RigidPunchThrough(os.environ["MESH"], os.environ["OUT"], params, meta=dict(run_id=os.environ["RUN_ID"]))
if after or settling:
    step = run.each_step

    def each_step():   # the scheduler: one SIGTERM, mid-chunk
        step()
        if (after and run.loading and O.iter - run.iter_load == int(after)) or (
                settling and not run.loading and O.iter == int(settling)):
            os.kill(os.getpid(), signal.SIGTERM)
    run.each_step = each_step
try:
    run.run(resume=not (after or settling))
except RunInterrupted as e:
    print("STOPPED", e, flush=True)
    sys.exit(75)
except ValueError as e:
    print("REFUSED", e, flush=True)
    sys.exit(1)
