"""Mesh of a pile (paper section 2.4): continuous over bonded faces, freeze-bond edges, porosity."""
import os
import subprocess
from collections import defaultdict

import numpy as np
import pytest

from icerubble.files import mesh_file
from icerubble.geometry import contact_resolution, meshing, pile

YB = pile.layer_bottom_y()          # keel top = layer bottom
W = 8.0                             # domain: layer [-4, -2] | indenter [-2, 2] | layer [2, 4]


def box(x0, x1, y0, y1):
    return np.array([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], float)


def pile_dict(corners):
    return dict(corners=np.array(corners, float),
                meta=dict(domain_width=W, layer_thickness=1.0, layer_bottom_y=YB))


def tilted_corner_touch(x_tip, y_tip, depth):
    """A block at 45 deg whose top corner pokes `depth` up past y_tip at x_tip."""
    r = pile.rectangle((0.0, 0.0), 0.8, 0.3, np.pi / 4)
    top = r[np.argmax(r[:, 1])]
    return r + np.array([x_tip, y_tip + depth]) - top


# A: on the layer, across the left cut of the indenter.       -> bonded to layer and indenter
# B: under A, overlapping it by 2 mm.                           -> bonded to A over 1.0 m
# C: 4 mm below the indenter (a gap < gap_tol).                 -> snapped, bonded over 1.4 m
# D: a corner poking 3 mm into C's bottom face.                 -> a corner touch, not bonded
# E: 2 cm below the layer (a gap > gap_tol).                    -> no contact
CASE = [box(-3.0, -1.0, YB - 0.3, YB),
        box(-2.5, -1.5, YB - 0.598, YB - 0.298),
        box(0.5, 1.9, YB - 0.254, YB - 0.004),
        tilted_corner_touch(1.2, YB - 0.254, 0.003),
        box(2.5, 3.5, YB - 0.32, YB - 0.02)]
NB = len(CASE)
LAYER_L, INDENTER, LAYER_R = NB, NB + 1, NB + 2


@pytest.fixture(scope="module")
def case_mesh():
    return meshing.build_mesh(pile_dict(CASE), element_size=0.1)


def bond_lengths(m):
    X, E, EB = m["nodes"], m["bond_edges"], m["bond_edge_bodies"]
    out = defaultdict(float)
    for (a, b), (i, j) in zip(E, EB):
        out[(int(i), int(j))] += float(np.linalg.norm(X[a] - X[b]))
    return dict(out)


def test_bonds_where_blocks_touch_by_the_tolerance_rule(case_mesh):
    got = bond_lengths(case_mesh)
    expected = {(0, LAYER_L): 1.0, (0, INDENTER): 1.0, (0, 1): 1.0, (2, INDENTER): 1.4}
    assert set(got) == set(expected)
    for k, v in expected.items():
        # the bond edges cover exactly the common face: only round-off differs
        assert got[k] == pytest.approx(v, abs=1e-9), k
    c = case_mesh["contacts"]
    contacts = {frozenset((int(i), int(j))): (ch, b) for (i, j), ch, b in
                zip(c["bodies"], c["chord"], c["bonded"])}
    # D's corner cut along C's face is 2 x 3 mm long: a corner touch, not bonded
    chord, bonded = contacts[frozenset((2, 3))]
    assert chord == pytest.approx(0.006, abs=1e-9) and not bonded
    # all faces here are parallel or far apart: the mesh bonds exactly the rule's chords
    np.testing.assert_allclose(c["bond_length"], np.where(c["bonded"], c["chord"], 0.0), atol=1e-9)
    assert not any(4 in pair for pair in contacts)


def test_overlap_sliver_goes_to_the_target_and_gaps_snap(case_mesh):
    rb = case_mesh["resolved_blocks"]
    area = [abs(pile.polygon_area(p)) for p in rb]
    assert area[0] == pytest.approx(2.0 * 0.3, rel=1e-12)       # target A keeps its shape
    assert area[1] == pytest.approx(1.0 * 0.298, rel=1e-12)     # B loses the 2 mm overlap
    assert area[2] == pytest.approx(1.4 * 0.254, rel=1e-12)     # C's top face snapped 4 mm up
    assert contact_resolution.max_overlap_depth(rb) <= 1e-12
    # D no longer touches C: it was pulled back by eps_sep
    eps = case_mesh["settings"]["eps_sep"]
    assert rb[3][:, 1].max() == pytest.approx(YB - 0.254 - eps, abs=1e-12)


