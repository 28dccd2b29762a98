"""The study's ridges as data: ridge N of a scene is one pile on every machine.

YADE's phase 1 settles blocks dropped at random; the settle is chaotic and
its floating point follows the processor (glibc's libm and numpy choose code
paths by the CPU's features). Measured: demo ridge 1 made with AVX-512, or
AVX2 and FMA, masked from glibc and numpy (an older processor, emulated) is
another pile, and so another mesh and another F^m; on another machine of this
project's kind, paper ridge 1 had 91,716 triangles against 90,950. So the
piles of the ridges the study tables name were made once, in YADE, and ship
in data/ridges/: the scene cache copies them instead of running phase 1.
Any other ridge number is made here by phase 1 (its pile records the
processor it was made on, `made_on`).

Meshing a pile (gmsh, numpy) gave the same bits with those features masked;
manifest.json keeps each shipped ridge's mesh digest, so a machine whose
gmsh meshes it differently says so (tests/run/test_shipped_ridges.py).
`tools/make_ridges.py` makes the piles and the manifest.
"""
import hashlib
import json
import os

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
RIDGES_DIR = os.path.join(ROOT, "data", "ridges")
MANIFEST = os.path.join(RIDGES_DIR, "manifest.json")
# shipped beyond the tables' ridges: the demo's and the sleeping benchmark's far field
ALSO_SHIPPED = (("demo", 1), ("wide", 1))


def file_stem(scene_name, ridge, pile_friction):
    """<scene>_ridge<N>_pilemu<mu>: the name of a ridge's files, shipped or cached."""
    return f"{scene_name}_ridge{int(ridge)}_pilemu{float(pile_friction):g}"


def manifest():
    """{stem: entry} of the shipped ridges ({} if none are shipped)."""
    if not os.path.exists(MANIFEST):
        return {}
    with open(MANIFEST) as f:
        return json.load(f)["ridges"]


def shipped(scene_name, ridge, pile_friction):
    """(pile path, manifest entry) of a shipped ridge, or None."""
    stem = file_stem(scene_name, ridge, pile_friction)
    entry = manifest().get(stem)
    if entry is None:
        return None
    # a scene meshing the central part of another's pile names that pile
    return os.path.join(RIDGES_DIR, entry.get("pile", stem + "_pile.h5")), entry


def digest(path):
    """sha256 of an HDF5 file's datasets (names, dtypes, shapes, values): its
    geometry, not the attributes that say when and by what it was written."""
    h = hashlib.sha256()

    def add(name, obj):
        if isinstance(obj, h5py.Dataset):
            a = np.ascontiguousarray(obj[()])
            h.update(f"{name}:{a.dtype}:{a.shape}".encode())
            h.update(a.tobytes())
    with h5py.File(path, "r") as f:
        f.visititems(add)
    return h.hexdigest()
