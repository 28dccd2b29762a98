"""Phase-1 contacts resolved into bond lines before meshing (paper section 2.4).

Phase-1 blocks touch with mm-cm overlaps or small gaps. For every pair closer
than `gap_tol` the contact line is the target face, the edge whose normal is the
separating axis of least overlap (the layer is always the target). A contactor
face within `gap_tol` of it snaps onto it; the contactor is cut along it, so the
overlap sliver goes to the target and both meet on an exactly shared line. A common
face of at least `min_bond_length` is bonded; a shorter one (a corner touch) is cut
back to a gap `eps_sep` and left to the phase-2 contact law. Blocks only shrink,
except by the snaps. A clean-up then keeps every curve of the geometry at least
the feature size f long (face ends on a bonded line coincide or lie f apart,
shorter edges are removed, a corner held by two bonds loses a triangle where a
face end rests within f of it), since the explicit step follows the smallest
element. Full statement: docs/pile_and_mesh.md.
"""
from __future__ import annotations

import numpy as np

from . import pile as _pile
from ..plain_products import dot2, norm2


def _axes(p):
    """Unit outward edge normals of a counter-clockwise convex polygon."""
    e = np.roll(p, -1, axis=0) - p
    n = np.stack([e[:, 1], -e[:, 0]], axis=1)
    return n / np.linalg.norm(n, axis=1)[:, None]


def contact_line(a, b):
    """Target face of the contact between convex CCW polygons a and b.

    The separating axis of least overlap is an outward edge normal n of one of
    them, the target; the other is the contactor. Returns
    (target, n, c, depth): target 0 (a) or 1 (b), the target face line n.x = c
    (target in n.x <= c), and the overlap depth of the contactor past it
    (negative: a gap).
    """
    best = None
    for which, (t, k) in enumerate(((a, b), (b, a))):
        for n in _axes(t):
            c = (dot2(t, n)).max()
            depth = c - (dot2(k, n)).min()
            if best is None or depth < best[3]:
                best = (which, n, c, depth)
    return best


def _segment_on(p, n, c, tol):
    """Extent (s0, s1) along the line n.x = c of the corners of p lying on it, or None."""
    on = np.abs(dot2(p, n) - c) <= tol
    if on.sum() < 2:
        return None
    s = dot2(p[on], np.array([-n[1], n[0]]))
    return s.min(), s.max()


def _snap_face(p, n, c, gap_tol, own_lines=(), on_tol=1e-9):
    """A face of p lying within gap_tol of the line n.x = c (a near face-face contact) moves onto it.

    p lies in n.x <= c (the target beyond). Corners already on a bonded line of p
    stay unless the move is along that line, so earlier bonds stay exact.
    """
    d = c - dot2(p, n)  # > 0: a gap to the line; < 0: past it (the cut that follows puts it on)
    near = d <= gap_tol  # corners past the line are cut onto it anyway
    if near.sum() < 2:
        return p
    move = near & (d > on_tol)
    for k in np.flatnonzero(move):
        # a corner on a bonded line may only slide along it (the bond stays exact)
        if any(abs(dot2(p[k], m) - cm) <= on_tol and abs(d[k] * (dot2(n, m))) > on_tol
               for m, cm in own_lines):
            move[k] = False
    if move.any():
        p = p.copy()
        p[move] += d[move][:, None] * n[None, :]
    return p


def _resolve_pair(t, k, n, c, gap_tol, min_bond_length, eps_sep, on_tol, k_lines=()):
    """Contactor k against target face n.x = c: (new k, chord, bonded)."""
    # the contactor lies in n.x >= c: in _snap_face's terms the target is on the -n side
    k = _snap_face(k, -n, -c, gap_tol, k_lines, on_tol)
    # the overlap sliver goes to the target: cut the contactor along the target face
    k = _pile.clip_halfplane(k, -n, -c)
    sk, st = _segment_on(k, n, c, on_tol), _segment_on(t, n, c, on_tol)
    chord = 0.0 if sk is None or st is None else max(0.0, min(sk[1], st[1]) - max(sk[0], st[0]))
    if chord < min_bond_length:  # a corner touch: leave it to the phase-2 contact law
        k = _pile.clip_halfplane(k, -n, -(c + eps_sep))
        return k, chord, False
    return k, chord, True


