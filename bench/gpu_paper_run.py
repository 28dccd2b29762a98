"""A punch-through timed whole, not projected (issue 28's item 3; docs/gpu.md):
the scene's run through the study's own run (study.line.run_one) on a device,
settle and loading, bond events included. Not a test. Writes a JSON of what it
measured beside the result.

    python3 bench/gpu_paper_run.py --device cuda --preset fast --travel-mm 20 [--scene paper --ridge 1]

The scene's pile and mesh are taken from --runs/scenes (made with
`scene_files`, or carried to a machine without gmsh); the result goes to a
fresh folder under --runs/gpu_paper_run. Its progress lines (the loading's
travel and ETA) show how far a run cut short got.
"""
import argparse
import glob
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
from icerubble.study.line import run_one  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", default="paper")
    ap.add_argument("--ridge", type=int, default=1)
    ap.add_argument("--device", default="cuda", choices=("cpu", "cuda"))
    ap.add_argument("--preset", default="fast")
    ap.add_argument("--travel-mm", type=float, default=20.0)
    ap.add_argument("--runs", default=os.path.join(ROOT, "runs"), help="a folder whose scenes/ holds the pile and mesh")
    a = ap.parse_args(argv)
    name = f"{a.scene}_ridge{a.ridge}_"
    files = glob.glob(os.path.join(a.runs, "scenes", name + "*_pile.h5")) + \
        glob.glob(os.path.join(a.runs, "scenes", name + "*_mesh.h5"))
    if len(files) < 2:
        sys.exit(f"gpu_paper_run: no pile and mesh of {a.scene} ridge {a.ridge} in {a.runs}/scenes")
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
        y, F = h["force/y_I"][()], h["force/F"][()]
        first = F[y <= 0.005]
        k = int(np.argmax(first)) if first.size else 0
        out = dict(scene=a.scene, ridge=a.ridge, device=a.device,
                   device_name=gpu.device_name() if a.device == "cuda" else processor(),
                   preset=a.preset, travel_mm=a.travel_mm, wall_s=wall, settle_time_s=float(h.attrs["settle_time"]),
                   first_peak_kN_per_m=float(first[k]) / 1e3 if first.size else None,
                   y_at_first_peak_mm=float(y[k]) * 1e3 if first.size else None,
                   points_split=int(np.isfinite(h["bonds/y_I_split"][()]).sum()),
                   code_version=code_version(), measured=time.strftime("%Y-%m-%d"))
    with open(os.path.join(out_dir, "gpu_paper_run.json"), "w") as f:
        json.dump(out, f, indent=1)
    print(json.dumps(out), flush=True)


if __name__ == "__main__":
    main()
