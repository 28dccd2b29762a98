"""The mesh file: the meshed pile that phase 2 runs on (layout: docs/pile_and_mesh.md).

The reader checks every dataset (present, shape, dtype, finite, units) and
that every index points into the node / triangle / body arrays before any
work: a broken or millimetre mesh is refused with the file and dataset named.
"""
import numpy as np

from .h5io import AtomicH5, open_complete, read_checked, write_dataset

MESH_FORMAT = "icerubble-mesh"
MESH_FORMAT_VERSION = 1

# body_kind codes of every mesh and result (docs/conventions.md): declared here,
# where the file that carries them is read and written
KIND_BLOCK, KIND_LAYER, KIND_INDENTER = 0, 1, 2


def mesh_geometry(mesh):
    """The geometry of a mesh (read_mesh), as the registry's mesh group names
    it (icerubble/parameters.py): what a run simulates and its result records
    in /parameters, whatever Table 1 says (the geometry is the scene's)."""
    a = mesh["attrs"]
    body_kind = np.asarray(mesh["body_kind"])
    indenter = np.nonzero(body_kind == KIND_INDENTER)[0]
    if len(indenter) != 1:
        raise ValueError(f"mesh must have exactly one indenter body (found {len(indenter)})")
    tri = np.asarray(mesh["triangles"])
    nodes = np.asarray(mesh["nodes"], dtype=float)[np.unique(tri[np.asarray(mesh["body"]) == indenter[0]])]
    xs, ys = nodes[:, 0], nodes[:, 1]
    return dict(keel_depth=float(a["keel_top_y"]) - float(a["keel_bottom_y"]),
                indenter_width=float(xs.max() - xs.min()), indenter_thickness=float(ys.max() - ys.min()),
                layer_thickness=float(a["layer_thickness"]), domain_width=float(a["domain_width"]))


def write_mesh(path, m, source="", pile_origin=None):
    """Write the mesh dict of geometry.meshing.build_mesh to `path` (atomically).
    pile_origin: where the pile comes from (its `made_on` and `shipped`
    attributes, machine.py), kept with the mesh for every result made on it."""
    with AtomicH5(path, MESH_FORMAT, MESH_FORMAT_VERSION) as f:
        f.attrs["source_pile"] = source
        for k, v in (pile_origin or {}).items():
            f.attrs["pile_" + k] = v
        f.attrs["element_size"] = m["element_size"]
        f.attrs["porosity"] = m["porosity"]
        f.attrs["pile_friction"] = m.get("pile_friction", np.nan)
        if np.isfinite(m.get("pile_hold_friction", np.nan)):
            f.attrs["pile_hold_friction"] = m["pile_hold_friction"]
        for k, v in zip(("keel_x_min", "keel_x_max", "keel_bottom_y", "keel_top_y"), m["keel_bounds"]):
            f.attrs[k] = v
        for k, v in m["settings"].items():
            f.attrs[k] = v
        write_dataset(f, "nodes", m["nodes"], "m")
        write_dataset(f, "triangles", m["triangles"], "-")
        write_dataset(f, "body", m["body"], "-")
        write_dataset(f, "body_kind", m["body_kind"], "-")
        write_dataset(f, "bond_edges", m["bond_edges"], "-")
        write_dataset(f, "bond_edge_bodies", m["bond_edge_bodies"], "-")
        write_dataset(f, "node_sets/layer_top", m["layer_top"], "-")
        write_dataset(f, "node_sets/indenter_top", m["indenter_top"], "-")
        c = m["contacts"]
        write_dataset(f, "contacts/bodies", c["bodies"], "-")
        write_dataset(f, "contacts/chord", c["chord"], "m")
        write_dataset(f, "contacts/bonded", c["bonded"].astype(np.int8), "-")
        write_dataset(f, "contacts/bond_length", c["bond_length"], "m")
        if m.get("pile_domain_width", m["settings"]["domain_width"]) != m["settings"]["domain_width"]:
            # the central part of a wider pile: which pile block each body is
            f.attrs["pile_domain_width"] = m["pile_domain_width"]
            write_dataset(f, "pile_block", m["pile_block"], "-")
            # the block nodes on the faces the crop cut: held in x by the scene
            write_dataset(f, "node_sets/cut_sides", m["cut_sides"], "-")
        rb = m["resolved_blocks"]
        write_dataset(f, "resolved_blocks/vertices", np.vstack(rb), "m")
        write_dataset(f, "resolved_blocks/offsets",
                      np.cumsum([0] + [len(p) for p in rb]).astype(np.int64), "-")
        q = f.create_group("quality")
        for k, v in m["quality"].items():
            q.attrs[k] = v
        for k, v in m["resolve_info"].items():
            q.attrs[k] = v


