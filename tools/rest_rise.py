"""How far a settle moved the indenter and the keel from where they were meshed.

    /usr/bin/python3 tools/rest_rise.py DIR [DIR ...]

For each rest state (`<mesh>_rest_<key>.checkpoint.h5`, icerubble/run/rest_states.py)
or run checkpoint (`*.checkpoint.h5`) under each DIR (a study's `scenes/` folder or
its results folder): τ_cr, μ, how the bonds were treated while settling, the mean
vertical displacement of the indenter's nodes, of the block nodes meshed under it
(|x| < w_I/2) and of those far from it (|x| > w_I), and the bond points no longer
intact. The indenter is free while settling (docs/model.md §3.4); a keel whose
buoyant part under it breaks loose lifts it (docs/study_paper_depth.md, "Run log"),
where a keel at rest moves it by under a millimetre.
"""
import functools
import glob
import json
import os
import sys

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

from icerubble.files.mesh_file import KIND_BLOCK, KIND_INDENTER, read_mesh  # noqa: E402

# a folder's meshes are read once, whatever the number of checkpoints beside them
mesh = functools.lru_cache(maxsize=None)(read_mesh)


def mesh_of(checkpoint, folder):
    """The mesh a checkpoint was made from: beside a rest state, by its name;
    for a run's checkpoint, the mesh of DIR or DIR/scenes with as many
    triangles (splits add nodes, never triangles)."""
    if "_rest_" in os.path.basename(checkpoint):
        return checkpoint.split("_rest_")[0] + "_mesh.h5"
    with h5py.File(checkpoint, "r") as f:
        n_tri = f["engine/body"].shape[0]
    found = [m for m in sorted(glob.glob(os.path.join(folder, "*_mesh.h5")) +
                               glob.glob(os.path.join(folder, "scenes", "*_mesh.h5")))
             if len(mesh(m)["body"]) == n_tri]
    return found[0] if len(found) == 1 else None


def rise(checkpoint, mesh_path):
    with h5py.File(checkpoint, "r") as f:
        e = f["engine"]
        p = e["positions"][()].reshape(-1, 2)
        p0 = e["reference_positions"][()].reshape(-1, 2)
        body = e["body"][()]
        tri = e["triangles"][()].reshape(-1, 3)
        params = json.loads(f["driver"].attrs["params"])
        intact = e["bond_state/point_state"][()] == 0 if "bond_state/point_state" in e else None
    kind = np.asarray(mesh(mesh_path)["body_kind"])[body]
    half = 0.5 * params["indenter_width"]
    indenter = np.unique(tri[kind == KIND_INDENTER])
    blocks = np.unique(tri[kind == KIND_BLOCK])
    under = blocks[np.abs(p0[blocks, 0]) < half]
    far = blocks[np.abs(p0[blocks, 0]) > 2.0 * half]
    dy = p[:, 1] - p0[:, 1]
    mm = [f"{1e3 * dy[nodes].mean():.1f}" if nodes.size else "—" for nodes in (indenter, under, far)]
    return params, mm, (-1 if intact is None else int((~intact).sum()))


def main(argv):
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if argv else 2
    missing = [d for d in argv if not os.path.isdir(d)]
    if missing:
        print(f"rest_rise: no such folder: {', '.join(missing)}", file=sys.stderr)
        return 2
    print("| checkpoint | τ_cr [kPa] | μ | bonds while settling | indenter [mm] | keel under it [mm] "
          "| keel beyond w_I [mm] | points not intact |")
    print("|---|---|---|---|---|---|---|---|")
    for d in argv:
        for ckpt in sorted(glob.glob(os.path.join(d, "*.checkpoint.h5"))):
            with h5py.File(ckpt, "r") as f:
                phase = f["driver"].attrs.get("phase", "")
            rest = "_rest_" in os.path.basename(ckpt)
            if not rest and phase != "settle":
                continue  # a loading checkpoint: its positions hold the indenter's travel
            mesh_path = mesh_of(ckpt, d)
            if mesh_path is None:
                print(f"| {os.path.basename(ckpt)} | no single mesh of its triangles in {d} or its scenes/ |||||||")
                continue
            params, mm, split = rise(ckpt, mesh_path)
            name = os.path.basename(ckpt) + ("" if rest else " (settling)")
            print(f"| {name} | {params['tau_cr'] / 1e3:g} | {params['mu']:g} "
                  f"| {params.get('settle_bonds', 'held')} | {' | '.join(mm)} | {split} |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
