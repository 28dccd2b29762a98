"""One run of the study: scene files + parameters -> result file."""
import json
import os
import re
import time

import h5py

from ..files.mesh_file import read_mesh
from .. import parameters as P
from ..run import run_identity as RI
from ..run.punch_through_run import PunchThrough, RunOptions
from ..run.scene_cache import scene_files
from ..run.presets import DEFAULT_NUMERICS, SCENES, numerics, scene


def run_name(scene_name, ridge, params):
    # '_wc' names the work-conjugate direction whichever form is the default, so a
    # name made before the default changed (docs/model.md §3.3) still names its physics
    return (f"{scene_name}_ridge{int(ridge)}_mu{params['mu']:g}_tau{params['tau_cr'] / 1e3:g}k"
            + ("" if params["force_direction"] == "paper" else "_wc"))


# The models a run can be (a table's `model` column): the FEM-DEM of the paper, or
# the discrete-only comparison model of rigid blocks in YADE (docs/model.md §6).
MODELS = ("fem-dem", "rigid-dem")


# A line's description names its result file, OUT/<description>.h5: a plain
# name, so that no line writes outside OUT ('/', '..') or to a hidden file
RESULT_NAME = re.compile(r"[A-Za-z0-9_+=,-][A-Za-z0-9._+=,-]*")
RESULT_NAME_CHARS = "letters, digits and . _ - + = , (not first: .)"


def result_name_problem(description):
    """Why `description` cannot name a result file (None: it can)."""
    if not RESULT_NAME.fullmatch(description):
        return f"is not a plain file name: use only {RESULT_NAME_CHARS}"
    if len(description) > 200:   # with .checkpoint.h5 and _fields/ it must fit a file name (255)
        return f"is {len(description)} characters long: at most 200"
    return None


def run_one(scene_name="demo", ridge=1, overrides=None, out_dir="runs", description="",
            resume=True, options=None, numerics_name=None, model="fem-dem", share_rest=True, device="cpu",
            settle_max_time=None):
    """Make (or reuse) the pile and mesh, then run the punch-through; returns the result path.
    numerics_name: the scene's numerical preset (presets.NUMERICS; default DEFAULT_NUMERICS);
    model: "fem-dem", or "rigid-dem" (only inside YADE: the blocks are YADE polyhedra);
    share_rest: load from (or leave) the shared rest state of the runs of this
    scene that differ only in what the settle never reads (rest_states.py):
    the same result, bit for bit, without the settle;
    device: where the FEM-DEM's steps run, 'cpu' or 'cuda' (engine.DEVICES;
    options, when given, carry their own); settle_max_time: the settle's
    limit [s] (None: the registry's; not part of the run's identity)."""
    if model not in MODELS:
        raise ValueError(f"model={model!r} is unknown: valid values are {', '.join(MODELS)}")
    if model == "rigid-dem" and device != "cpu":
        raise ValueError(f"device={device!r}: the rigid-dem model runs on YADE's engines, on the CPU only")
    sc = scene(scene_name)
    settings = numerics(scene_name, numerics_name)   # fails on an unknown preset before any work
    params = P.validate(dict(sc["params"], **(overrides or {})), scenes=SCENES)   # fail before any work
    if options is not None and settle_max_time is not None and settle_max_time != options.settle_max_time:
        raise ValueError(f"settle_max_time={settle_max_time} and options.settle_max_time="
                         f"{options.settle_max_time} differ: options, when given, carry the settle's limit "
                         "(give it in RunOptions, or leave options out)")
    if options is None:   # checked before any work
        # a dt column is the step asked for; otherwise the scene's fraction of the stable step
        if "dt" in (overrides or {}):
            settings["dt_fraction"] = None
        limit = {} if settle_max_time is None else dict(settle_max_time=settle_max_time)
        options = RunOptions.from_numerics(settings, name=numerics_name or DEFAULT_NUMERICS, device=device, **limit)
    if not description or description == "default":
        description = run_name(scene_name, ridge, params) + ("_rigid" if model == "rigid-dem" else "")
    why = result_name_problem(description)
    if why:
        raise ValueError(f"description {description!r} {why} (it names the result file in {out_dir})")
    out = os.path.join(out_dir, description + ".h5")
    if os.path.exists(out):
        stored_identity(out)   # a damaged file there is refused before the scene is made
    _, mesh_path = scene_files(scene_name, ridge, root=out_dir)   # checks the ridge before it makes out_dir
    ident = RI.identity(params, read_mesh(mesh_path), options)
    if model != "fem-dem":   # absent: the FEM-DEM (identities of runs made before models)
        ident["model"] = model
    rid = RI.run_id(ident)
    if os.path.exists(out):
        stored = stored_identity(out)
        if stored is not None and RI.run_id(stored) == rid:
            print(f"[study] {out} exists (complete, same run id {rid}): nothing to do", flush=True)
            return out
        if stored is None:
            why = ["it records no run identity (made before they were recorded)"]
        else:
            why = RI.differences(stored, ident)
        raise ValueError(f"{out} exists but is not the run asked for: " + "; ".join(why)
                         + ". Give this run its own description (yade-batch: the description column), "
                           "or move the stored file away.")
    t0 = time.perf_counter()
    if model == "rigid-dem":
        from ..rigid_dem.punch_through import RigidPunchThrough   # needs YADE
        with RI.RunLock(out):
            RigidPunchThrough(mesh_path, out, params, meta=dict(
                ridge=f"{scene_name}-{int(ridge)}", seed=int(ridge), scene=scene_name, run_id=rid,
                run_identity=RI.to_json(ident))).run(resume=resume)
        print(f"[study] wrote {out} ({time.perf_counter() - t0:.0f} s)", flush=True)
        return out
    with RI.RunLock(out):
        # runs of this ridge that differ only in what the settle never reads
        # (the tau_cr sweep) settle once: rest states kept beside the scene's files
        run = PunchThrough(mesh_path, out, params=params, options=options,
                           meta=dict(ridge=f"{scene_name}-{int(ridge)}", seed=int(ridge), model="fem-dem",
                                     scene=scene_name, run_id=rid,
                                     run_identity=RI.to_json(ident)),
                           rest_dir=os.path.dirname(mesh_path) if share_rest else None)
        run.run(resume=resume)
    print(f"[study] wrote {out} ({time.perf_counter() - t0:.0f} s)", flush=True)
    return out


def stored_identity(path):
    """The identity recorded in a result file (None if it records none)."""
    try:
        f = h5py.File(path, "r")
    except OSError as e:   # damaged from outside, or not HDF5: never taken for (or replaced by) a run
        raise ValueError(f"{path} exists but cannot be read as a result ({e}): move it away, or give this "
                         "run another description") from None
    with f:
        text = f.attrs.get("run_identity")
    if text is None:
        return None
    return json.loads(text.decode() if isinstance(text, bytes) else text)
