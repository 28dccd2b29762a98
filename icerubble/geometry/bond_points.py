"""Freeze-bond points found from a mesh (docs/model.md §3.3, paper Fig. 2-3).

The mesh is continuous over touching block surfaces, so a freeze bond edge is
an element edge shared by triangles of two different bodies, and its nodes are
bond points. For each bond point this module gives what the splitting needs:
the bond normal n, the tributary crack length l (half of each bond edge that
meets the node, so the l of all bond points add up to the total bond length),
the bodies it joins, and strength and fracture energy from its depth.

Rules for the special nodes (documented in docs/freeze_bonds.md):
- a bond edge that ends on a free surface simply contributes half its length
  to its end node; the node is an ordinary two-body bond point;
- a node where three or more bodies meet is a *junction*: it is one bond point
  whose pairs are the body pairs that share a bond edge there; each pair has
  its own normal and length, and the point splits into one node per body.
"""
from dataclasses import dataclass

import numpy as np

from ..cohesive_law import strength_at_depth


@dataclass
class BondPoints:
    node: np.ndarray        # (P,) mesh node id
    position: np.ndarray    # (P,2) m
    normal: np.ndarray      # (P,2) unit bond normal (mean of the bond edge normals, body_a -> body_b)
    length: np.ndarray      # (P,) m, tributary crack length l
    bodies: np.ndarray      # (P,2) the two bodies joined; for a junction the pair with the longest edge
    n_bodies: np.ndarray    # (P,) number of bodies meeting at the node (>= 2; > 2 is a junction)
    depth: np.ndarray       # (P,) m below the keel top
    sigma_cr: np.ndarray    # (P,) Pa
    tau_cr: np.ndarray      # (P,) Pa
    G: np.ndarray           # (P,) J/m^2
    edges: np.ndarray       # (E,2) bond edges (node ids), first node < second
    edge_bodies: np.ndarray  # (E,2) bodies on either side of each bond edge, lower id first
    edge_normal: np.ndarray = None  # (E,2) unit normal of each bond edge, lower-id body -> higher

    def __len__(self):
        return len(self.node)


def bond_edges(triangles, body, exclude_pairs=()):
    """Edges shared by triangles of two different bodies.

    Returns (edges (E,2), edge_bodies (E,2), edge_normals (E,2)); the normal is
    the outward normal of the lower-id body's triangle. Pairs of bodies listed
    in exclude_pairs (e.g. indenter and consolidated layer, which are cut, not
    frozen) are left out.
    """
    tri = np.asarray(triangles, dtype=np.int64)
    body = np.asarray(body, dtype=np.int64)
    m = len(tri)
    # directed edges i->j of each CCW triangle
    a = tri.reshape(-1)
    b = np.roll(tri, -1, axis=1).reshape(-1)
    owner = np.repeat(np.arange(m), 3)
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    key = lo * (int(a.max()) + 1) + hi
    order = np.argsort(key, kind="stable")
    k = key[order]
    dup = k[1:] == k[:-1]
    if np.any(dup[1:] & dup[:-1]):
        raise ValueError("an element edge is shared by more than two triangles")
    same = np.nonzero(dup)[0]
    e1, e2 = order[same], order[same + 1]
    b1, b2 = body[owner[e1]], body[owner[e2]]
    diff = b1 != b2
    e1, e2, b1, b2 = e1[diff], e2[diff], b1[diff], b2[diff]
    # orient each edge from the lower-id body's side
    swap = b1 > b2
    first = np.where(swap, e2, e1)
    bodies = np.column_stack([np.minimum(b1, b2), np.maximum(b1, b2)])
    excl = {tuple(sorted(p)) for p in exclude_pairs}
    if excl:
        keep = np.array([tuple(p) not in excl for p in bodies.tolist()], dtype=bool)
        first, bodies = first[keep], bodies[keep]
    src, dst = a[first], b[first]
    edges = np.column_stack([np.minimum(src, dst), np.maximum(src, dst)])
    return edges, bodies, (src, dst)


def find_bond_points(nodes, triangles, body, *, keel_top_y, keel_depth, sigma_cr, tau_cr, G,
                     bottom_fraction=0.1, exclude_pairs=()):
    """All bond points of a mesh with their normal, length, bodies and strengths."""
    nodes = np.asarray(nodes, dtype=float)
    body = np.asarray(body, dtype=np.int64)
    edges, ebodies, (src, dst) = bond_edges(triangles, body, exclude_pairs)
    d = nodes[dst] - nodes[src]
    elen = np.hypot(d[:, 0], d[:, 1])
    if np.any(elen <= 0):
        raise ValueError("mesh has a zero-length bond edge (coincident nodes)")
    # outward normal of the lower-id body's CCW triangle: edge direction rotated -90 deg
    en = np.column_stack([d[:, 1], -d[:, 0]]) / elen[:, None]

    ends = edges.reshape(-1)
    pnode, inv = np.unique(ends, return_inverse=True)
    inv = inv.reshape(-1, 2)
    P = len(pnode)
    length = np.zeros(P)
    nsum = np.zeros((P, 2))
    for c in (0, 1):
        np.add.at(length, inv[:, c], 0.5 * elen)
        np.add.at(nsum, inv[:, c], 0.5 * elen[:, None] * en)
    # bodies meeting at each node (over all triangles, not only bond edges)
    tri = np.asarray(triangles, dtype=np.int64)
    nb_pairs = np.unique(np.column_stack([tri.reshape(-1), np.repeat(body, 3)]), axis=0)
    count = np.bincount(nb_pairs[:, 0], minlength=len(nodes))
    n_bodies = count[pnode]
    # the pair named for each bond point: the pair with the longest bond edge there
    bodies = np.zeros((P, 2), dtype=np.int64)
    best = np.full(P, -1.0)
    for c in (0, 1):
        for e in range(len(edges)):
            p = inv[e, c]
            if elen[e] > best[p]:
                best[p] = elen[e]
                bodies[p] = ebodies[e]
    nrm = np.hypot(nsum[:, 0], nsum[:, 1])
    # a node whose bond edges fold back on themselves has no mean direction;
    # fall back to its longest edge's normal
    normal = np.where(nrm[:, None] > 1e-12 * length[:, None], nsum / np.maximum(nrm, 1e-300)[:, None], 0.0)
    if np.any(nrm <= 1e-12 * length):
        for p in np.nonzero(nrm <= 1e-12 * length)[0]:
            e = np.nonzero((inv[:, 0] == p) | (inv[:, 1] == p))[0]
            normal[p] = en[e[np.argmax(elen[e])]]
    pos = nodes[pnode]
    depth = np.clip(keel_top_y - pos[:, 1], 0.0, keel_depth)
    return BondPoints(
        node=pnode, position=pos, normal=normal, length=length, bodies=bodies, n_bodies=n_bodies,
        depth=depth, **strength_at_depth(depth, keel_depth, sigma_cr, tau_cr, G, bottom_fraction),
        edges=edges, edge_bodies=ebodies, edge_normal=en)