def resolve_contacts(corners, layer_y, x_min, x_max, gap_tol=0.01, min_bond_length=0.05,
                     eps_sep=2e-3, min_feature=0.01, indenter_width=None, info=None, fuzzy=0.0):
    """Apply the contact rule (module docstring) to the block corners (n, k, 2).

    Returns (polys, contacts): the resolved blocks (list of CCW convex polygons,
    subsets of the inputs up to face snaps of at most gap_tol) and a list of
    (i, j, chord, bonded), j = -1 for the consolidated layer (with the indenter).
    min_feature: shortest block edge and shortest distance between two face ends
    on a bonded line (the shortest geometry curve). indenter_width: the indenter
    cuts at x = +-indenter_width/2 are face ends on the layer line too. info: a
    dict that receives counts of the clean-up.
    """
    info = {} if info is None else info
    polys = [np.array(_pile.ccw(p), float) for p in corners]
    n = len(polys)
    on_tol = 1e-9 * max(1.0, x_max - x_min)
    contacts = []
    lines = [[] for _ in range(n)]  # bonded contact lines (n, c) of each block
    # phase-1 side walls (not meshed): blocks are cut to the domain, never bonded there
    for i in range(n):
        polys[i] = _pile.clip_box(polys[i], x_min, x_max, -np.inf, np.inf)
    # the layer is always the target: its face is the keel top y = layer_y
    up = np.array([0.0, 1.0])
    for i in range(n):
        if polys[i][:, 1].max() <= layer_y - gap_tol:
            continue
        k = _snap_face(polys[i], up, layer_y, gap_tol, (), on_tol)
        k = _pile.clip_halfplane(k, up, layer_y)
        seg = _segment_on(k, up, layer_y, on_tol)
        chord = 0.0 if seg is None else seg[1] - seg[0]
        if chord < min_bond_length:
            k = _pile.clip_halfplane(k, up, layer_y - eps_sep)
        polys[i] = k
        contacts.append((i, -1, chord, chord >= min_bond_length))
        if chord >= min_bond_length:
            lines[i].append((up, layer_y))
    lo = np.array([p.min(axis=0) for p in polys])
    hi = np.array([p.max(axis=0) for p in polys])
    reach = gap_tol + on_tol
    near = np.argwhere(np.triu((lo[:, None, 0] <= hi[None, :, 0] + reach) &
                               (lo[None, :, 0] <= hi[:, None, 0] + reach) &
                               (lo[:, None, 1] <= hi[None, :, 1] + reach) &
                               (lo[None, :, 1] <= hi[:, None, 1] + reach), k=1))
    # pass 1 resolves every near pair; a face snap moves corners out by < gap_tol and
    # may push into a block resolved before, so pass 2 cuts what still overlaps
    # (cuts only shrink blocks: one such pass leaves no overlap)
    found = {}
    for pass_gap in (gap_tol, 0.0):
        for i, j in near:
            which, nrm, c, depth = contact_line(polys[i], polys[j])
            if depth < -gap_tol or (pass_gap == 0.0 and depth <= on_tol):
                continue
            ti, ki = (i, j) if which == 0 else (j, i)
            polys[ki], chord, bonded = _resolve_pair(polys[ti], polys[ki], nrm, c, pass_gap,
                                                     min_bond_length, eps_sep, on_tol, lines[ki])
            if bonded:
                lines[ti].append((nrm, c))
                lines[ki].append((nrm, c))
            found[(int(i), int(j))] = (chord, bonded, (ti, ki, nrm, c) if bonded else None)
    bonds = [v[2] for v in found.values() if v[1]]
    bonds += [(i, -1, up, layer_y) for i, j, _, bonded in contacts if bonded]
    xi = 0.5 * indenter_width if indenter_width else None
    cut_x = [x_min, x_max] if xi is None else [x_min, -xi, xi, x_max]
    plates = [(np.array([a, layer_y]), np.array([b, layer_y]), a in (-xi, xi) if xi else False,
               b in (-xi, xi) if xi else False, np.array([0.5 * (a + b), layer_y + 1.0]))
              for a, b in zip(cut_x[:-1], cut_x[1:])]
    polys = [_dedupe(p, on_tol) for p in polys]
    info["end_moves"] = _space_line_ends(polys, lines, bonds, plates, min_feature,
                                         min_bond_length, on_tol, eps_sep)
    for i in range(n):
        polys[i] = _collapse_short_edges(_dedupe(polys[i], on_tol), lines[i], min_feature, on_tol)
    info["chamfers"] = _chamfer_held_corners(polys, lines, bonds, min_feature, min_bond_length,
                                             on_tol, fuzzy,
                                             [np.array([x, layer_y]) for x in cut_x])
    # report the common face as it is in the final geometry (later cuts can shorten it)
    final = []
    for i, j, chord, bonded in contacts:  # the layer
        if bonded:
            seg = _segment_on(polys[i], up, layer_y, on_tol)
            chord = 0.0 if seg is None else seg[1] - seg[0]
        final.append((i, j, chord, bonded))
    for (i, j), (chord, bonded, line) in found.items():
        if bonded:
            ti, ki, nrm, c = line
            sk, st = _segment_on(polys[ki], nrm, c, on_tol), _segment_on(polys[ti], nrm, c, on_tol)
            chord = 0.0 if sk is None or st is None else \
                max(0.0, min(sk[1], st[1]) - max(sk[0], st[0]))
        final.append((i, j, chord, bonded))
    return polys, final