def test_every_bond_edge_joins_exactly_two_bodies(case_mesh):
    T, body = case_mesh["triangles"], case_mesh["body"]
    owners = defaultdict(list)
    for t, tri in enumerate(T):
        for a, b in ((tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])):
            owners[(min(a, b), max(a, b))].append(t)
    assert max(len(v) for v in owners.values()) == 2
    between = {e for e, ts in owners.items() if len(ts) == 2 and body[ts[0]] != body[ts[1]]}
    tagged = {tuple(int(x) for x in sorted(e)) for e in case_mesh["bond_edges"]}
    assert tagged == between
    for e, (i, j) in zip(case_mesh["bond_edges"], case_mesh["bond_edge_bodies"]):
        ts = owners[(min(e), max(e))]
        assert sorted(body[ts]) == [i, j] and i != j


def test_triangles_ccw_and_not_degenerate(case_mesh):
    X, T = case_mesh["nodes"], case_mesh["triangles"]
    p = X[T]
    area = 0.5 * ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) -
                  (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1]))
    assert area.min() > 0
    q = case_mesh["quality"]
    # every geometric corner of this case is >= 45 deg; a min element angle under
    # 15 deg would mean a sliver (CST stiffness and time step degrade)
    assert q["min_angle_deg"] >= 15.0
    assert q["min_area"] == pytest.approx(area.min(), rel=1e-12)
    assert q["max_edge"] <= 0.1 * 1.5  # gmsh keeps edges near the element size


def test_body_areas_equal_the_resolved_geometry(case_mesh):
    X, T, body = case_mesh["nodes"], case_mesh["triangles"], case_mesh["body"]
    p = X[T]
    area = 0.5 * np.abs((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) -
                        (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1]))
    per_body = np.bincount(body, weights=area, minlength=NB + 3)
    want = [abs(pile.polygon_area(q)) for q in case_mesh["resolved_blocks"]] + [2.0, 4.0, 2.0]
    np.testing.assert_allclose(per_body, want, rtol=1e-10)
    assert list(case_mesh["body_kind"]) == [0] * NB + [1, 2, 1]


def test_node_sets_and_indenter_cut(case_mesh):
    X, T, body = case_mesh["nodes"], case_mesh["triangles"], case_mesh["body"]
    y_top = YB + 1.0
    lt, it = case_mesh["layer_top"], case_mesh["indenter_top"]
    assert np.allclose(X[lt, 1], y_top) and np.allclose(X[it, 1], y_top)
    assert np.isclose(X[lt, 0].min(), -4.0) and np.isclose(X[lt, 0].max(), 4.0)
    assert np.all(np.abs(X[lt, 0]) >= 2.0 - 1e-12) and np.all(np.abs(X[it, 0]) <= 2.0 + 1e-12)
    # layer and indenter share only the bridging corner where block A crosses the cut
    lay = np.unique(T[(body == LAYER_L) | (body == LAYER_R)])
    ind = np.unique(T[body == INDENTER])
    shared = np.intersect1d(lay, ind)
    assert len(shared) == 1 and np.allclose(X[shared[0]], (-2.0, YB))
    assert shared[0] in T[body == 0]


def test_porosity_of_known_rectangles():
    # two exactly touching blocks: A (2 x 0.3 m) on the layer, B (1 x 0.5 m) under
    # it, reaching 0.2 m below the region bottom; region 8 m x 0.6 m below the layer
    A = box(-3.0, -1.0, YB - 0.3, YB)
    B = box(-2.5, -1.5, YB - 0.8, YB - 0.3)
    bounds = (-4.0, 4.0, YB - 0.6, YB)
    eta = 1.0 - (0.6 + 0.3) / (8.0 * 0.6)
    assert pile.porosity([A, B], bounds) == pytest.approx(eta, abs=1e-12)
    m = meshing.build_mesh(pile_dict([A, B]), element_size=0.1)
    ice = m["body_kind"][m["body"]] == 0
    assert meshing.porosity_of_mesh(m["nodes"], m["triangles"], ice, bounds) == \
        pytest.approx(eta, abs=1e-12)
    # the file's porosity uses the mean column depth: 1.0 m of 8 m has 0.8 m, 1.0 m
    # has 0.3 m (A alone), the rest none -> keel bottom h = (0.8 + 0.3) / 8 m below;
    # inside it only A's 2 m x h: eta = 1 - 2 h / (8 h) = 0.75
    h = 1.1 / 8.0
    assert m["keel_bounds"][2] == pytest.approx(YB - h, abs=1e-12)
    assert m["porosity"] == pytest.approx(0.75, abs=1e-12)


def test_mesh_file_round_trip(tmp_path, case_mesh):
    path = str(tmp_path / "mesh.h5")
    mesh_file.write_mesh(path, case_mesh, source="case")
    back = mesh_file.read_mesh(path)
    for k in ("nodes", "triangles", "body", "body_kind", "bond_edges", "bond_edge_bodies",
              "layer_top", "indenter_top"):
        np.testing.assert_array_equal(back[k], case_mesh[k])
    assert back["attrs"]["porosity"] == case_mesh["porosity"]
    assert back["quality"]["min_angle_deg"] == case_mesh["quality"]["min_angle_deg"]
    assert not os.path.exists(path + ".part")


