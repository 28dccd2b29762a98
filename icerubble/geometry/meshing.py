"""Mesh of the settled pile for phase 2 (paper section 2.4): gmsh, continuous over touching blocks.

Bodies: blocks 0..n-1 (body_kind 0, same index as in the pile file), then the
consolidated layer left of the indenter (kind 1), the indenter (kind 2) and the
layer right of it (kind 1). The mesh is continuous wherever two bodies are bonded:
their common boundary is one gmsh curve (occ.fragment), so the elements on both
sides share its nodes. Every element edge between two different bodies is a
freeze-bond edge (docs/model.md §3.3). The indenter is cut free from the layer (as in a
punch-through test): its side faces share no nodes with the layer.

Before meshing, the phase-1 contacts are resolved into shared bond lines
(contact_resolution.py); the fragment then runs with the fuzzy tolerance `fuzzy`.
The mesh file: icerubble/files/mesh_file.py.
"""
from __future__ import annotations

import os
import time

import numpy as np

from .. import polygon
from ..files.mesh_file import KIND_BLOCK, KIND_INDENTER, KIND_LAYER
from ..openmp_threads import openmp_threads_kept
from ..parameters import require_range
from . import pile as _pile
from . import mesh_order
from .bond_points import bond_edges
from .contact_resolution import resolve_contacts


def _validate(element_size, gap_tol, min_bond_length, eps_sep, min_feature, indenter_width,
              indenter_thickness, domain_width, layer_thickness):
    r = require_range
    r("element_size (m)", element_size, 0.0, lo_open=True)
    r("gap_tol (m)", gap_tol, 0.0)
    r("min_bond_length (m)", min_bond_length, 0.0, lo_open=True)
    r("eps_sep (m)", eps_sep, 0.0, lo_open=True)
    r("min_feature (m)", min_feature, 0.0, min_bond_length)
    r("layer_thickness (m)", layer_thickness, 0.0, lo_open=True)
    r("indenter_width (m)", indenter_width, 0.0, lo_open=True)
    r("indenter_thickness (m)", indenter_thickness, 0.0, lo_open=True)
    if indenter_width >= domain_width:
        raise ValueError(f"indenter_width = {indenter_width} m must be smaller than the "
                         f"domain width {domain_width} m")
    if abs(indenter_thickness - layer_thickness) > 1e-12:
        raise ValueError(f"indenter_thickness = {indenter_thickness} m must equal the layer "
                         f"thickness {layer_thickness} m (the indenter is a plate cut from it)")


def _surface(occ, poly):
    pts = [occ.addPoint(float(x), float(y), 0.0) for x, y in poly]
    lines = [occ.addLine(pts[k], pts[(k + 1) % len(pts)]) for k in range(len(pts))]
    return occ.addPlaneSurface([occ.addCurveLoop(lines)])


# how far from x = +-W/2 a block node still lies on a face the crop cut [m]:
# the clip puts them there exactly, gmsh to round-off
CUT_TOL = 1e-6


def crop_blocks(corners, domain_width, min_width):
    """The pile's blocks cut to |x| <= domain_width/2 (the central part of a wider
    pile), as phase 1's side walls cut them; a piece thinner than ``min_width``
    (its smallest width across, over its edge normals) is dropped, since it could
    only be meshed with elements smaller than the scene's. Returns (polygons,
    kept, cut): the pieces, the pile index of each, and whether the crop cut it."""
    x0, x1 = -0.5 * domain_width, 0.5 * domain_width
    polys, kept, cut = [], [], []
    for i, c in enumerate(corners):
        p = _pile.clip_box(_pile.ccw(c), x0, x1, -np.inf, np.inf)
        if len(p) < 3 or polygon.min_width(p) < min_width:
            continue
        polys.append(p)
        kept.append(i)
        cut.append(bool(c[:, 0].min() < x0 or c[:, 0].max() > x1))
    return polys, np.array(kept, dtype=np.int64), np.array(cut, dtype=bool)


