"""The cohesive pairs of a mesh's bond points, in the form the engine takes
them (Model.set_bond_points; the rigid-block model's bonds, rigid_dem/scene.py).

The bond points themselves (which nodes, their normals, lengths and strengths)
are found from the mesh by icerubble/geometry/bond_points.py; this is the
engine's side of that hand-over, so the engine needs nothing from geometry.
"""
import numpy as np


def bond_pairs(bp, nodes):
    """The cohesive pairs of each bond point, as the engine needs them.

    A pair is two bodies that share a bond edge at the point's node: one per
    ordinary bond point, one per such body pair at a junction. Per pair: its
    point index, the bodies on the - and + side (the normal points from the
    lower id to the higher), the normal (length-weighted mean of the pair's
    edge normals at the node), l (half of each of the pair's bond edges at the
    node) and two frame nodes whose rotation turns the normal with the bodies
    while the pair is intact (the far ends of its two edges, or the node and
    the far end of its only edge). For an ordinary bond point normal and l
    equal the point's. Sorted by point. Returns a dict of arrays.
    """
    nodes = np.asarray(nodes, dtype=float)
    if bp.edge_normal is None:
        raise ValueError("bond points lack edge normals: build them with find_bond_points")
    edges = np.asarray(bp.edges, dtype=np.int64)
    eb = np.asarray(bp.edge_bodies, dtype=np.int64)
    en = np.asarray(bp.edge_normal, dtype=float)
    d = nodes[edges[:, 1]] - nodes[edges[:, 0]]
    elen = np.hypot(d[:, 0], d[:, 1])
    point_of = {int(n): p for p, n in enumerate(np.asarray(bp.node))}
    # one row per (edge end): point, bodies, edge, far end
    rows = []
    for e in range(len(edges)):
        for c in (0, 1):
            rows.append((point_of[int(edges[e, c])], int(eb[e, 0]), int(eb[e, 1]), e, int(edges[e, 1 - c])))
    rows.sort()
    out = {k: [] for k in ("point", "body_minus", "body_plus", "normal", "length", "frame_p", "frame_q")}
    i = 0
    while i < len(rows):
        j = i
        while j < len(rows) and rows[j][:3] == rows[i][:3]:
            j += 1
        group = rows[i:j]
        p, b0, b1 = group[0][:3]
        es = [r[3] for r in group]
        far = [r[4] for r in group]
        length = 0.5 * elen[es].sum()
        nsum = (0.5 * elen[es, None] * en[es]).sum(axis=0)
        nn = np.hypot(*nsum)
        normal = nsum / nn if nn > 1e-12 * length else en[es[int(np.argmax(elen[es]))]]
        node = int(bp.node[p])
        fp, fq = (far[0], far[1]) if len(far) >= 2 else (node, far[0])
        for k, v in zip(out, (p, b0, b1, normal, length, fp, fq)):
            out[k].append(v)
        i = j
    return {
        "point": np.array(out["point"], dtype=np.int32),
        "body_minus": np.array(out["body_minus"], dtype=np.int32),
        "body_plus": np.array(out["body_plus"], dtype=np.int32),
        "normal": np.array(out["normal"], dtype=float).reshape(-1, 2),
        "length": np.array(out["length"], dtype=float),
        "frame_p": np.array(out["frame_p"], dtype=np.int32),
        "frame_q": np.array(out["frame_q"], dtype=np.int32),
    }