# Attributes phase 2 reads from a mesh: a mesh without them cannot place the
# water line, the keel or the indenter.
_REQUIRED_ATTRS = ("element_size", "domain_width", "layer_thickness", "layer_bottom_y",
                   "keel_top_y", "keel_bottom_y", "indenter_width")


def read_mesh(path):
    """Read a mesh file into a dict; ValueError naming the file and dataset
    if it is not a complete, consistent icerubble mesh in metres."""
    with open_complete(path, MESH_FORMAT, what="mesh file") as f:
        def get(name, shape, kind="f", units=None):
            return read_checked(f, name, shape=shape, kind=kind, units=units, what="mesh file")
        out = dict(nodes=get("nodes", (None, 2), units="m"),
                   triangles=get("triangles", (None, 3), "i"),
                   bond_edges=get("bond_edges", (None, 2), "i"),
                   bond_edge_bodies=get("bond_edge_bodies", (None, 2), "i"),
                   layer_top=get("node_sets/layer_top", (None,), "i"),
                   indenter_top=get("node_sets/indenter_top", (None,), "i"))
        # a cropped mesh's cut faces (none in a mesh of a whole pile)
        out["cut_sides"] = (get("node_sets/cut_sides", (None,), "i") if "node_sets/cut_sides" in f
                            else np.zeros(0, np.int32))
        n_tri = len(out["triangles"])
        out["body"] = get("body", (n_tri,), "i")
        n_body = int(out["body"].max()) + 1 if n_tri else 0
        out["body_kind"] = get("body_kind", (n_body,), "i")
        for name, ids, n in (("triangles", out["triangles"], len(out["nodes"])),
                             ("bond_edges", out["bond_edges"], len(out["nodes"])),
                             ("node_sets/layer_top", out["layer_top"], len(out["nodes"])),
                             ("node_sets/indenter_top", out["indenter_top"], len(out["nodes"])),
                             ("node_sets/cut_sides", out["cut_sides"], len(out["nodes"])),
                             ("body", out["body"], n_body),
                             ("bond_edge_bodies", out["bond_edge_bodies"], n_body)):
            if ids.size and (ids.min() < 0 or ids.max() >= n):
                raise ValueError(f"mesh file {path!r}, dataset {name!r}: ids must lie in "
                                 f"[0, {n - 1}], got [{ids.min()}, {ids.max()}]")
        missing = [k for k in _REQUIRED_ATTRS if k not in f.attrs]
        if missing:
            raise ValueError(f"mesh file {path!r}: root attribute(s) {', '.join(missing)} missing")
        v = get("resolved_blocks/vertices", (None, 2), units="m")
        o = get("resolved_blocks/offsets", (None,), "i")
        out["resolved_blocks"] = [v[o[i]:o[i + 1]] for i in range(len(o) - 1)]
        nc = len(get("contacts/bodies", (None, 2), "i"))
        out["contacts"] = dict(bodies=f["contacts/bodies"][...],
                               chord=get("contacts/chord", (nc,), units="m"),
                               bonded=get("contacts/bonded", (nc,), "i").astype(bool),
                               bond_length=get("contacts/bond_length", (nc,), units="m"))
        out["attrs"] = dict(f.attrs)
        out["quality"] = dict(f["quality"].attrs) if "quality" in f else {}
        return out
