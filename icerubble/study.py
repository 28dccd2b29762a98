"""One run of the study: scene files + parameters -> result file."""
import os
import time

from . import parameters as P
from .punch_through import PunchThrough, RunOptions
from .scene_files import scene_files
from .scenes import scene


def run_name(scene_name, ridge, params):
    return (f"{scene_name}_ridge{int(ridge)}_mu{params['mu']:g}_tau{params['tau_cr'] / 1e3:g}k"
            + ("" if params["force_direction"] == "paper" else "_wc"))


def run_one(scene_name="demo", ridge=1, overrides=None, out_dir="runs", description="",
            resume=True, options=None):
    """Make (or reuse) the pile and mesh, then run the punch-through; returns the result path."""
    sc = scene(scene_name)
    params = P.validate(dict(sc["params"], **(overrides or {})))   # fail before any work
    if not description or description == "default":
        description = run_name(scene_name, ridge, params)
    os.makedirs(out_dir, exist_ok=True)
    _, mesh_path = scene_files(scene_name, ridge, root=out_dir)
    out = os.path.join(out_dir, description + ".h5")
    if os.path.exists(out):
        print(f"[study] {out} exists (complete): nothing to do", flush=True)
        return out
    t0 = time.perf_counter()
    if options is None:
        options = RunOptions(dt_fraction=sc.get("dt_fraction"), mass_scaling_dt=sc.get("mass_scaling_dt"))
    run = PunchThrough(mesh_path, out, params=params, options=options,
                       meta=dict(ridge=f"{scene_name}-{int(ridge)}", seed=int(ridge), model="fem-dem",
                                 scene=scene_name))
    run.run(resume=resume)
    print(f"[study] wrote {out} ({time.perf_counter() - t0:.0f} s)", flush=True)
    return out
