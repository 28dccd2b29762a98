"""Per-step cost of the discrete-only (rigid-block) model on the paper scene
(not a test): the paper mesh of ridge 1 as YADE polyhedra with the project's
friction, water and bonds (icerubble/rigid_dem), timed over the first steps of
its settle, with each YADE engine's share. Writes bench/results/rigid_cost.json.

    /usr/bin/python3 bench/rigid_cost.py [--steps 200] [--quick]

It runs itself inside YADE (`yade -n -x`), one thread.
"""
import json
import os
import subprocess
import sys
import time

if "yade" not in sys.modules:   # started from python3: run inside YADE
    sys.exit(subprocess.call(["yade", "-n", "-x", os.path.abspath(__file__)] + sys.argv[1:],
                             cwd=os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                             env=dict(os.environ, OMP_NUM_THREADS="1")))

# inside YADE __file__ is not this script: its path is argv[0] (started from the checkout)
HERE = os.path.dirname(os.path.abspath(sys.argv[0]))
ROOT = os.path.dirname(HERE)
OUT = os.path.join(HERE, "results", "rigid_cost.json")

sys.path.insert(0, ROOT)
import argparse  # noqa: E402

from yade.wrapper import O  # noqa: E402

from icerubble.rigid_dem.punch_through import RigidPunchThrough  # noqa: E402
from icerubble.run.presets import scene  # noqa: E402
from icerubble.run.scene_cache import scene_files  # noqa: E402

ap = argparse.ArgumentParser()
ap.add_argument("--steps", type=int, default=200)
ap.add_argument("--quick", action="store_true", help="50 steps")
a = ap.parse_args(sys.argv[1:])
steps = 50 if a.quick else a.steps
_, mesh = scene_files("paper", 1, root=os.path.join(ROOT, "runs"))
run = RigidPunchThrough(mesh, os.devnull, dict(scene("paper")["params"], mu=0.3), dict(ridge="paper-1", seed=1))
t0 = time.perf_counter()
run.build()
build_s = time.perf_counter() - t0
O.run(20, True)   # contacts found, caches warm
O.timingEnabled = True
for e in O.engines:
    e.execTime = 0
w0 = time.perf_counter()
O.run(steps, True)
wall = (time.perf_counter() - w0) / steps
shares = {e.__class__.__name__: e.execTime * 1e-9 / steps for e in O.engines}
n_contacts = sum(1 for i in O.interactions if i.isReal)
res = dict(blocks=int(len(run.blocks)), bond_pairs=int(len(run.sc["bond_a"])), contacts=n_contacts,
           dt=run.dt, s_per_step=wall, engine_s_per_step=shares, build_s=build_s,
           hull_added_area=run.hull_added_area, threads=1)
os.makedirs(os.path.dirname(OUT), exist_ok=True)
with open(OUT, "w") as f:
    json.dump(res, f, indent=1)
print(f"rigid model, paper scene ridge 1: {res['blocks']} blocks, {res['bond_pairs']} bond pairs, "
      f"{n_contacts} touching pairs; dt {run.dt:.2e} s; {1e3 * wall:.1f} ms per step (1 thread)")
for k, v in sorted(shares.items(), key=lambda kv: -kv[1]):
    print(f"  {k:28s} {1e3 * v:8.2f} ms/step ({100 * v / wall:.0f} %)")
print(f"wrote {OUT}")
