"""A FEM-DEM state as rigid blocks in YADE (docs/model.md §6): the ridge of a
FEM-DEM result at one of its snapshots, each body the outline of its deformed
triangles (as a convex prism), the bond pairs whose point had not fully failed
anchored where the bodies are, with the rigid model's friction, water and bonds.

    yade -n -x yade_scripts/load_state.py RESULT.h5                    # the last snapshot
    yade -n -x yade_scripts/load_state.py RESULT.h5 --snapshot 0       # by number (0: the first)
    yade -n -x yade_scripts/load_state.py RESULT.h5 --y-I-mm 20 --save ridge_20mm.yade.gz

Prints what was loaded (bodies, bond pairs kept and failed, y_I, the largest
area a body's convex hull added). --save writes the bodies to a YADE file
(O.save; the coupling is Python and is not in it: icerubble.rigid_dem.yade_state
builds it again). Without -x, YADE stays open on the loaded scene.
"""
import argparse
import os
import sys

from yade.wrapper import O

# This checkout's package, not whichever one is installed (an editable install
# points at one checkout; a worktree is another): YADE puts neither the
# script's folder nor the working folder on sys.path.
_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(sys.argv[0] if sys.argv[0].endswith(".py")
                                                        else __file__)))
sys.path.insert(0, _ROOT)

from icerubble.rigid_dem.snapshot import fem_dem_state
from icerubble.rigid_dem.yade_state import load_into_yade


def parse(argv):
    ap = argparse.ArgumentParser(prog="load_state.py", description="Load a FEM-DEM snapshot into YADE as rigid blocks.")
    ap.add_argument("result", help="a FEM-DEM result file (.h5)")
    which = ap.add_mutually_exclusive_group()
    which.add_argument("--snapshot", type=int, help="snapshot number, 0 the first (default: the last)")
    which.add_argument("--y-I-mm", type=float, help="the snapshot nearest this indenter travel [mm]")
    ap.add_argument("--save", metavar="FILE", help="write the scene's bodies here (e.g. scene.yade.gz)")
    return ap.parse_args(argv)


args = parse(sys.argv[1:])
try:
    sc = fem_dem_state(args.result, snapshot=args.snapshot,
                       y_I=None if args.y_I_mm is None else args.y_I_mm * 1e-3)
except ValueError as e:   # bad arguments, not a FEM-DEM result, a damaged file
    sys.exit(f"load_state: error: {e}")
O.reset()
st = load_into_yade(sc)
src = sc["source"]
kind = sc["body_kind"]
worst = int(st.hull_gain.argmax())
print(f"[load_state] {src['file']}: snapshot {src['snapshot']} (#{src['index']}) at y_I = {src['y_I'] * 1e3:.3f} mm, "
      f"t = {src['t']:.4f} s after loading started", flush=True)
print(f"[load_state] bodies {len(kind)}: {len(st.blocks)} blocks, {len(st.layer)} layer pieces (fixed), "
      f"1 indenter; step {st.dt:.3g} s", flush=True)
print(f"[load_state] bond pairs intact {len(sc['bond_point'])} (of them {int(sc['bond_split'].sum())} had split "
      f"and load unbroken), failed {sc['pairs_failed']} (left out)", flush=True)
print(f"[load_state] largest hull area gain {st.hull_added_area:.3g} (body {worst}); nodes rebuilt to "
      f"{sc['centroid_residual']:.2g} m of the snapshot's triangle centroids", flush=True)
if args.save:
    out = os.path.abspath(args.save)
    engines, O.engines = O.engines, []   # the coupling's PyRunner names a Python object no file holds
    O.save(out)
    O.engines = engines
    print(f"[load_state] saved the bodies to {out}", flush=True)