def build_mesh(pile_data, element_size=0.1, gap_tol=0.01, min_bond_length=0.05, eps_sep=2e-3,
               min_feature=0.01, fuzzy=1e-3, indenter_width=4.0, indenter_thickness=1.0,
               algorithm=6, feature_fraction=0.4, domain_width=None, verbose=False):
    """Mesh a pile (dict from icerubble.files.pile_file.read_pile). Returns the mesh dict (see write_mesh).

    ``domain_width`` below the pile's own meshes the central part of the pile
    (crop_blocks, pieces thinner than ``element_size`` dropped); its blocks are
    then numbered in pile order among the pieces kept (``pile_block``)."""
    import gmsh
    meta = pile_data["meta"]
    W_pile = float(meta["domain_width"])
    W = W_pile if domain_width is None else float(domain_width)
    if not 0.0 < W <= W_pile:
        raise ValueError(f"domain_width = {W} m must be in (0, {W_pile}] m, the pile's own width")
    t_c = float(meta["layer_thickness"])
    y_b = float(meta["layer_bottom_y"])
    _validate(element_size, gap_tol, min_bond_length, eps_sep, min_feature, indenter_width,
              indenter_thickness, W, t_c)
    require_range("fuzzy (m)", fuzzy, 0.0, 0.5 * eps_sep)
    require_range("feature_fraction (of element_size)", feature_fraction, 0.0, 0.5)
    times = {}
    t0 = time.perf_counter()
    x0, x1 = -0.5 * W, 0.5 * W
    feature = max(min_feature, feature_fraction * element_size)
    info = {}
    if W < W_pile:
        blocks, pile_block, cut = crop_blocks(pile_data["corners"], W, element_size)
    else:
        n = len(pile_data["corners"])
        blocks, pile_block, cut = list(pile_data["corners"]), np.arange(n), np.zeros(n, dtype=bool)

    def resolve():
        info.clear()   # the clean-up counts of the last resolution
        return resolve_contacts(blocks, y_b, x0, x1, gap_tol, min_bond_length, eps_sep, feature,
                                indenter_width, info, fuzzy)
    polys, contacts = resolve()
    while W < W_pile:
        # a piece cut from its block that keeps no bond lost what held it (the
        # part beyond the cut): it would float off, so it is dropped too (and
        # then any cut piece bonded only to it)
        bonded = {i for i, j, _, b in contacts if b} | {j for i, j, _, b in contacts if b and j >= 0}
        loose = {k for k in np.flatnonzero(cut) if k not in bonded}
        if not loose:
            break
        keep = [k for k in range(len(blocks)) if k not in loose]
        blocks, pile_block, cut = [blocks[k] for k in keep], pile_block[keep], cut[keep]
        polys, contacts = resolve()
    times["resolve"] = time.perf_counter() - t0
    nb = len(polys)
    xi = 0.5 * indenter_width
    y_t = y_b + t_c
    plates = [[(x0, y_b), (-xi, y_b), (-xi, y_t), (x0, y_t)],
              [(-xi, y_b), (xi, y_b), (xi, y_t), (-xi, y_t)],
              [(xi, y_b), (x1, y_b), (x1, y_t), (xi, y_t)]]
    body_kind = np.array([KIND_BLOCK] * nb + [KIND_LAYER, KIND_INDENTER, KIND_LAYER], np.int8)
    owner_rank = np.r_[np.arange(nb) + 3, [0, 1, 2]]  # overlap slivers: plates first, then lower id

    t0 = time.perf_counter()
    # gmsh.initialize() sets the process's OpenMP thread count to 1 and keeps it
    # so: put back, or a run that meshes its scene computes on one thread
    with openmp_threads_kept():
        gmsh.initialize(readConfigFiles=False)
        try:
            gmsh.option.setNumber("General.Terminal", 1 if verbose else 0)
            gmsh.model.add("pile")
            # OCC fuzzy booleans: corners and faces closer than `fuzzy` are one
            # (round-off and sub-mm mismatches of the contact rule would otherwise
            # leave sub-mm curves that force tiny elements); unbonded contacts are
            # kept apart by eps_sep > 2 fuzzy.
            gmsh.option.setNumber("Geometry.ToleranceBoolean", fuzzy)
            occ = gmsh.model.occ
            tags = [_surface(occ, p) for p in polys] + [_surface(occ, p) for p in plates]
            _, child_map = occ.fragment([(2, t) for t in tags], [])
            occ.synchronize()
            times["fragment"] = time.perf_counter() - t0
            parents = {}
            for body, children in enumerate(child_map):
                for dim, tag in children:
                    if dim == 2:
                        parents.setdefault(tag, []).append(body)
            surf_body = {}
            n_slivers, sliver_area = 0, 0.0
            for tag, bodies in parents.items():
                surf_body[tag] = min(bodies, key=lambda b: owner_rank[b])
                if len(bodies) > 1:
                    n_slivers += 1
                    sliver_area += occ.getMass(2, tag)
            t0 = time.perf_counter()
            gmsh.option.setNumber("Mesh.MeshSizeMax", element_size)
            gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
            gmsh.option.setNumber("Mesh.Algorithm", algorithm)
            # near a short curve the size follows its length, so small features get
            # small, well-shaped triangles instead of slivers; 1.6 x the length: the
            # short curve stays one element edge and the triangles next to it are not
            # smaller than it (at 1.0 x, gmsh puts ~0.6 L altitudes around a curve L)
            curve_len = {c: occ.getMass(1, c) for _, c in gmsh.model.getEntities(1)}
            # curves the clean-up could not lengthen (both ends held by other bonds)
            # still force elements of their size: count them
            lens = np.array(list(curve_len.values()))
            info["n_short_curves"] = int((lens < (1.0 - 1e-6) * feature).sum())
            info["shortest_curve"] = float(lens.min())
            for _, pt in gmsh.model.getEntities(0):
                up, _ = gmsh.model.getAdjacencies(0, pt)
                lmin = min((curve_len[c] for c in up), default=element_size)
                gmsh.model.mesh.setSize([(0, pt)], min(element_size, 1.6 * lmin))
            gmsh.model.mesh.generate(2)
            times["mesh"] = time.perf_counter() - t0
            node_tags, coords, _ = gmsh.model.mesh.getNodes()
            index = np.full(int(node_tags.max()) + 1, -1, np.int64)
            index[node_tags] = np.arange(len(node_tags))
            nodes = coords.reshape(-1, 3)[:, :2].copy()
            tris, body = [], []
            for tag, b in surf_body.items():
                etypes, _, enodes = gmsh.model.mesh.getElements(2, tag)
                for et, en in zip(etypes, enodes):
                    if et != 2:
                        raise RuntimeError(f"gmsh returned element type {et} on surface {tag}; "
                                           "expected 3-node triangles")
                    t3 = index[np.asarray(en, np.int64)].reshape(-1, 3)
                    tris.append(t3)
                    body.append(np.full(len(t3), b, np.int32))
        finally:
            gmsh.finalize()
    tris = np.vstack(tris)
    body = np.concatenate(body)
    # counter-clockwise
    a = _signed_areas(nodes, tris)
    tris[a < 0] = tris[a < 0][:, ::-1]
    nodes, tris = _cut_indenter(nodes, tris, body, nb, xi, y_b, y_t)
    # neighbours in space made neighbours in memory (every step reads each
    # triangle's corners and gathers each node's corner forces)
    nodes, tris, body, _ = mesh_order.renumber(nodes, tris, body, cell=0.5 * element_size)
    bond_edges_, bond_bodies, _ = bond_edges(tris, body)
    bond_edges_ = bond_edges_.astype(np.int32)
    bond_bodies = bond_bodies.astype(np.int32)
    tol = 1e-9 * max(1.0, W)
    layer_top = np.unique(tris[np.isin(body, [nb, nb + 2])])
    layer_top = layer_top[np.abs(nodes[layer_top, 1] - y_t) < tol]
    ind_top = np.unique(tris[body == nb + 1])
    ind_top = ind_top[np.abs(nodes[ind_top, 1] - y_t) < tol]
    # The faces the crop cut (|x| = W/2): the rest of the pile held them there,
    # so the scene holds them in x (cut_sides). Left free, the deep scene's
    # keel spread out of its cut sides and floated up, splitting bonds across
    # the section before the indenter had moved 1 mm (docs/study_paper_depth.md).
    cut_sides = np.zeros(0, np.int32)
    if W < W_pile:
        block_nodes = np.unique(tris[body_kind[body] == KIND_BLOCK])
        on_cut = np.abs(np.abs(nodes[block_nodes, 0]) - 0.5 * W) < CUT_TOL
        cut_sides = block_nodes[on_cut].astype(np.int32)
    blocks_final = [p.copy() for p in polys]
    bounds = _pile.keel_bounds(blocks_final, y_b, x0, x1)
    eta = porosity_of_mesh(nodes, tris, body_kind[body] == KIND_BLOCK, bounds)
    return dict(nodes=nodes, triangles=tris.astype(np.int32), body=body, body_kind=body_kind,
                bond_edges=bond_edges_, bond_edge_bodies=bond_bodies,
                layer_top=layer_top.astype(np.int32), indenter_top=ind_top.astype(np.int32),
                cut_sides=cut_sides,
                keel_bounds=bounds, porosity=eta,
                quality=dict(quality(nodes, tris), feature=feature),
                contacts=contact_table(contacts, nodes, bond_edges_, bond_bodies, nb),
                resolved_blocks=blocks_final, pile_block=pile_block.astype(np.int32),
                pile_domain_width=W_pile,
                # the friction phase 1 settled the pile at (NaN: not recorded)
                pile_friction=float(meta.get("friction", np.nan)),
                # ... and the friction it was then held at rest at (NaN: no hold stage)
                pile_hold_friction=float(meta.get("hold_friction", np.nan)),
                element_size=float(element_size), times=times,
                settings=dict(gap_tol=gap_tol, min_bond_length=min_bond_length, eps_sep=eps_sep,
                              min_feature=min_feature, fuzzy=fuzzy,
                              indenter_width=indenter_width, indenter_thickness=indenter_thickness,
                              layer_thickness=t_c, layer_bottom_y=y_b, domain_width=W,
                              algorithm=algorithm, feature_fraction=feature_fraction,
                              node_order=mesh_order.ORDER),
                resolve_info=dict(info, n_slivers=n_slivers, sliver_area=sliver_area))


