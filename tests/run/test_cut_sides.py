"""A cropped scene holds its cut faces in x (a roller), as the rest of the pile
held them there: without it the deep scene's keel spread out of its cut sides
(docs/study_paper_depth.md). The faces still move up and down."""
import numpy as np

from icerubble import parameters as P
from icerubble.files import mesh_file
from icerubble.geometry import meshing
from icerubble.run.presets import scene
from icerubble.run.scene import Scene
from tests.geometry.test_meshing import W, YB, box, pile_dict


def test_the_cut_faces_slide_vertically_and_never_sideways(tmp_path):
    # A bonded under the layer and B bonded under A, both cut at x = -2.5 by
    # the crop; free otherwise, they would swing and float about
    A = box(-3.0, -1.0, YB - 0.3, YB)
    B = box(-2.55, -1.5, YB - 0.6, YB - 0.3)
    m = meshing.build_mesh(pile_dict([A, B]), element_size=0.1, domain_width=5.0)
    path = str(tmp_path / "cut_mesh.h5")
    mesh_file.write_mesh(path, m, source="test")
    mesh = mesh_file.read_mesh(path)
    np.testing.assert_array_equal(np.sort(mesh["cut_sides"]), np.sort(m["cut_sides"]))
    params = P.validate(dict(scene("tiny")["params"]))
    sc = Scene(mesh, params, threads=1)
    model = sc.model
    sc.hold_boundaries(model)
    model.set(dt_fraction=0.8)
    cut = model.node_sets["cut_sides"]
    x0 = model.positions[cut].copy()
    model.step(2000)
    moved = model.positions[cut] - x0
    assert np.all(moved[:, 0] == 0.0)              # held in x, exactly
    assert np.abs(moved[:, 1]).max() > 1e-7        # free in y: the blocks settle on their faces


def test_side_walls_held_hold_the_blocks_where_phase_1s_walls_stood(tmp_path):
    # An uncropped scene: A under the layer against the left wall (x = -W/2),
    # B under A, 5 mm off the wall (it leaned on it within phase 1's overlap)
    A = box(-0.5 * W, -0.5 * W + 2.0, YB - 0.3, YB)
    B = box(-0.5 * W + 0.005, -0.5 * W + 1.0, YB - 0.6, YB - 0.3)
    m = meshing.build_mesh(pile_dict([A, B]), element_size=0.1)
    assert m["cut_sides"].size == 0
    path = str(tmp_path / "walls_mesh.h5")
    mesh_file.write_mesh(path, m, source="test")
    mesh = mesh_file.read_mesh(path)
    free = Scene(mesh, P.validate(dict(scene("tiny")["params"])), threads=1)
    assert "wall_sides" not in free.model.node_sets            # the default: no walls in phase 2
    sc = Scene(mesh, P.validate(dict(scene("tiny")["params"], side_walls="held")), threads=1)
    model = sc.model
    walls = model.node_sets["wall_sides"]
    x = model.positions[walls, 0]
    assert walls.size and np.all(np.abs(x + 0.5 * W) < 0.01)   # A's and B's nodes at the wall
    assert np.any(np.abs(x + 0.5 * W) > 1e-3)                   # B's, 5 mm off it
    sc.hold_boundaries(model)
    model.set(dt_fraction=0.8)
    x0 = model.positions[walls].copy()
    model.step(2000)
    moved = model.positions[walls] - x0
    assert np.all(moved[:, 0] == 0.0)              # held in x, exactly
    assert np.all(moved[:, 1] != 0.0)              # free in y: every one moves with its block
