"""`icerubble mesh`: mesh a settled pile (phase 1 output) for the punch-through phase.

    icerubble mesh pile.h5 mesh.h5 [--element-size 0.1] [...]

From Python or a YADE script: icerubble.geometry.meshing.mesh_pile_file.
Contact rule: icerubble/geometry/contact_resolution.py; file layout: docs/pile_and_mesh.md.
"""
import argparse
import time

from . import meshing


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
    a = ap.parse_args(argv)
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
