"""Pile and mesh files of a named scene and ridge, made on first use.

Phase 1 (the rigid-block pile) runs in YADE as a separate process
(yade_scripts/make_pile.py), so this works both from a YADE script and from
/usr/bin/python3; the mesh is made with gmsh in this process. Files are cached
under ``root/scenes``: a second run on the same ridge reuses them. The cache
key is the scene, the ridge and the friction the pile was settled at
(``<scene>_ridge<N>_pilemu<mu_settle>_pile.h5`` and ``..._mesh.h5``): a pile
made at another friction is never picked up, and a reused pile whose recorded
friction is not the scene's is refused. Runs of one ridge started together
(the lines of a study on a cluster) make its files once: the first takes a
lock (``..._scene.lock``, an advisory file lock), the others wait for it and
then find the files made.

The ridges the study tables name are shipped (data/ridges/, shipped_ridges.py):
their pile is copied, not made, so ridge N is the same pile on every machine;
a cached pile at a shipped ridge's name that is not the shipped one (made
here by phase 1 before ridges were shipped) is refused.
"""
import contextlib
import fcntl
import os
import shutil
import subprocess
import sys
import tempfile
import time

import h5py

from .. import parameters as P
from ..files.pile_file import read_pile
from ..geometry import mesh_order, meshing
from . import shipped_ridges
from .presets import pile_friction, pile_scene, scene

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MAKE_PILE = os.path.join(ROOT, "yade_scripts", "make_pile.py")


def run_phase1(pile_path, seed, pile_params, threads=1):
    """Run yade_scripts/make_pile.py for one pile; raises if YADE fails.

    One thread by default: YADE's pile is then the same bit for bit for the
    same seed (with two threads it is not: contact order varies); two threads
    are ~1.4x faster for large piles. A pile with a hold stage (mu_hold) is
    made in two YADE runs, the rise and the hold of its result (hold_from), so
    a pile made here is made as the shipped ones were."""
    params = dict(pile_params)
    mu_hold = params.pop("mu_hold", None)
    if mu_hold is None or mu_hold < 0:
        _yade_make_pile(dict(params, seed=int(seed), out=pile_path), threads)
        return
    rise = pile_path + ".rise.h5"
    try:
        _yade_make_pile(dict(params, seed=int(seed), out=rise), threads)
        _yade_make_pile(dict(params, seed=int(seed), mu_hold=mu_hold, hold_from=rise, out=pile_path),
                        threads)
    finally:
        if os.path.exists(rise):
            os.remove(rise)


def _yade_make_pile(cols, threads):
    with tempfile.NamedTemporaryFile("w", suffix=".table", delete=False) as f:
        f.write(" ".join(cols) + "\n")
        f.write(" ".join(repr(v) for v in cols.values()) + "\n")
        table = f.name
    env = dict(os.environ, YADE_BATCH=f"{table}:2")
    cmd = ["yade", f"-j{threads}", "-n", "-x", MAKE_PILE]
    t0 = time.perf_counter()
    try:
        r = subprocess.run(cmd, env=env, cwd=ROOT, capture_output=True, text=True)
    finally:
        os.remove(table)
    if r.returncode != 0 or not os.path.exists(cols["out"]):
        tail = "\n".join((r.stdout + r.stderr).strip().splitlines()[-15:])
        raise RuntimeError(f"phase 1 (YADE pile) failed with exit code {r.returncode}:\n{tail}")
    last = [ln for ln in r.stdout.splitlines() if ln.startswith("make_pile:")]
    print(last[-1] if last else f"make_pile: wrote {cols['out']}", f"({time.perf_counter() - t0:.0f} s)",
          flush=True)


def scene_paths(name, ridge, root="runs"):
    """Where scene_files keeps the pile and mesh of scene `name`, ridge
    `ridge`: (pile_path, mesh_path), nothing made or checked (e.g. to use a
    scene only where it is already made)."""
    ridge = P.require_whole("ridge", ridge, 0)   # it seeds the pile
    # absolute: phase 1 runs YADE in another folder
    d = os.path.join(os.path.abspath(root), "scenes")
    mu = pile_friction(name)
    return (os.path.join(d, shipped_ridges.file_stem(pile_scene(name), ridge, mu)) + "_pile.h5",
            os.path.join(d, shipped_ridges.file_stem(name, ridge, mu)) + "_mesh.h5")


def scene_files(name, ridge, root="runs", threads=1):
    """(pile_path, mesh_path) of scene `name`, ridge number `ridge` (its seed).

    A scene that meshes the central part of another scene's piles (``pile_of``)
    shares that scene's pile file and has a mesh of its own."""
    sc = scene(name)
    ridge = P.require_whole("ridge", ridge, 0)   # it seeds the pile
    pile_path, mesh_path = scene_paths(name, ridge, root)
    os.makedirs(os.path.dirname(pile_path), exist_ok=True)
    source = pile_scene(name)
    mu = pile_friction(name)
    pile_base = pile_path[:-len("_pile.h5")]
    base = mesh_path[:-len("_mesh.h5")]
    ship = shipped_ridges.shipped(source, ridge, mu)
    if os.path.exists(pile_path) and os.path.exists(mesh_path) and _mesh_current(mesh_path):
        _check_friction(pile_path, source, mu)
        _check_shipped(pile_path, ship, pile_base)
        return pile_path, mesh_path
    with _scene_lock(pile_base + "_scene.lock"):
        _make_pile(source, scene(source), ridge, mu, pile_path, threads, ship, pile_base)
    # a cropping scene's manifest entry has its own mesh digest
    mesh_ship = ship if source == name else shipped_ridges.shipped(name, ridge, mu)
    with _scene_lock(base + "_scene.lock"):   # runs started together mesh it once
        _make_mesh(name, sc, ridge, pile_path, mesh_path, mesh_ship)
    return pile_path, mesh_path


