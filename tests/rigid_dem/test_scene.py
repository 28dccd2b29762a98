"""The rigid-block view of a FEM-DEM mesh (rigid_dem/scene.py): the same
bodies, the same bond points and strengths."""
import numpy as np
import pytest

from icerubble.files.mesh_file import read_mesh
from icerubble.parameters import validate
from icerubble.geometry import meshing
from icerubble.rigid_dem.scene import KIND_BLOCK, body_outline, rigid_scene
from icerubble.rigid_dem.water import polygon_frame
from icerubble.run.scene import Scene
from tests.paths import ROOT


@pytest.fixture(scope="module")
def demo_mesh(tmp_path_factory):
    path = tmp_path_factory.mktemp("mesh") / "demo_mesh.h5"
    meshing.mesh_pile_file(f"{ROOT}/tests/data/demo_pile.h5", str(path), element_size=0.15, min_feature=0.03)
    return read_mesh(str(path))


def test_bodies_cover_the_meshed_area(demo_mesh):
    s = rigid_scene(demo_mesh, dict(mu=0.3))
    nodes, tri, body = demo_mesh["nodes"], demo_mesh["triangles"], demo_mesh["body"]
    p = nodes[tri]
    area = 0.5 * np.abs(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]))
    for b, poly in enumerate(s["polygons"]):
        a, _, _ = polygon_frame(poly)
        # a block's outline is what was meshed: the same area to gmsh's round-off
        assert a == pytest.approx(area[body == b].sum(), rel=1e-9), b


def test_bond_pairs_are_the_fem_dem_runs(demo_mesh):
    params = dict(mu=0.3, tau_cr=50e3)
    s = rigid_scene(demo_mesh, params)
    fem = Scene(demo_mesh, validate(params))
    bp = fem.bond_points
    # every bond point's pairs: total crack length = total bond edge length
    edges = np.asarray(bp.edges)
    nodes = np.asarray(demo_mesh["nodes"])
    total = np.linalg.norm(nodes[edges[:, 0]] - nodes[edges[:, 1]], axis=1).sum()
    assert s["bond_length"].sum() == pytest.approx(total, rel=1e-12)
    assert np.all(s["bond_a"] < s["bond_b"])
    # no bond across the indenter cut
    ind, layer = s["indenter"], set(s["layer"].tolist())
    assert not any((a == ind and b in layer) or (b == ind and a in layer) for a, b in zip(s["bond_a"], s["bond_b"]))
    # strengths graded with depth as the FEM-DEM's (top value at the keel top)
    assert s["sigma_cr"].max() <= 10e3 and s["tau_cr"].max() <= 50e3
    assert s["sigma_cr"].min() >= 0.1 * 10e3 * (1 - 1e-12)
    # stiff enough for every pair's peak (the engine refuses the others)
    k_min = (np.maximum(1.0, s["tau_cr"] / s["sigma_cr"]) * s["sigma_cr"] * s["bond_length"]) ** 2 / (
        2 * s["G"] * s["bond_length"])
    assert np.all(s["bond_k"] > k_min)
    # the bonded blocks are the blocks of the FEM-DEM's bond points
    assert set(map(tuple, np.sort(np.column_stack([s["bond_a"], s["bond_b"]]), axis=1))) == \
        set(map(tuple, np.asarray(bp.edge_bodies)))


def test_unknown_parameters_are_refused(demo_mesh):
    with pytest.raises(ValueError, match="unknown parameter"):
        rigid_scene(demo_mesh, dict(muu=0.3))


def test_outlines_of_blocks_are_convex_or_named(demo_mesh):
    """YADE polyhedra are convex: count the blocks whose meshed outline is not
    (they need a clump). On the demo pile contact resolution cuts only along
    lines, so every block stays convex to the snap tolerance."""
    s = rigid_scene(demo_mesh, {})
    for b in np.flatnonzero(s["body_kind"] == KIND_BLOCK):
        q = s["polygons"][b]
        u = np.roll(q, -1, axis=0) - q
        turns = u[:, 0] * np.roll(u, -1, axis=0)[:, 1] - u[:, 1] * np.roll(u, -1, axis=0)[:, 0]
        assert turns.min() > -1e-3 * np.abs(turns).max(), b


def test_the_outline_of_a_square_of_triangles_is_its_four_corners():
    nodes = np.array([(0, 0), (1, 0), (2, 0), (2, 1), (1, 1), (0, 1)], float)
    tri = np.array([(0, 1, 4), (0, 4, 5), (1, 2, 3), (1, 3, 4)])
    out = body_outline(nodes, tri)
    assert out.tolist() == [[0, 0], [2, 0], [2, 1], [0, 1]]