def _same_line(n1, c1, n2, c2, on_tol):
    """True if n1.x = c1 and n2.x = c2 are one line (either orientation)."""
    if abs(n1[0] * n2[1] - n1[1] * n2[0]) > 1e-9:
        return False
    return abs(c1 - c2) <= on_tol if dot2(n1, n2) > 0 else abs(c1 + c2) <= on_tol


def _line_groups(bonds, on_tol):
    """Bonded contacts (a, b, n, c) grouped by their line: [(n, c, [(a, b), ...])]."""
    groups, buckets = [], {}
    for a, b, n, c in bonds:
        if n[1] < -1e-12 or (abs(n[1]) <= 1e-12 and n[0] < 0):
            n, c = -n, -c  # one orientation per line
        key = int(np.floor(np.arctan2(n[1], n[0]) * 1e6))
        hit = None
        for k in (key - 1, key, key + 1):
            for g in buckets.get(k, ()):
                if _same_line(n, c, g[0], g[1], on_tol):
                    hit = g
                    break
            if hit is not None:
                break
        if hit is None:
            hit = (n, c, [])
            groups.append(hit)
            buckets.setdefault(key, []).append(hit)
        hit[2].append((a, b))
    return groups


def _on_other_line(v, own_lines, n, c, on_tol):
    """True if corner v lies on a bonded line of its block other than n.x = c."""
    return any(abs(dot2(v, m) - cm) <= on_tol for m, cm in own_lines
               if not _same_line(m, cm, n, c, on_tol))


def _clear_growth(polys, b, k, s_new, n, c, t, clearance, on_tol):
    """True if corner k of block b can slide along its line to s_new into empty space.

    The block gains the triangle (old corner, new corner, the corner's neighbour
    off the line); no other body (except across the line) may come within
    `clearance` of it.
    """
    p = polys[b]
    m = len(p)
    nb_k = [j for j in ((k - 1) % m, (k + 1) % m) if abs(dot2(p[j], n) - c) > on_tol]
    if len(nb_k) != 1:
        return False
    v_new = p[k] + (s_new - dot2(p[k], t)) * t
    grown = p.copy()
    grown[k] = v_new
    e = np.roll(grown, -1, axis=0) - grown
    if np.any(e[:, 0] * np.roll(e, -1, axis=0)[:, 1] - e[:, 1] * np.roll(e, -1, axis=0)[:, 0] < 0):
        return False  # the block would stop being convex
    tri = np.array([p[k], v_new, p[nb_k[0]]])
    if np.linalg.norm(np.roll(tri, -1, axis=0) - tri, axis=1).min() <= 10 * on_tol:
        return False  # the corner would land on its neighbour
    if _pile.polygon_area(tri) < 0:
        tri = tri[::-1]
    lo, hi = tri.min(axis=0) - clearance, tri.max(axis=0) + clearance
    side = np.sign(dot2(p.mean(axis=0), n) - c)
    for j, q in enumerate(polys):
        if j == b or np.any(q.max(axis=0) < lo) or np.any(q.min(axis=0) > hi):
            continue
        if np.all(side * (dot2(q, n) - c) <= on_tol):
            continue  # across the line: touches the gained triangle on the line at most
        if contact_line(tri, _dedupe(q, on_tol))[3] > -clearance:
            return False
    return True