def contact_table(contacts, nodes, bond_edges, bond_bodies, nb):
    """Contacts of the rule with the bond length the mesh actually has for each.

    bodies (C,2): block ids, j = -1 for the layer and indenter together; chord (C,):
    common face of the rule; bonded (C,); bond_length (C,): total length of the
    bond edges between the two (>= chord where the fuzzy fragment also joined
    faces diverging by less than `fuzzy` next to the common face).
    """
    length = np.linalg.norm(nodes[bond_edges[:, 0]] - nodes[bond_edges[:, 1]], axis=1)
    per = {}
    for (i, j), ln in zip(bond_bodies, length):
        key = (int(i), -1 if j >= nb else int(j))
        per[key] = per.get(key, 0.0) + float(ln)
    bodies = np.array([(i, j) for i, j, _, _ in contacts], np.int32).reshape(-1, 2)
    bond_length = np.array([per.get((min(i, j), max(i, j)) if j >= 0 else (i, -1), 0.0)
                            for i, j, _, _ in contacts])
    return dict(bodies=bodies, chord=np.array([c for _, _, c, _ in contacts], float),
                bonded=np.array([b for _, _, _, b in contacts], bool), bond_length=bond_length)


def _signed_areas(nodes, tris):
    p0, p1, p2 = nodes[tris[:, 0]], nodes[tris[:, 1]], nodes[tris[:, 2]]
    return 0.5 * ((p1[:, 0] - p0[:, 0]) * (p2[:, 1] - p0[:, 1]) -
                  (p2[:, 0] - p0[:, 0]) * (p1[:, 1] - p0[:, 1]))


