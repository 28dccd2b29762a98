"""A punch-through timed whole, not projected (issue 28's item 3; docs/gpu.md):
the scene's run through the study's own run (study.line.run_one) on a device,
settle and loading, bond events included. Not a test. Writes a JSON of what it
measured beside the result.

    python3 bench/gpu_paper_run.py --device cuda --preset fast --travel-mm 20 [--scene paper --ridge 1]

The scene's pile and mesh are taken from --runs/scenes (made there by
`scene_files` where they are missing, or carried to a machine without gmsh
and YADE); the result goes to a
fresh folder under --runs/gpu_paper_run. Its progress lines (the loading's
travel and ETA) show how far a run cut short got.
"""
import argparse
import json
import os
import shutil
import sys
import time

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)
from icerubble.code_identity import code_version  # noqa: E402
from icerubble.engine import gpu  # noqa: E402
from icerubble.machine import processor  # noqa: E402
from icerubble.run.scene_cache import scene_files  # noqa: E402
from icerubble.study.line import run_one  # noqa: E402
from postproc.loads import cohesive_peak  # noqa: E402
import result_file  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default="paper")
    ap.add_argument("--ridge", type=int, default=1)
    ap.add_argument("--device", default="cuda", choices=("cpu", "cuda"))
    ap.add_argument("--preset", default="fast")
    ap.add_argument("--travel-mm", type=float, default=20.0)
    ap.add_argument("--runs", default=os.path.join(ROOT, "runs"), help="a folder whose scenes/ holds the pile and mesh")
    a = ap.parse_args(argv)
    files = scene_files(a.scene, a.ridge, root=a.runs)   # there already, or made (gmsh, YADE) where it can
    out_dir = os.path.join(a.runs, "gpu_paper_run", f"{a.scene}{a.ridge}_{a.device}_{a.preset}_{time.strftime('%H%M%S')}")
    os.makedirs(os.path.join(out_dir, "scenes"))
    for f in files:
        shutil.copy(f, os.path.join(out_dir, "scenes"))
    t0 = time.perf_counter()
    path = run_one(a.scene, a.ridge, overrides=dict(target_travel=a.travel_mm * 1e-3), out_dir=out_dir,
                   description=f"{a.scene}{a.ridge}_{a.device}_{a.preset}", numerics_name=a.preset,
                   share_rest=False, device=a.device)
    wall = time.perf_counter() - t0
    with h5py.File(path, "r") as h:
        F_m, y_m = cohesive_peak(h["force/y_I"][()], h["force/F"][()])   # the 5 mm rule's F^m
        out = dict(scene=a.scene, ridge=a.ridge, device=a.device,
                   device_name=gpu.device_name() if a.device == "cuda" else processor(),
                   preset=a.preset, travel_mm=a.travel_mm, wall_s=wall, settle_time_s=float(h.attrs["settle_time"]),
                   F_m_kN_per_m=F_m / 1e3, y_I_at_F_m_mm=y_m * 1e3,
                   points_split=int(np.isfinite(h["bonds/y_I_split"][()]).sum()),
                   # where the wall time went: the GPU's steps, the model's own (splits), the
                   # copies to the GPU and the list rebuilds (Model.timings)
                   step_timings=json.loads(h.attrs["step_timings"]) if "step_timings" in h.attrs else None,
                   code_version=code_version(), measured=time.strftime("%Y-%m-%d"))
    result_file.write(os.path.join(out_dir, "gpu_paper_run.json"), out)
    print(json.dumps(out), flush=True)


if __name__ == "__main__":
    main()