def _space_line_ends(polys, lines, bonds, plates, feature, min_bond_length, on_tol, clearance):
    """Ends of faces on a bonded line are either one point or at least `feature` apart.

    Every face end on a bonded line splits the faces across it into separate
    curves, so two ends a little apart (two blocks resting on one face with a
    small gap between them, a face ending just short of its partner's end, a
    block end next to the indenter cut) leave a curve shorter than `feature` and
    tiny elements (the explicit time step follows the smallest element). The end
    moves along the line, so its block only shrinks: onto the other end when
    that belongs to the body across the line (the faces then end together),
    else away from it to a gap of `feature`. The smaller move wins. Corners on a
    second bonded line stay (bonds stay exact), and no bonded chord on the line
    drops below min(min_bond_length, its length before). Plates (layer,
    indenter) never move; no block end goes onto an indenter cut point, which
    would join indenter and layer through the block. Returns the number of moves.
    """
    moves = 0
    for n, c, pairs in _line_groups(bonds, on_tol):
        t = np.array([-n[1], n[0]])
        bodies = sorted({b for ab in pairs for b in ab})
        partners = {}
        for a, b in pairs:
            partners.setdefault(a, set()).add(b)
            partners.setdefault(b, set()).add(a)
        for _ in range(4 * len(bodies) + 4):
            seg, ends = {}, []
            for b in bodies:
                if b < 0:  # the layer: plates with fixed ends (cut: an indenter cut point)
                    lo_all, hi_all = np.inf, -np.inf
                    for pid, (p0, p1, cut0, cut1, centre) in enumerate(plates):
                        side = 1 if dot2(centre, n) > c else -1
                        (s0, c0), (s1, c1) = sorted(((dot2(p0, t), cut0), (dot2(p1, t), cut1)))
                        ends.append((s0, ("plate", pid), None, +1, side, c0))
                        ends.append((s1, ("plate", pid), None, -1, side, c1))
                        lo_all, hi_all = min(lo_all, s0), max(hi_all, s1)
                    seg[b] = (lo_all, hi_all)
                    continue
                p = polys[b]
                on = np.flatnonzero(np.abs(dot2(p, n) - c) <= on_tol)
                if len(on) < 2:
                    continue
                s = dot2(p[on], t)
                side = 1 if dot2(p.mean(axis=0), n) > c else -1
                k0, k1 = on[np.argmin(s)], on[np.argmax(s)]
                seg[b] = (s.min(), s.max())
                ends.append((s.min(), b, k0, +1, side, False))
                ends.append((s.max(), b, k1, -1, side, False))
            ends.sort(key=lambda e: e[0])
            fix = None
            for e1, e2 in zip(ends[:-1], ends[1:]):
                gap = e2[0] - e1[0]
                if not on_tol < gap < feature or e1[1] == e2[1]:
                    continue
                if not any(lo <= e1[0] + on_tol and hi >= e2[0] - on_tol for lo, hi in seg.values()):
                    continue  # no face spans the gap: it is no curve
                options = []
                for e, o in ((e1, e2), (e2, e1)):
                    b, k, inward = e[1], e[2], e[3]
                    if not isinstance(b, (int, np.integer)) or b < 0:
                        continue
                    if _on_other_line(polys[b][k], lines[b], n, c, on_tol):
                        continue
                    if o[4] != e[4] and not o[5]:  # onto the end across the line
                        options.append((abs(o[0] - e[0]), b, k, o[0]))
                    target = o[0] + inward * feature
                    if (target - e[0]) * inward > 0:
                        options.append((abs(target - e[0]), b, k, target))
                for _, b, k, s_new in sorted(options, key=lambda o: o[0]):
                    s_old = dot2(polys[b][k], t)
                    low_end = abs(s_old - seg[b][0]) <= on_tol
                    lo, hi = (s_new, seg[b][1]) if low_end else (seg[b][0], s_new)
                    shrinks = (s_new - s_old) * (1 if low_end else -1) > 0
                    ok = hi - lo > on_tol and (
                        shrinks or _clear_growth(polys, b, k, s_new, n, c, t, clearance, on_tol))
                    for q in partners.get(b, ()):
                        if q not in seg:
                            continue
                        old = min(seg[b][1], seg[q][1]) - max(seg[b][0], seg[q][0])
                        new = min(hi, seg[q][1]) - max(lo, seg[q][0])
                        ok &= new >= min(min_bond_length, old) - on_tol
                    if ok:
                        fix = (b, k, s_new)
                        break
                if fix is not None:
                    break
            if fix is None:
                break
            b, k, s_new = fix
            polys[b] = polys[b].copy()
            polys[b][k] += (s_new - dot2(polys[b][k], t)) * t
            polys[b] = _dedupe(polys[b], on_tol)
            moves += 1
    return moves