@pytest.mark.parametrize("kw,word", [(dict(element_size=-0.1), "element_size"),
                                     (dict(element_size=0.0), "element_size"),
                                     (dict(min_bond_length=0.0), "min_bond_length"),
                                     (dict(gap_tol=-0.01), "gap_tol"),
                                     (dict(indenter_width=9.0), "indenter_width")])
def test_invalid_parameters_raise(kw, word):
    with pytest.raises(ValueError, match=word):
        meshing.build_mesh(pile_dict(CASE), **kw)


def test_a_file_that_is_not_a_pile_stops_before_work(tmp_path):
    bad = tmp_path / "mesh_me.txt"
    bad.write_text("hello")
    out = tmp_path / "out.h5"
    with pytest.raises(ValueError, match="not an HDF5"):
        meshing.mesh_pile_file(str(bad), str(out))
    assert not out.exists()
    proc = subprocess.run(["icerubble", "mesh", str(bad), str(out), "--element-size", "0.1"],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode != 0 and "not an HDF5" in proc.stderr
    assert not out.exists()


def test_a_narrower_domain_meshes_the_central_part_of_the_pile():
    """domain_width below the pile's cuts its blocks at +-W/2 as phase 1's walls
    do; a piece thinner than one element is dropped, whole blocks outside too."""
    A = box(-3.0, -1.0, YB - 0.3, YB)            # cut at x = -2.5: keeps 1.5 m
    B = box(-2.55, -1.5, YB - 0.6, YB - 0.3)     # cut at -2.5: keeps 1.0 m, loses 5 cm
    C = box(-2.5 - 0.3 + 0.04, -2.46, YB - 0.9, YB - 0.6)  # 4 cm inside after the cut: dropped
    D = box(2.6, 3.5, YB - 0.3, YB)              # wholly outside: dropped
    full = meshing.build_mesh(pile_dict([A, B, C, D]), element_size=0.1)
    m = meshing.build_mesh(pile_dict([A, B, C, D]), element_size=0.1, domain_width=5.0)
    np.testing.assert_array_equal(m["pile_block"], [0, 1])
    assert m["settings"]["domain_width"] == 5.0 and m["pile_domain_width"] == W
    assert m["nodes"][:, 0].min() == pytest.approx(-2.5) and m["nodes"][:, 0].max() == pytest.approx(2.5)
    area = np.abs(meshing._signed_areas(m["nodes"], m["triangles"]))
    blocks = np.bincount(m["body"], weights=area)[:2]
    np.testing.assert_allclose(blocks, [1.5 * 0.3, 1.0 * 0.3], rtol=1e-9)
    # A and B still bond to each other and to the layer as in the full mesh
    assert {k for k in bond_lengths(m) if k[0] < 2 and k[1] < 2} == {(0, 1)}
    assert bond_lengths(m)[(0, 1)] == pytest.approx(1.0, rel=1e-9)
    assert len(full["pile_block"]) == 4 and "pile_domain_width" in full
    # the faces the crop cut are marked for the scene to hold; a whole pile has none
    cut = m["cut_sides"]
    assert len(cut) > 0 and full["cut_sides"].size == 0
    np.testing.assert_allclose(m["nodes"][cut, 0], -2.5, atol=1e-9)
    faces = np.isin(m["triangles"], cut).any(axis=1)
    blocks_at_cut = {int(b) for b in np.unique(m["body"][faces]) if m["body_kind"][b] == mesh_file.KIND_BLOCK}
    assert blocks_at_cut == {0, 1}   # A and B, the pieces the crop cut (their top corner is the layer's too)
    # every block node at x = -2.5 is in the set
    on_face = np.unique(m["triangles"][m["body"] < 2])
    on_face = on_face[np.abs(m["nodes"][on_face, 0] + 2.5) < 1e-9]
    np.testing.assert_array_equal(np.sort(cut), on_face)
    with pytest.raises(ValueError, match="domain_width"):
        meshing.build_mesh(pile_dict([A]), element_size=0.1, domain_width=9.0)


def test_a_cut_piece_without_a_bond_is_dropped_with_the_crop():
    """A piece the crop leaves with no bonded contact lost what held it: dropped.
    A whole block without bonds (held by friction) is the pile's and stays."""
    A = box(-3.0, -1.0, YB - 0.3, YB)                    # cut at -2.5, bonded to the layer
    F = box(-2.9, -2.3, YB - 0.9, YB - 0.6)              # cut at -2.5, 0.2 m left, touching nothing
    G = box(0.5, 1.5, YB - 0.9, YB - 0.6)                # whole, touching nothing: stays
    m = meshing.build_mesh(pile_dict([A, F, G]), element_size=0.1, domain_width=5.0)
    np.testing.assert_array_equal(m["pile_block"], [0, 2])
