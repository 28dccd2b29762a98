"""Make the shipped ridges (data/ridges/): each (scene, ridge) a table in data/
names, plus the demo's and the benchmarks', settled once in YADE here and kept
as data, so ridge N is one pile on every machine (icerubble/run/shipped_ridges.py).

    /usr/bin/python3 tools/make_ridges.py [--piles DIR] [--remake] [--scenes demo,small,...]

A pile already in data/ridges/ is kept (its digest must not change: results
name it), unless --remake; --piles DIR takes piles made before, named as the
scene cache names them (DIR/<scene>_ridge<N>_pilemu<mu>_pile.h5), instead of
running phase 1 again. Every pile is meshed with its scene's settings and the
manifest records both digests, the blocks, the keel and the processor it was
made on. Phase 1 of a paper ridge takes 10-30 minutes.
"""
import argparse
import datetime
import json
import os
import shutil
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

import h5py  # noqa: E402

from icerubble import machine  # noqa: E402
from icerubble.files.pile_file import read_pile  # noqa: E402
from icerubble.run import shipped_ridges as SR  # noqa: E402
from icerubble.run.presets import pile_friction, pile_scene, scene  # noqa: E402
from icerubble.run.scene_cache import mesh_scene, run_phase1  # noqa: E402
from icerubble.study.table_check import ridges_to_ship  # noqa: E402

def main(argv=None):
    ap = argparse.ArgumentParser(prog="tools/make_ridges.py", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--piles", help="a folder of piles made before (the scene cache's names)")
    ap.add_argument("--remake", action="store_true", help="make every pile again (new digests)")
    ap.add_argument("--scenes", help="only these scenes' ridges (comma-separated); the manifest keeps the others")
    a = ap.parse_args(argv)
    os.makedirs(SR.RIDGES_DIR, exist_ok=True)
    entries = SR.manifest()
    only = set(a.scenes.split(",")) if a.scenes else None
    # a scene that meshes another's piles after that scene's piles are shipped
    for name, ridge in sorted(ridges_to_ship(), key=lambda sr: (pile_scene(sr[0]) != sr[0], sr)):
        if only is not None and name not in only:
            continue
        sc = scene(name)
        mu = pile_friction(name)
        stem = SR.file_stem(name, ridge, mu)
        # a scene that meshes the central part of another's piles ships no pile
        # of its own: its entry names the source pile and its own mesh
        source = pile_scene(name)
        pile_path = os.path.join(SR.RIDGES_DIR, SR.file_stem(source, ridge, mu) + "_pile.h5")
        given = os.path.join(a.piles, SR.file_stem(source, ridge, mu) + "_pile.h5") if a.piles else None
        if source != name and not os.path.exists(pile_path):
            raise SystemExit(f"{name} ridge {ridge} meshes {source} ridge {ridge}'s pile: ship that first "
                             f"(--scenes {source})")
        if source == name and (a.remake or not os.path.exists(pile_path)):
            if given and os.path.exists(given):
                shutil.copyfile(given, pile_path)
            else:
                print(f"phase 1: {name} ridge {ridge} ...", flush=True)
                run_phase1(pile_path, ridge, sc["pile"], threads=1)   # one thread: YADE's own order
        with h5py.File(pile_path, "r+") as f:
            f.attrs["shipped"] = os.path.relpath(pile_path, ROOT)
            if "made_on" not in f.attrs:   # made here, before piles recorded it
                f.attrs["made_on"] = machine.processor()
        meta = read_pile(pile_path)["meta"]
        with tempfile.TemporaryDirectory() as tmp:
            mesh_path = os.path.join(tmp, "mesh.h5")
            m = mesh_scene(sc, pile_path, mesh_path)
            mesh_digest = SR.digest(mesh_path)
        entries[stem] = dict(
            scene=name, ridge=ridge, pile=os.path.basename(pile_path), pile_digest=SR.digest(pile_path),
            mesh_digest=mesh_digest,
            n_blocks=int(meta["n_blocks"]) if source == name else len(m["resolved_blocks"]),
            pile_porosity=round(float(meta["porosity"]), 4),
            keel_depth=round(float(meta["keel_top_y"] - meta["keel_bottom_y"]) if source == name
                             else float(m["keel_bounds"][3] - m["keel_bounds"][2]), 3),
            n_triangles=int(len(m["triangles"])), mesh_porosity=round(float(m["porosity"]), 4),
            made_on=str(meta["made_on"]), yade_version=str(meta["yade_version"]))
        print(f"{stem}: {entries[stem]['n_blocks']} blocks, {entries[stem]['n_triangles']} triangles, "
              f"keel {entries[stem]['keel_depth']} m", flush=True)
    with open(SR.MANIFEST + ".part", "w") as f:
        json.dump(dict(made=datetime.date.today().isoformat(), made_by="tools/make_ridges.py",
                       ridges=entries), f, indent=1, sort_keys=True)
        f.write("\n")
    os.replace(SR.MANIFEST + ".part", SR.MANIFEST)
    print(f"wrote {SR.MANIFEST} ({len(entries)} ridges)")


if __name__ == "__main__":
    main()