def _clear_point(polys, b, x, on_tol, clearance):
    """True if x is on no block but b nearer than `clearance`, except exactly on its boundary."""
    for j, q in enumerate(polys):
        if j == b or np.any(q.min(axis=0) > x + clearance) or np.any(q.max(axis=0) < x - clearance):
            continue
        e = np.roll(q, -1, axis=0) - q
        t = np.clip(np.einsum("ij,ij->i", x - q, e) / np.einsum("ij,ij->i", e, e), 0.0, 1.0)
        d = np.linalg.norm(q + t[:, None] * e - x, axis=1).min()
        if on_tol < d < clearance:
            return False
    return True


def _bond_chords(polys, bonds, b, on_tol):
    """{(a, q, line index): chord} of every bond of block b (q = -1: the layer)."""
    out = {}
    for m, (a, q, n, c) in enumerate(bonds):
        if b not in (a, q):
            continue
        sa = _segment_on(polys[a], n, c, on_tol)
        if q < 0:
            out[m] = 0.0 if sa is None else sa[1] - sa[0]
            continue
        sq = _segment_on(polys[q], n, c, on_tol)
        out[m] = 0.0 if sa is None or sq is None else \
            max(0.0, min(sa[1], sq[1]) - max(sa[0], sq[0]))
    return out


