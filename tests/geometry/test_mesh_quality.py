"""Element quality of the pile mesh relative to the element size h (the explicit step follows
the smallest altitude) with the bond rule of docs/pile_and_mesh.md kept."""
import os
from collections import defaultdict

import numpy as np
import pytest

from icerubble.files import pile_file
from icerubble.geometry import contact_resolution, meshing, pile
from tests.paths import DATA

YB = pile.layer_bottom_y()
W = 8.0                     # layer [-4, -2] | indenter [-2, 2] | layer [2, 4]
H = 0.1                     # element size of the constructed cases
NB_OF = {}


def box(x0, x1, y0, y1):
    return np.array([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], float)


def mesh_of(blocks, **kw):
    p = dict(corners=np.array(blocks, float),
             meta=dict(domain_width=W, layer_thickness=1.0, layer_bottom_y=YB))
    return meshing.build_mesh(p, element_size=H, **kw)


def altitudes(m):
    p = m["nodes"][m["triangles"]]
    e = np.linalg.norm(p - np.roll(p, -1, axis=1), axis=2)
    a = 0.5 * np.abs((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) -
                     (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1]))
    return 2.0 * a / e.max(axis=1)


def bonds(m):
    X, out = m["nodes"], defaultdict(float)
    for (a, b), (i, j) in zip(m["bond_edges"], m["bond_edge_bodies"]):
        out[(int(i), int(j))] += float(np.linalg.norm(X[a] - X[b]))
    return dict(out)


def face_end(poly, y, right=True):
    """x of the right (left) end of the polygon's face on the line y."""
    on = np.abs(poly[:, 1] - y) < 1e-9
    return poly[on, 0].max() if right else poly[on, 0].min()


def shared_nodes(m, i, j):
    T, body = m["triangles"], m["body"]
    return np.intersect1d(np.unique(T[body == i]), np.unique(T[body == j]))


# The bound: with no geometry curve shorter than feature = 0.4 h, gmsh's
# Frontal-Delaunay triangles next to the shortest curve are near-equilateral with
# edges >= ~0.3 h (altitude ~0.26 h or more); 0.25 h is the target of the mesher.
MIN_ALT = 0.25 * H


def test_two_blocks_on_one_face_12mm_apart():
    # P and Q hang under A, 12 mm apart (> gap_tol: no contact between them). A's
    # face would be split into a 12 mm curve between their ends: one end moves
    # away to a gap of feature = 0.4 h (its block shrinks by 23 mm).
    A = box(-1.5, 1.5, YB - 0.3, YB)
    P = box(-1.0, -0.006, YB - 0.6, YB - 0.3)
    Q = box(0.006, 1.0, YB - 0.6, YB - 0.3)
    m = mesh_of([A, P, Q])
    ind = 3 + 1
    b = bonds(m)
    assert set(b) == {(0, ind), (0, 1), (0, 2)}
    assert b[(0, ind)] == pytest.approx(3.0, abs=1e-9)
    feature = 0.4 * H
    # the blocks only lose the move: each bond is its face, shortened by at most feature
    assert 0.994 - feature <= b[(0, 1)] <= 0.994 + 1e-9
    assert 0.994 - feature <= b[(0, 2)] <= 0.994 + 1e-9
    rb = m["resolved_blocks"]
    gap = face_end(rb[2], YB - 0.3, right=False) - face_end(rb[1], YB - 0.3)
    assert gap == pytest.approx(feature, abs=1e-9)
    assert len(shared_nodes(m, 1, 2)) == 0
    assert altitudes(m).min() >= MIN_ALT


@pytest.mark.parametrize("end", [1.501, 1.499])
def test_face_end_1mm_from_the_partner_end(end):
    # B under A, its face ending 1 mm past / short of A's corner: the two ends
    # become one point (the 1 mm move), the bond is the common face up to 1 mm.
    A = box(-1.5, 1.5, YB - 0.3, YB)
    B = box(-1.0, end, YB - 0.6, YB - 0.3)
    m = mesh_of([A, B])
    b = bonds(m)
    assert b[(0, 1)] == pytest.approx(2.5, abs=1.001e-3)
    assert m["contacts"]["bonded"].all()
    rb = m["resolved_blocks"]
    assert face_end(rb[0], YB - 0.3) == pytest.approx(face_end(rb[1], YB - 0.3), abs=1e-9)
    assert altitudes(m).min() >= MIN_ALT


def test_two_blocks_1mm_apart_on_the_layer_bond_and_share_their_corner():
    # a face-face contact across a 1 mm gap (< gap_tol) is bonded; the corners of
    # A and C on the layer line coincide, so no 1 mm curve is left on the indenter
    A = box(-1.5, -0.0005, YB - 0.3, YB)
    C = box(0.0005, 1.5, YB - 0.3, YB)
    m = mesh_of([A, C])
    ind = 2 + 1
    b = bonds(m)
    assert set(b) == {(0, 1), (0, ind), (1, ind)}
    assert b[(0, 1)] == pytest.approx(0.3, abs=1e-9)
    assert b[(0, ind)] + b[(1, ind)] == pytest.approx(3.0, abs=1e-9)
    assert altitudes(m).min() >= MIN_ALT