def _cut_indenter(nodes, tris, body, nb, xi, y_b, y_t):
    """Give the layer its own copies of the nodes on the indenter's two side faces.

    The indenter is cut free from the layer (no bond edge between them). A bottom
    corner (+-xi, y_b) where a block bridges the cut stays one node of all three
    bodies, so the block keeps its bonds to both (a bond point of three bodies).
    """
    tol = 1e-9 * max(1.0, xi)
    ind = body == nb + 1
    lay = np.isin(body, [nb, nb + 2])
    ind_nodes = np.unique(tris[ind])
    lay_nodes = np.unique(tris[lay])
    shared = np.intersect1d(ind_nodes, lay_nodes)
    on_cut = (np.abs(np.abs(nodes[shared, 0]) - xi) < tol) & (nodes[shared, 1] > y_b - tol) & \
             (nodes[shared, 1] < y_t + tol)
    if not on_cut.all():
        raise RuntimeError("indenter and layer share nodes off the cut lines")
    shared = np.setdiff1d(shared, np.unique(tris[body < nb]))
    new_id = {int(k): len(nodes) + m for m, k in enumerate(shared)}
    nodes = np.vstack([nodes, nodes[shared]])
    lt = tris[lay]
    for k, v in new_id.items():
        lt[lt == k] = v
    tris = tris.copy()
    tris[lay] = lt
    return nodes, tris