def _chamfer_held_corners(polys, lines, bonds, feature, min_bond_length, on_tol, near_tol,
                          fixed_ends=()):
    """Cut off a held corner that another block's face end sits next to.

    A corner C of block B on two of its bonded lines cannot slide (bonds stay
    exact). Where another block's corner E rests on one of those faces within
    `feature` of C (a junction held by two bonds), the face piece C-E is a short
    free curve. B loses the triangle C, E, P with P on the other face `feature`
    from C: the corner becomes E (both blocks' ends coincide there) and P, B
    stays convex and only shrinks. Done only if no bond of B drops below
    min(min_bond_length, its length before) and no other corner lies within
    `feature` of P on that face (fixed_ends: the plates' ends and indenter cut
    points count too). Returns the number of corners cut.
    """
    from scipy.spatial import cKDTree
    def corner_index():
        own = np.concatenate([np.full(len(p), b) for b, p in enumerate(polys)] +
                             [np.full(len(fixed_ends), -1)])
        pts = np.vstack(list(polys) + [np.reshape(fixed_ends, (-1, 2))])
        return own, pts, cKDTree(pts)

    owner, allpts, tree = corner_index()
    cuts = 0
    for b in range(len(polys)):
        if len(lines[b]) < 2:
            continue
        k = 0
        while k < len(polys[b]):
            p = polys[b]
            C = p[k]
            held = [(n, c) for n, c in lines[b] if abs(dot2(C, n) - c) <= on_tol]
            if len(held) < 2:
                k += 1
                continue
            done = False
            for nb_k, other_k in (((k + 1) % len(p), (k - 1) % len(p)),
                                  ((k - 1) % len(p), (k + 1) % len(p))):
                A, D = p[nb_k], p[other_k]  # A: along the face with E; D: along the other face
                la, ld = norm2(A - C), norm2(D - C)
                ua, ud = (A - C) / la, (D - C) / ld
                on_bonded = any(abs(dot2(A, n) - c) <= on_tol for n, c in held)
                if not on_bonded or ld < 2 * feature or la < 2 * feature:
                    continue
                best = None
                for v in tree.query_ball_point(C, feature):
                    if owner[v] == b or owner[v] < 0:
                        continue
                    E = allpts[v]
                    s = dot2((E - C), ua)
                    if on_tol < s < feature and abs(dot2((E - C), np.array([-ua[1], ua[0]]))) <= near_tol:
                        best = s if best is None else min(best, s)
                if best is None:
                    continue
                E = C + best * ua
                P = C + feature * ud
                # no other corner on the other face within feature of P (a new short curve)
                if any(owner[v] != b and abs(dot2((allpts[v] - C), np.array([-ud[1], ud[0]]))) <= near_tol
                       and on_tol < abs(dot2((allpts[v] - P), ud)) < feature - on_tol
                       for v in tree.query_ball_point(P, feature)):
                    continue
                # P is exactly on its partner's face or clear of every block by 2 fuzzy:
                # nearer, the fuzzy fragment would join faces that are not bonded
                if not _clear_point(polys, b, P, on_tol, 2.0 * near_tol):
                    continue
                q = p.copy()
                new = [E, P] if nb_k == (k + 1) % len(p) else [P, E]
                q = np.insert(np.delete(q, k, axis=0), k, np.array(new[::-1]), axis=0)
                before = _bond_chords(polys, bonds, b, on_tol)
                polys[b] = q
                after = _bond_chords(polys, bonds, b, on_tol)
                if all(after[m] >= min(min_bond_length, before[m]) - on_tol for m in before):
                    cuts += 1
                    owner, allpts, tree = corner_index()  # later cuts see this one
                    done = True
                    break
                polys[b] = p
            k += 1 if not done else 2
    return cuts


def _dedupe(p, tol):
    """Drop corners that coincide with the previous one (cuts through a corner repeat it)."""
    keep = np.linalg.norm(p - np.roll(p, 1, axis=0), axis=1) > tol
    return p[keep] if keep.sum() >= 3 else p


def _collapse_short_edges(p, own_lines, min_feature, on_tol):
    """Edges shorter than min_feature disappear (the block only shrinks).

    A corner on a bonded line is kept and the other end of the short edge is
    dropped; with no bonded corner the edge shrinks to its midpoint; an edge
    between two bonded lines stays, so bonded faces stay exact.
    """
    def bonded(v):
        return any(abs(dot2(v, n) - c) <= on_tol for n, c in own_lines)

    while len(p) > 3:
        e = np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1)
        changed = False
        for k in np.argsort(e):
            if e[k] >= min_feature:
                break
            ka, kb = k, (k + 1) % len(p)
            ba, bb = bonded(p[ka]), bonded(p[kb])
            if ba and bb:
                continue
            if ba or bb:
                p = np.delete(p, kb if ba else ka, axis=0)
            else:
                mid = 0.5 * (p[ka] + p[kb])
                p = np.delete(p, kb, axis=0)
                p[ka if ka < kb else ka - 1] = mid
            changed = True
            break
        if not changed:
            break
    return p


def max_overlap_depth(polys):
    """Largest overlap depth between any two convex polygons (<= 0: none overlap)."""
    worst = -np.inf
    lo = np.array([p.min(axis=0) for p in polys])
    hi = np.array([p.max(axis=0) for p in polys])
    for i in range(len(polys)):
        for j in range(i + 1, len(polys)):
            if np.all(lo[i] <= hi[j]) and np.all(lo[j] <= hi[i]):
                worst = max(worst, contact_line(polys[i], polys[j])[3])
    return worst


