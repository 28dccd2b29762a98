"""A FEM-DEM snapshot loaded into YADE, for tests/rigid_dem/test_snapshot_state.py
(run inside YADE: `yade -n -x tests/rigid_dem/yade_state_scene.py`, with RESULT,
SNAPSHOT, RUN_TIME and OUT in the environment).

Loads snapshot SNAPSHOT of RESULT (icerubble.rigid_dem.yade_state), writes the
bodies as placed (outline, mass, centroid), every bond pair's force after the
first step, then runs RUN_TIME s with gravity and water and writes each body's
move, speed and turn, and the bond pairs broken.
"""
import json
import os
import sys

sys.path.insert(0, os.getcwd())  # the repository: run from its root

import numpy as np
from yade.wrapper import O

from icerubble.rigid_dem.prisms import inertia_z
from icerubble.rigid_dem.snapshot import fem_dem_state
from icerubble.rigid_dem.yade_state import load_into_yade

sc = fem_dem_state(os.environ["RESULT"], snapshot=int(os.environ["SNAPSHOT"]))
O.reset()
st = load_into_yade(sc)
bodies = [O.bodies[int(i)] for i in st.ids]
placed = dict(polygons=[p.tolist() for p in st.polygons], mass=[b.state.mass for b in bodies],
              inertia_z=[inertia_z(b) for b in bodies],
              pos=[(b.state.pos[0], b.state.pos[1], b.state.pos[2]) for b in bodies],
              hull_gain=st.hull_gain.tolist(), hull_added_area=st.hull_added_area, dt=st.dt,
              rho_i=sc["params"]["rho_i"], n_pairs=len(sc["bond_point"]))
O.step()
b = st.coupling.bonds
first = dict(f_n=np.asarray(b.f_n).tolist(), f_t=np.asarray(b.f_t).tolist(),
             peak=(sc["sigma_cr"] * sc["bond_length"]).tolist())
pos0 = np.array([(s.state.pos[0], s.state.pos[1]) for s in bodies])
O.run(int(round(float(os.environ["RUN_TIME"]) / st.dt)), True)
pos1 = np.array([(s.state.pos[0], s.state.pos[1]) for s in bodies])
run = dict(time=O.time, move=np.hypot(*(pos1 - pos0).T).tolist(),
           speed=[s.state.vel.norm() for s in bodies], spin=[s.state.angVel.norm() for s in bodies],
           turn=st.coupling.body_arrays()[3].tolist(), state=np.asarray(b.state).tolist())
with open(os.environ["OUT"], "w") as f:
    json.dump(dict(placed=placed, first=first, run=run), f)
