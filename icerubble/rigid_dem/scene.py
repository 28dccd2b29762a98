"""A ridge as rigid blocks: the FEM-DEM run's mesh seen as polygons and bond
pairs (docs/model.md §6), so that both models run the same ridge.

- bodies: every mesh body (blocks, the two layer pieces, the indenter) as one
  polygon: the outline of its triangles in the mesh (collinear boundary nodes
  dropped), so exactly the shape the FEM-DEM run deforms;
- bond pairs: the FEM-DEM's cohesive pairs (icerubble/engine/bond_pairs.py):
  the same points, normals, crack lengths and depth-graded strengths, so both
  models bond the same faces in the same places;
- bond stiffness: a rigid block has no elements to carry an intact bond, so
  each pair is a spring as stiff as a contact face of its length in YADE's
  volumetric law (k = E l / 2 per metre of width: k_n = E/2 per m³ times the
  face l times 1 m of depth);
- a deformed state of the mesh (`state`, e.g. a FEM-DEM snapshot: snapshot.py):
  the outlines are taken where its triangles are, the pairs of fully failed
  bond points are left out and the others are placed where their point is
  then; which pairs there are, their strengths, lengths and stiffnesses stay
  the meshed ones (a bond's material, not its strain).

Nothing here needs YADE: the YADE driver builds bodies from it.
"""
import numpy as np

from .. import parameters as P
from ..engine.bond_pairs import bond_pairs
from ..files.mesh_file import KIND_BLOCK, KIND_INDENTER, KIND_LAYER, mesh_geometry
from ..geometry.bond_points import find_bond_points

# [m] every body's outline moved inward: faces that coincide exactly make YADE's
# polyhedra overlap run away; 10 um apart they do not, and the gap is closed at
# once under load (2 mm, the mesh's eps_sep, delayed contact by 2 mm of travel)
INSET = 1e-5


def body_outline(nodes, triangles, straight=1e-9):
    """The outline of one body's triangles, counter-clockwise, without the
    boundary nodes where it runs straight on (|sin| of the turn below
    `straight`). ValueError if the triangles do not make one simple region."""
    tri = np.asarray(triangles)
    directed = np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]])
    undirected = {}
    for i, j in directed:
        key = (min(i, j), max(i, j))
        undirected[key] = undirected.get(key, 0) + 1
    nxt = {int(i): int(j) for i, j in directed if undirected[(min(i, j), max(i, j))] == 1}
    if not nxt:
        raise ValueError("a body's triangles have no boundary")
    start = min(nxt)
    loop = [start]
    while nxt[loop[-1]] != start:
        loop.append(nxt[loop[-1]])
        if len(loop) > len(nxt):
            raise ValueError("a body's boundary is not one closed loop")
    if len(loop) != len(nxt):
        raise ValueError("a body's triangles make more than one boundary loop (a hole or two pieces)")
    pts = np.asarray(nodes, float)[loop]
    prev, nxt_pts = np.roll(pts, 1, axis=0), np.roll(pts, -1, axis=0)
    u, v = pts - prev, nxt_pts - pts
    turn = (u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]) / (np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1))
    return pts[np.abs(turn) > straight]


