"""A FEM-DEM state as rigid blocks (docs/model.md §6): the ridge of a FEM-DEM
result file at one of its snapshots, in the description `rigid_scene` gives
a mesh, so that YADE can take the pile up where the FEM-DEM run had it
(yade_state.load_into_yade, yade_scripts/load_state.py).

    sc = fem_dem_state("runs/x.h5", snapshot=2)   # or y_I=0.02 [m]: the nearest snapshot
    sc["polygons"], sc["bond_a"], ..., sc["source"]

Every body is the outline of its triangles where the snapshot has them; the
bond pairs are the mesh's, less those whose point had fully failed by the
snapshot's travel (y_I_fail <= y_I), each placed where its point is then.

The file does not hold the node positions, so they are rebuilt from what it
holds (docs/results_format.md):
- u_node and u_elem are measured from the rest state reached before loading
  (the recorder's reference), not from /mesh/nodes, the mesh as meshed: the
  settle moves blocks by millimetres (settle_max_block_move). The settled
  nodes are stored only through their triangle centroids, /mesh/centroid: they
  are rebuilt as the nodes with those centroids nearest to each body's rigid
  move from the meshed ones. The centroids fix the nodes of most meshes; where
  a few patterns of node moves leave every centroid in place (two on the small
  ridge 2's mesh), those come from the rigid move, missing only the settle's
  strain in them (~1e-6).
- u_node moves the mesh's own nodes. Where a bond point has split, the body
  with the highest id keeps the node and every other body has a copy (engine
  bond_split.cpp) that u_node does not hold: a copy is placed so that its
  triangles' centroids are the snapshot's (/mesh/centroid + u_elem), nearest
  to its body's rigid move since the rest state.
The rebuilt nodes must give back every triangle centroid of the snapshot: the
largest miss is recorded (`centroid_residual`) and a file they do not fit
(more than CENTROID_TOL) is refused.

Nothing here needs YADE.
"""
import os

import h5py
import numpy as np
from scipy.sparse import coo_matrix, identity
from scipy.sparse.linalg import splu

from .. import parameters as P
from ..files import results
from ..files.h5io import read_checked
from .scene import KIND_LAYER, rigid_scene

# [m] the rebuilt nodes' largest miss of a snapshot's triangle centroids: the
# file's own round-off is ~1e-15 m; a missed split shows as its opening (um-mm)
CENTROID_TOL = 1e-7
# relative weight of "nearest to the rigid move" against "these centroids":
# small enough to leave the centroids to round-off, large enough that the
# patterns the centroids do not fix stay at the rigid move
_NEAREST = 1e-5


def _rigid_move(src, dst, w):
    """The rotation R and shift t with dst ~ R src + t, weighted least squares."""
    ms, md = np.average(src, axis=0, weights=w), np.average(dst, axis=0, weights=w)
    s, d = src - ms, dst - md
    turn = np.arctan2(np.sum(w * (s[:, 0] * d[:, 1] - s[:, 1] * d[:, 0])), np.sum(w * (s * d).sum(axis=1)))
    c, sn = np.cos(turn), np.sin(turn)
    R = np.array([[c, -sn], [sn, c]])
    return R, md - R @ ms


def _fit_to_centroids(tri, centroids, guess, free):
    """`guess` with its `free` nodes moved as little as possible so that every
    triangle's corners average to `centroids` (the other nodes stay):
    min |A z - r|^2 + _NEAREST^2 |z|^2, A the free corners of each triangle."""
    rows = np.flatnonzero(free[tri].any(axis=1))
    out = np.array(guess, float)
    if len(rows) == 0:
        return out
    t = tri[rows]
    col = np.full(len(guess), -1)
    col[free] = np.arange(int(free.sum()))
    i, j = np.nonzero(free[t])
    A = coo_matrix((np.ones(len(i)), (i, col[t[i, j]])), shape=(len(rows), int(free.sum()))).tocsr()
    r = 3.0 * centroids[rows] - out[t].sum(axis=1)
    z = splu((A.T @ A + _NEAREST ** 2 * identity(A.shape[1])).tocsc()).solve(A.T @ r)
    out[free] += z
    return out


def _body_moves(body, area, before, after):
    """Per body, the rigid move (R, t) that takes its triangle centroids
    `before` nearest to `after` (area-weighted)."""
    return [_rigid_move(before[body == b], after[body == b], area[body == b]) for b in range(int(body.max()) + 1)]