@contextlib.contextmanager
def _scene_lock(path):
    with open(path, "a") as f:
        try:
            fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            print(f"[scene] waiting for another run making the same scene ({path})", flush=True)
            fcntl.flock(f, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(f, fcntl.LOCK_UN)


def _mesh_current(mesh_path):
    """False for a cached mesh numbered before mesh_order (the same mesh, several
    times slower to step), or a cropped one that does not yet mark its cut faces
    (node_sets/cut_sides, which the scene holds): it is made again from its pile."""
    with h5py.File(mesh_path, "r") as f:
        order = f.attrs.get("node_order", "")
        cropped_unmarked = "pile_domain_width" in f.attrs and "node_sets/cut_sides" not in f
    return order == mesh_order.ORDER and not cropped_unmarked


def _check_friction(pile_path, name, mu):
    recorded = float(read_pile(pile_path)["meta"].get("friction", float("nan")))
    if recorded != mu:
        raise ValueError(f"{pile_path} was settled at friction {recorded:g}, the {name} scene's piles at "
                         f"{mu:g}: remove it (and its mesh) to make it again")


def _check_shipped(pile_path, ship, base):
    """A cached pile at a shipped ridge's name must be the shipped pile."""
    if ship is None or shipped_ridges.digest(pile_path) == ship[1]["pile_digest"]:
        return
    made_on = read_pile(pile_path)["meta"].get("made_on", "a processor not recorded")
    raise ValueError(
        f"{pile_path} is not this ridge's shipped pile ({os.path.relpath(ship[0], ROOT)}): it was made "
        f"by phase 1 on {made_on}, and YADE makes another pile for the same seed on another processor. "
        f"Move {base}_* away (the pile, its mesh and rest states) to run the ridge every machine runs.")


def _make_pile(name, sc, ridge, mu, pile_path, threads, ship, base):
    """The pile (shipped, or phase 1 in YADE) unless it exists."""
    if not os.path.exists(pile_path) and ship is not None:
        print(f"[scene] {name} ridge {ridge}: the shipped pile {os.path.relpath(ship[0], ROOT)} "
              f"(made in YADE on {ship[1]['made_on']}; the same on every machine)", flush=True)
        part = pile_path + f".{os.getpid()}.part"
        shutil.copyfile(ship[0], part)
        os.replace(part, pile_path)   # whole or not at all
    elif not os.path.exists(pile_path):
        print(f"[scene] phase 1: settling the pile of {name} ridge {ridge} in YADE at friction {mu:g} "
              "(a ridge not shipped in data/ridges: its pile depends on this machine's processor) ...",
              flush=True)
        run_phase1(pile_path, ridge, sc["pile"], threads=threads)
    _check_friction(pile_path, name, mu)
    _check_shipped(pile_path, ship, base)


def _make_mesh(name, sc, ridge, pile_path, mesh_path, ship):
    """The scene's mesh of the pile unless a current one exists."""
    if os.path.exists(mesh_path) and not _mesh_current(mesh_path):
        print(f"[scene] {mesh_path} predates the locality numbering of its nodes or the marking of its cut "
              "faces: meshing it again", flush=True)
    if not os.path.exists(mesh_path) or not _mesh_current(mesh_path):
        t0 = time.perf_counter()
        m = mesh_scene(sc, pile_path, mesh_path)
        q = m["quality"]
        print(f"[scene] mesh: {len(m['nodes'])} nodes, {len(m['triangles'])} triangles, "
              f"{len(m['bond_edges'])} bond edges, porosity {m['porosity']:.3f}, min angle "
              f"{q['min_angle_deg']:.1f} deg ({time.perf_counter() - t0:.1f} s)", flush=True)
        if ship is not None and shipped_ridges.digest(mesh_path) != ship[1]["mesh_digest"]:
            print(f"[scene] warning: this machine's mesh of {name} ridge {ridge} differs from the one its "
                  "shipped pile was meshed into where it was made (gmsh or numpy compute otherwise here): "
                  "results on it are not comparable bit for bit with other machines' "
                  "(docs/reproducibility.md)", flush=True)


def mesh_scene(sc, pile_path, mesh_path):
    """Mesh a pile with the scene's settings; returns the mesh dict."""
    # block edges shorter than a fifth of the element size are collapsed: they
    # would only make tiny elements that set a tiny stable step
    return meshing.mesh_pile_file(pile_path, mesh_path, element_size=sc["element_size"],
                                  min_feature=0.2 * sc["element_size"],
                                  domain_width=sc.get("domain_width"))


if __name__ == "__main__":
    print(scene_files(sys.argv[1], int(sys.argv[2])))