@pytest.mark.parametrize("x_end", [-2.01, -1.99])
def test_block_end_10mm_from_the_indenter_cut(x_end):
    # D on the layer, its end 10 mm before / past the indenter cut x = -2. Its end
    # never goes onto the cut (that would join layer and indenter through D's
    # node); it moves to at least feature from it.
    D = box(-3.0, x_end, YB - 0.3, YB)
    m = mesh_of([D])
    lay_l, ind = 1, 2   # the right part of the layer, 3, is not touched
    x1 = face_end(m["resolved_blocks"][0], YB)
    assert abs(x1 + 2.0) >= 0.4 * H - 1e-9
    b = bonds(m)
    assert b[(0, lay_l)] == pytest.approx(min(x1, -2.0) + 3.0, abs=1e-9)
    assert b.get((0, ind), 0.0) == pytest.approx(max(0.0, x1 + 2.0), abs=1e-9)
    # layer and indenter are joined only where D bridges the cut
    assert len(shared_nodes(m, lay_l, ind)) == (1 if x1 > -2.0 else 0)
    assert altitudes(m).min() >= MIN_ALT


def test_held_corner_next_to_a_held_face_end_is_cut_off():
    # B's corner C = (0, YB-0.3) lies on two bonded lines (D below, R right); D's
    # end E rests on B's face 20 mm from C and D is bonded sideways to Q, so
    # neither end may slide and the free 20 mm piece C-E would force 20 mm
    # elements. B loses the triangle C, E, P with P feature = 0.4 h up its right
    # face: its corner becomes E, so the short curve is gone.
    B = box(-1.5, 0.0, YB - 0.3, YB)
    R = box(0.0, 1.5, YB - 0.3, YB)
    xq = -0.02 - 0.035 * 0.035 / 0.3  # Q's top corner on the line of D's right face
    D = np.array([(-1.0, YB - 0.6), (-0.055, YB - 0.6), (-0.02, YB - 0.3), (-1.0, YB - 0.3)])
    Q = np.array([(-0.055, YB - 0.6), (1.0, YB - 0.6), (1.0, YB - 0.335), (xq, YB - 0.335)])
    m = mesh_of([B, R, D, Q])
    m0 = mesh_of([B, R, D, Q], feature_fraction=0.0)  # no clean-up at the element size
    feature = 0.4 * H
    c, c0 = m["contacts"], m0["contacts"]
    np.testing.assert_array_equal(c["bodies"], c0["bodies"])
    np.testing.assert_array_equal(c["bonded"], c0["bonded"])
    assert c["bonded"].all()
    assert m["resolve_info"]["chamfers"] == 1
    b = bonds(m)
    # the B-R bond loses exactly the cut piece, the others keep their length
    assert b[(0, 1)] == pytest.approx(0.3 - feature, abs=1e-9)
    assert b[(0, 2)] == pytest.approx(0.98, abs=1e-9)
    b0 = bonds(m0)
    assert b[(2, 3)] == pytest.approx(b0[(2, 3)], abs=feature)
    rb = m["resolved_blocks"]
    assert face_end(rb[0], YB - 0.3) == pytest.approx(-0.02, abs=1e-9)
    # B only shrinks, by the triangle 20 mm x feature
    assert pile.polygon_area(rb[0]) == pytest.approx(0.45 - 0.5 * 0.02 * feature, abs=1e-12)
    assert contact_resolution.max_overlap_depth(rb) <= 1e-9
    assert m["resolve_info"]["n_short_curves"] == 0
    assert m0["resolve_info"]["shortest_curve"] == pytest.approx(0.02, abs=1e-9)
    assert altitudes(m).min() >= MIN_ALT


@pytest.fixture(scope="module")
def demo():
    p = pile_file.read_pile(os.path.join(DATA, "demo_pile.h5"))
    h = 0.15
    # feature_fraction = 0: the clean-up at min_feature only (no element-size rule)
    return (h, meshing.build_mesh(p, element_size=h, min_feature=0.2 * h),
            meshing.build_mesh(p, element_size=h, min_feature=0.2 * h, feature_fraction=0.0))


def test_demo_pile_bonds_unchanged(demo):
    h, m, m0 = demo
    c, c0 = m["contacts"], m0["contacts"]
    np.testing.assert_array_equal(c["bodies"], c0["bodies"])
    # the same contacts are bonded; every bonded one keeps a bond of at least
    # min_bond_length in the mesh, every unbonded one has none
    np.testing.assert_array_equal(c["bonded"], c0["bonded"])
    mbl = m["settings"]["min_bond_length"]
    assert np.all(c["bond_length"][c["bonded"]] >= mbl - 1e-9)
    assert np.all(c["bond_length"][~c["bonded"]] == 0.0)
    assert contact_resolution.max_overlap_depth(m["resolved_blocks"]) <= 1e-9


def test_demo_pile_quality_report_is_true(demo):
    h, m, m0 = demo
    q = m["quality"]
    alt = altitudes(m)
    assert q["min_altitude"] == pytest.approx(alt.min(), rel=1e-12)
    assert q["feature"] == pytest.approx(0.4 * h)
    # small elements only where a curve shorter than the feature is left (both
    # its ends held by other bonds): the file says how many
    if alt.min() < 0.25 * h:
        assert m["resolve_info"]["n_short_curves"] > 0
    assert (alt < 0.25 * h).sum() < (altitudes(m0) < 0.25 * h).sum()