def settled_nodes(nodes, tri, body, centroid):
    """The mesh's nodes at the rest state: triangle centroids `centroid`,
    nearest to each body's rigid move from `nodes` (a node of two bodies at
    the mean of their moves: no bond has split while settling)."""
    p = nodes[tri]
    area = 0.5 * np.abs(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]))
    guess, count = np.zeros_like(nodes), np.zeros(len(nodes))
    for b, (R, t) in enumerate(_body_moves(body, area, p.mean(axis=1), centroid)):
        ids = np.unique(tri[body == b])
        guess[ids] += nodes[ids] @ R.T + t
        count[ids] += 1
    used = count > 0
    guess[used] /= count[used][:, None]
    guess[~used] = nodes[~used]
    return _fit_to_centroids(tri, centroid, guess, used)


def deformed_mesh(nodes, tri, body, centroid, u_node, u_elem, split_nodes):
    """The mesh where a snapshot has it: (positions (N + copies, 2), triangles
    (M, 3) on them, largest miss of the snapshot's triangle centroids [m]).
    `centroid`: /mesh/centroid (the rest state's); `split_nodes`: the mesh
    nodes of the bond points split by then (every body but the highest id at
    such a node has its own copy, appended)."""
    rest = settled_nodes(nodes, tri, body, centroid)
    now_centroid = centroid + u_elem
    x = rest + u_node
    tri_now = np.array(tri)
    copies, guess = [], []
    p = nodes[tri]
    area = 0.5 * np.abs(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]))
    moves = None
    corner = np.argsort(tri.reshape(-1), kind="stable")   # the corners at each node, by node
    first = np.searchsorted(tri.reshape(-1)[corner], np.arange(len(nodes) + 1))
    for i in np.unique(split_nodes):
        at = corner[first[i]:first[i + 1]]                 # flat corner indices at node i
        bodies = np.unique(body[at // 3])
        if len(bodies) < 2:
            continue
        if moves is None:   # each body's rigid move since the rest state
            moves = _body_moves(body, area, centroid, now_centroid)
        for b in bodies[:-1]:   # the highest body keeps the node
            k = len(x) + len(copies)
            mine = at[body[at // 3] == b]
            tri_now[mine // 3, mine % 3] = k
            R, t = moves[b]
            copies.append(k)
            guess.append(R @ rest[i] + t)
    if copies:
        x = np.vstack([x, np.array(guess)])
        free = np.zeros(len(x), bool)
        free[copies] = True
        x = _fit_to_centroids(tri_now, now_centroid, x, free)
    miss = float(np.abs(x[tri_now].mean(axis=1) - now_centroid).max()) if len(tri) else 0.0
    return x, tri_now, miss


def pick_snapshot(run, snapshot=None, y_I=None):
    """The index (in run.snapshots, by travel) of snapshot number `snapshot`, or
    of the one nearest travel `y_I` [m]; default the last. ValueError naming
    the parameter and what is valid."""
    snaps = run.snapshots
    if not snaps:
        raise ValueError(f"{run.path}: the result has no snapshots (/snapshots is empty or absent): "
                         "no state to load")
    if snapshot is not None and y_I is not None:
        raise ValueError("give snapshot or y_I, not both")
    travels = ", ".join(f"{s.y_I * 1e3:.2f}" for s in snaps)
    if snapshot is not None:
        if not (isinstance(snapshot, (int, np.integer)) and 0 <= snapshot < len(snaps)):
            raise ValueError(f"snapshot={snapshot!r} is out of range: valid 0 to {len(snaps) - 1} "
                             f"(y_I = {travels} mm)")
        return int(snapshot)
    if y_I is not None:
        y_last = snaps[-1].y_I
        if not (0.0 <= y_I <= y_last):
            raise ValueError(f"y_I={y_I * 1e3:.3g} mm is out of range: valid 0 to {y_last * 1e3:.3g} mm, "
                             f"the run's last snapshot (snapshots at y_I = {travels} mm)")
        return int(np.argmin([abs(s.y_I - y_I) for s in snaps]))
    return len(snaps) - 1


def read_result(path):
    """A result file read by files/results.py (ValueError if it is not a
    complete, readable result)."""
    try:
        return results.load(path)
    except results.ResultFileError as e:
        raise ValueError(str(e)) from None


def result_mesh(run):
    """The /mesh of result `run` as rigid_scene takes a mesh, with the
    attributes it needs: keel from /pile, layer thickness from /parameters
    (both the simulated mesh's), the domain width the layer's, the layer bottom its lowest node (what the
    mesh file records: the layer is meshed from its bottom to its top). The
    result's own mesh, so a result loads without its mesh file."""
    with h5py.File(run.path, "r") as f:
        def get(name, shape, kind="f", units=None):
            return read_checked(f, name, shape=shape, kind=kind, units=units, what="result file")
        nodes = get("mesh/nodes", (None, 2), units="m")
        tri = get("mesh/triangles", (None, 3), "i")
        body = get("mesh/body", (len(tri),), "i")
        kind = get("mesh/body_kind", (None,), "i")
    layer_nodes = np.unique(tri[np.isin(body, np.flatnonzero(kind == KIND_LAYER))])
    if len(layer_nodes) == 0:
        raise ValueError(f"{run.path}: /mesh has no consolidated layer (body_kind 1)")
    y = nodes[layer_nodes, 1]
    t = float(run.parameters["layer_thickness"])
    if abs((y.max() - y.min()) - t) > 1e-9 * max(1.0, t):
        raise ValueError(f"{run.path}: /parameters layer_thickness = {t} m, but the layer of /mesh is "
                         f"{y.max() - y.min()} m thick: the file does not describe one mesh")
    x = nodes[layer_nodes, 0]   # the layer spans the domain
    attrs = dict(keel_top_y=float(run.pile["keel_top_y"]), keel_bottom_y=float(run.pile["keel_bottom_y"]),
                 layer_bottom_y=float(y.min()), layer_thickness=t, domain_width=float(x.max() - x.min()))
    return dict(nodes=nodes, triangles=tri, body=body, body_kind=kind, attrs=attrs)


def result_params(run):
    """The run parameters of result `run` (its /parameters without units)."""
    return {key: v for key, v in run.parameters.items() if key in P.TABLE_1}


def fem_dem_state(path, snapshot=None, y_I=None):
    """The rigid description (rigid_scene's dict) of the ridge of FEM-DEM result
    `path` at snapshot number `snapshot` (0 the first, by travel) or the one
    nearest travel `y_I` [m] (default: the last snapshot), plus:

    - source: file, model, snapshot (its group name), index, y_I, t, and the
      y_I asked for (None if by number);
    - bond_split: per pair kept, whether its point had split (it is past its
      peak and softening in the FEM-DEM; a rigid scene's pairs start intact);
    - pairs_failed: how many of the mesh's pairs were left out as failed;
    - centroid_residual: the rebuilt nodes' largest miss of the snapshot's
      triangle centroids [m];
    - nodes, triangles: the deformed mesh the outlines were taken from.

    ValueError (naming the parameter or the file) for a snapshot or y_I out of
    range, a rigid-dem result, a result without snapshots, a damaged file."""
    path = os.fspath(path)
    run = read_result(path)
    if run.model != "fem-dem":
        raise ValueError(f"{path}: model = {run.model!r}; only a fem-dem result has a deformed state to load "
                         "(a rigid-dem run's snapshots move the FEM-DEM mesh with rigid bodies)")
    k = pick_snapshot(run, snapshot, y_I)
    snap = run.snapshots[k]
    mesh = result_mesh(run)
    n, m = len(mesh["nodes"]), len(mesh["triangles"])
    with h5py.File(path, "r") as f:
        centroid = read_checked(f, "mesh/centroid", shape=(m, 2), units="m", what="result file")
        g = f"snapshots/{snap.name}"
        u_node = read_checked(f, g + "/u_node", shape=(n, 2), units="m", what="result file")
        u_elem = read_checked(f, g + "/u_elem", shape=(m, 2), units="m", what="result file")
    params = result_params(run)
    reference = rigid_scene(mesh, params)
    bp = reference["bond_points"]
    b = run.bonds
    if b["position"].shape != bp.position.shape or not np.allclose(b["position"], bp.position, rtol=0, atol=1e-9):
        raise ValueError(f"{path}: /bonds/position is not the bond points of /mesh "
                         f"({len(b['position'])} rows, the mesh has {len(bp)})")
    y_fail, y_split = np.asarray(b["y_I_fail"], float), np.asarray(b["y_I_split"], float)
    failed = y_fail <= snap.y_I            # NaN (never failed) compares False
    split = failed | (y_split <= snap.y_I)
    nodes_now, tri_now, miss = deformed_mesh(mesh["nodes"], mesh["triangles"], mesh["body"], centroid,
                                             u_node, u_elem, bp.node[split])
    if not miss <= CENTROID_TOL:
        raise ValueError(f"{path}: snapshot {snap.name} (y_I = {snap.y_I * 1e3:.3g} mm): the rebuilt nodes miss "
                         f"its triangle centroids by up to {miss:.3g} m (> {CENTROID_TOL:g} m): u_node, u_elem "
                         "and /mesh/centroid do not describe one mesh (or a split bond point is not in /bonds)")
    sc = rigid_scene(mesh, params, state=dict(nodes=nodes_now, triangles=tri_now, failed=failed))
    sc.update(source=dict(file=os.path.abspath(path), model=run.model, snapshot=snap.name, index=k,
                          y_I=snap.y_I, t=snap.t, y_I_asked=y_I),
              bond_split=split[sc["bond_point"]], pairs_failed=len(reference["bond_point"]) - len(sc["bond_point"]),
              centroid_residual=miss, nodes=nodes_now, triangles=tri_now)
    return sc