def porosity_of_mesh(nodes, tris, is_ice, bounds):
    """eta = 1 - (ice triangle area inside the keel region) / (region area)."""
    x0, x1, y0, y1 = bounds
    pts = nodes[tris[is_ice]]
    inside = np.all((pts[:, :, 0] >= x0) & (pts[:, :, 0] <= x1) &
                    (pts[:, :, 1] >= y0) & (pts[:, :, 1] <= y1), axis=1)
    ice = np.abs(_signed_areas(nodes, tris[is_ice][inside])).sum()
    for p in pts[~inside]:
        ice += abs(_pile.polygon_area(_pile.clip_box(p, x0, x1, y0, y1)))
    return 1.0 - ice / ((x1 - x0) * (y1 - y0))


def quality(nodes, tris):
    """Angles, edge lengths, areas and the smallest altitude of the triangles.

    The smallest altitude (2 area / longest edge) sets the explicit engine's
    element time step (wave crossing time).
    """
    p = nodes[tris]
    e = np.stack([p[:, 1] - p[:, 0], p[:, 2] - p[:, 1], p[:, 0] - p[:, 2]], axis=1)
    ln = np.linalg.norm(e, axis=2)
    ang = []
    for k in range(3):
        u, v = -e[:, k - 1], e[:, k]
        cosv = np.einsum("ij,ij->i", u, v) / (np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1))
        ang.append(np.degrees(np.arccos(np.clip(cosv, -1, 1))))
    ang = np.stack(ang, axis=1)
    area = _signed_areas(nodes, tris)
    mn = ang.min(axis=1)
    return dict(min_angle_deg=float(mn.min()), mean_min_angle_deg=float(mn.mean()),
                max_angle_deg=float(ang.max()), frac_min_angle_below_20=float((mn < 20).mean()),
                min_edge=float(ln.min()), max_edge=float(ln.max()), mean_edge=float(ln.mean()),
                min_area=float(area.min()), max_area=float(area.max()),
                min_altitude=float((2.0 * np.abs(area) / ln.max(axis=1)).min()))


def mesh_pile_file(pile_path, mesh_path, **kw):
    """Read a pile file, mesh it, write the mesh file; returns the mesh dict."""
    from ..files.mesh_file import write_mesh
    from ..files.pile_file import read_pile
    p = read_pile(pile_path)  # validates before any work
    m = build_mesh(p, **kw)
    origin = {k: p["meta"][k] for k in ("made_on", "shipped") if k in p["meta"]}
    write_mesh(mesh_path, m, source=os.path.abspath(pile_path), pile_origin=origin)
    return m
