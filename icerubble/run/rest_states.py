"""Shared rest states: runs of one scene that differ only in what the settle
never reads settle once.

The settle (run/settle.py) holds every freeze bond by default (none is
checked, none splits) and leaves the indenter free until it holds it at rest.
So it reads neither the bond points' strengths and fracture energy nor the
indenter's ramp and travel: SETTLE_FREE. With settle_bonds='checked' it reads
the strengths too, and they join the key (parameters.settle_free). The paper's study sweeps
tau_cr over five values for each ridge and mu; with a shared rest state the
first of the five to settle writes it next to the scene's mesh and the other
four load from it (checkpoint.restore(shared=True), with their own
strengths), skipping a settle that is a large part of a short run on the
paper scene (bench/README.md, paper_cost.json). Only runs that start
after the rest state is written find it: runs that start together (a
SLURM array's tasks, yade-batch -j 2) all settle.

A run that loads from a shared rest state gives the result its own settle
would have given, bit for bit: the key is everything else the settle reads
(the run identity without SETTLE_FREE, the settle's options), the thread
count, since sums over threads round differently, and the code that settles
(code_identity.source_hash: other code settles, and keys, its own). tests/run/test_rest_states.py
checks both: the rest states of two runs differing in every SETTLE_FREE
parameter are equal bit for bit, and a run from another's rest state writes
the result of its own settle.
"""
import json
import os

from .. import parameters as P
from ..code_identity import source_hash
from ..files.h5io import open_complete
from . import checkpoint as ckpt
from . import run_identity as RI

# Parameters the settle does not read (see above), and the settle's own
# RunOptions (not in the run identity: their defaults are every study's, but
# a rest state is shared only under the same ones): both the registry's
# (icerubble/parameters.py: settle=False; group settle).
SETTLE_FREE = P.SETTLE_FREE
SETTLE_OPTIONS = P.SETTLE_OPTIONS


def settle_identity(params, mesh, options, threads, model="fem-dem"):
    """Everything that makes a rest state: the run identity without the
    parameters its settle never reads (SETTLE_FREE, less the bond strengths
    where settle_bonds='checked'), the settle's options, the thread count and the
    code (its source_hash)."""
    free = P.settle_free(params)   # the bond strengths are read where settle_bonds='checked'
    ident = RI.identity({k: v for k, v in params.items() if k not in free}, mesh, options)
    ident["settle_options"] = {k: RI._plain(getattr(options, k)) for k in SETTLE_OPTIONS}
    ident["threads"] = int(threads)
    # only the code that settled continues its rest state (code_identity.py):
    # other code keys, and settles, its own
    ident["code"] = source_hash()
    ident["model"] = model
    return ident


def rest_state_path(rest_dir, mesh_path, ident):
    """Where the shared rest state of `ident` is kept: beside the scene's
    files, named by the mesh and the settle identity's hash (as a run's run_id)."""
    stem = os.path.basename(os.fspath(mesh_path))
    stem = stem[:-3] if stem.endswith(".h5") else stem
    stem = stem[:-5] if stem.endswith("_mesh") else stem
    return os.path.join(os.fspath(rest_dir), f"{stem}_rest_{RI.run_id(ident)}.checkpoint.h5")


def share(run):
    """Leave the rest state of PunchThrough `run` (at the start of its
    loading) for the runs that differ from it only in what the settle never
    reads. Runs settling at once (a study's tasks) each write their own part
    file; the files are equal bit for bit, the last rename wins. A folder that
    cannot be written costs only the reuse."""
    path, ident = run.shared_rest
    if os.path.exists(path) and not run._shared_rest_damaged:
        return
    try:
        ckpt.save(run, path, driver_attrs=dict(settle_identity=ident), shared=True)
    except OSError as e:
        print(f"[punch-through] warning: the rest state could not be shared as {path} ({e}); "
              "the run goes on", flush=True)
        return
    print(f"[punch-through] rest state shared as {path}", flush=True)


def load_shared(run):
    """Start PunchThrough `run`'s loading from its shared rest state, after
    checking that it was made by the same settle."""
    path, ident = run.shared_rest
    try:
        with open_complete(path, ckpt.CHECKPOINT_FORMAT) as f:
            ckpt.check(f)
            stored = f["driver"].attrs.get("settle_identity")
            made_by = f.attrs.get("code_version", "")
    except (ValueError, OSError) as e:
        # files are written whole and renamed, so only outside damage does
        # this: the run settles itself and writes the rest state again
        print(f"[punch-through] warning: the shared rest state cannot be read ({e}); this run "
              "settles itself and replaces it", flush=True)
        run._shared_rest_damaged = True
        return
    stored = stored.decode() if isinstance(stored, bytes) else stored
    if stored != ident:
        why = "; ".join(RI.differences(json.loads(stored), json.loads(ident))) if stored else \
            "it records no settle identity"
        raise ValueError(f"shared rest state {path} was not made by this run's settle ({why}): "
                         "move it away")
    ckpt.restore(run, path, shared=True)
    # the code that settled, for people (the key holds its source hash, code_identity.py)
    made_by = made_by.decode() if isinstance(made_by, bytes) else str(made_by)
    run.recorder.meta.update(rest_state_from=os.path.abspath(path), rest_state_shared=1,
                             rest_state_code_version=made_by)
    run.rest_state = path
    print(f"[punch-through] loads from the shared rest state {path} (settled by an earlier run that "
          "differs only in what the settle never reads)", flush=True)
