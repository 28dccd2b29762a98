"""`icerubble mesh`: mesh a settled pile (phase 1 output) for the punch-through phase.

    icerubble mesh pile.h5 mesh.h5 [--element-size 0.1] [--overwrite] [...]

An existing MESH is kept unless --overwrite is given, and even then only an
icerubble mesh is replaced: never the input pile, never another file.

From Python or a YADE script: icerubble.geometry.meshing.mesh_pile_file.
Contact rule: icerubble/geometry/contact_resolution.py; file layout: docs/pile_and_mesh.md.
"""
import argparse
import os
import time

from ..files.h5io import open_complete
from ..files.mesh_file import MESH_FORMAT
from ..files.output_path import check_output_file
from . import meshing


def check_mesh_output(pile, mesh, overwrite):
    """Refuse (ValueError) a MESH whose writing would lose a file: the input
    pile itself, an existing file without --overwrite, or with it anything
    but an icerubble mesh (a result, a pile, a file of another program)."""
    check_output_file(mesh, "mesh file")
    if not os.path.exists(mesh):
        return
    if os.path.exists(pile) and os.path.samefile(pile, mesh):
        raise ValueError(f"mesh file {mesh!r} is the input pile: writing it would replace the pile; "
                         "name another mesh file")
    if not overwrite:
        raise ValueError(f"mesh file {mesh!r} exists: name another file, or give --overwrite to replace it")
    try:
        open_complete(mesh, MESH_FORMAT, what="mesh file").close()
    except ValueError as e:
        raise ValueError(f"{e}; --overwrite replaces only a complete icerubble mesh: name another file") from None


def main(argv=None):
    ap = argparse.ArgumentParser(prog="icerubble mesh", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("pile", help="icerubble-pile HDF5 file from yade_scripts/make_pile.py")
    ap.add_argument("mesh", help="output icerubble-mesh HDF5 file")
    ap.add_argument("--element-size", type=float, default=0.1, help="target element edge (m), default 0.1")
    ap.add_argument("--gap-tol", type=float, default=0.01,
                    help="faces closer than this (m) are snapped together, default 0.01")
    ap.add_argument("--min-bond-length", type=float, default=0.05,
                    help="shorter contacts are left unbonded (m), default 0.05")
    ap.add_argument("--min-feature", type=float, default=0.01,
                    help="shorter block edges are collapsed (m), default 0.01")
    ap.add_argument("--eps-sep", type=float, default=2e-3,
                    help="gap left at unbonded contacts (m), default 2e-3")
    ap.add_argument("--fuzzy", type=float, default=1e-3,
                    help="gmsh/OCC boolean tolerance (m), < eps_sep/2, default 1e-3")
    ap.add_argument("--indenter-width", type=float, default=4.0, help="m, default 4 (paper)")
    ap.add_argument("--overwrite", action="store_true", help="replace an existing icerubble mesh file MESH")
    a = ap.parse_args(argv)
    check_mesh_output(a.pile, a.mesh, a.overwrite)
    t0 = time.perf_counter()
    m = meshing.mesh_pile_file(a.pile, a.mesh, element_size=a.element_size, gap_tol=a.gap_tol,
                               min_bond_length=a.min_bond_length, min_feature=a.min_feature,
                               eps_sep=a.eps_sep, fuzzy=a.fuzzy, indenter_width=a.indenter_width)
    q = m["quality"]
    nb = int(m["contacts"]["bonded"].sum())
    print(f"mesh: wrote {a.mesh} in {time.perf_counter() - t0:.1f} s: "
          f"{len(m['nodes'])} nodes, {len(m['triangles'])} triangles, {len(m['bond_edges'])} bond edges, "
          f"{nb}/{len(m['contacts']['bonded'])} contacts bonded, porosity {m['porosity']:.3f}, "
          f"min angle {q['min_angle_deg']:.1f} deg, min edge {q['min_edge'] * 1e3:.2f} mm")