def rigid_scene(mesh, params, state=None):
    """The rigid-block description of a mesh (icerubble.files.mesh_file.read_mesh)
    for run parameters `params`: a dict of arrays, documented in the module.

    `state`: None (the mesh as meshed) or the mesh deformed, a dict of `nodes`
    (N', 2) positions now, `triangles` (M, 3) the mesh's triangles on them (a
    split bond node's copies appended, as the FEM-DEM engine splits) and
    `failed` (P,) bool per bond point of the mesh: fully failed by then."""
    # the geometry recorded is the mesh's, as a FEM-DEM run's (punch_through_run.py)
    p = P.recorded(P.validate(params), mesh_geometry(mesh))
    a = mesh["attrs"]
    nodes = np.asarray(mesh["nodes"], float)
    tri = np.asarray(mesh["triangles"])
    body = np.asarray(mesh["body"])
    kind = np.asarray(mesh["body_kind"])
    now, tri_now = (nodes, tri) if state is None else (np.asarray(state["nodes"], float),
                                                       np.asarray(state["triangles"]))
    if tri_now.shape != tri.shape:
        raise ValueError(f"state triangles {tri_now.shape} are not the mesh's {tri.shape}")
    polygons = [body_outline(now, tri_now[body == b]) for b in range(len(kind))]
    keel_top, keel_bottom = float(a["keel_top_y"]), float(a["keel_bottom_y"])
    indenter = np.flatnonzero(kind == KIND_INDENTER)
    layer = np.flatnonzero(kind == KIND_LAYER)
    if len(indenter) != 1:
        raise ValueError(f"mesh must have exactly one indenter body (found {len(indenter)})")
    cut = [(int(indenter[0]), int(b)) for b in layer]
    bp = find_bond_points(nodes, tri, body, keel_top_y=keel_top, keel_depth=keel_top - keel_bottom,
                          sigma_cr=p["sigma_cr"], tau_cr=p["tau_cr"], G=p["G"],
                          bottom_fraction=p["strength_bottom_fraction"], exclude_pairs=cut)
    pairs = bond_pairs(bp, nodes)
    position, normal = bp.position[pairs["point"]], pairs["normal"]
    if state is not None:
        failed = np.asarray(state["failed"], bool)
        if failed.shape != (len(bp),):
            raise ValueError(f"state failed has shape {failed.shape}, expected ({len(bp)},): one per bond point")
        position, normal = _pairs_now(pairs, bp.node, nodes, tri, body, now, tri_now)
        keep = ~failed[pairs["point"]]
        pairs = {k: v[keep] for k, v in pairs.items()}
        position, normal = position[keep], normal[keep]
    pt = pairs["point"]
    length = pairs["length"]
    layer_bottom = float(a["layer_bottom_y"])
    return dict(
        polygons=polygons, body_kind=kind, indenter=int(indenter[0]), layer=layer,
        y_w=layer_bottom + p["rho_i"] / p["rho_w"] * float(a["layer_thickness"]),
        keel_top_y=keel_top, keel_bottom_y=keel_bottom,
        bond_a=pairs["body_minus"], bond_b=pairs["body_plus"], bond_position=position,
        bond_normal=normal, bond_length=length, bond_point=pt,
        sigma_cr=bp.sigma_cr[pt], tau_cr=bp.tau_cr[pt], G=bp.G[pt], mu=np.full(len(pt), p["mu"]),
        bond_k=0.5 * p["E"] * length, bond_points=bp, params=p)


def _pairs_now(pairs, point_node, nodes, tri, body, now, tri_now):
    """Each cohesive pair's point and normal in a deformed state: the point
    midway between its two bodies' copies of the node (one node until it
    splits), the normal turned as its frame edge has turned (as the engine
    turns an intact pair's normal: docs/freeze_bonds.md, Frame)."""
    n_body = int(body.max()) + 1
    # (mesh node, body) -> that body's node now
    copy = dict(zip((tri.reshape(-1) * n_body + np.repeat(body, 3)).tolist(), tri_now.reshape(-1).tolist()))

    def at(node_ids, bodies):
        return now[[copy[int(i) * n_body + int(b)] for i, b in zip(node_ids, bodies)]]

    node = np.asarray(point_node)[pairs["point"]]
    a, b = pairs["body_minus"], pairs["body_plus"]
    position = 0.5 * (at(node, a) + at(node, b))
    fp, fq = pairs["frame_p"], pairs["frame_q"]
    e0 = nodes[fq] - nodes[fp]
    e1 = at(fq, a) - at(fp, a)
    turn = np.arctan2(e1[:, 1], e1[:, 0]) - np.arctan2(e0[:, 1], e0[:, 0])
    c, s = np.cos(turn), np.sin(turn)
    n = pairs["normal"]
    return position, np.column_stack([c * n[:, 0] - s * n[:, 1], s * n[:, 0] + c * n[:, 1]])
