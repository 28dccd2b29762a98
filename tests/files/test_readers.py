"""Pile and mesh files are checked before any work: a missing dataset, a wrong
shape, non-finite values, ids outside the arrays or another unit is refused
with one message naming the file, the dataset and what was expected (never a
KeyError traceback, never millimetres read as metres)."""
import os

import numpy as np
import pytest

from icerubble.files.mesh_file import read_mesh
from icerubble.files.pile_file import read_pile
from icerubble.geometry.meshing import mesh_pile_file
from tests.h5_edits import broken, replace
from tests.paths import DATA

PILE = os.path.join(DATA, "demo_pile.h5")


@pytest.fixture(scope="module")
def mesh_path(tmp_path_factory):
    path = str(tmp_path_factory.mktemp("mesh") / "demo_mesh.h5")
    mesh_pile_file(PILE, path, element_size=0.15)
    return path


def test_the_intact_files_read(mesh_path):
    p = read_pile(PILE)
    m = read_mesh(mesh_path)
    assert p["corners"].shape[1:] == (4, 2) and len(p["thickness"]) == len(p["corners"])
    assert m["triangles"].max() < len(m["nodes"]) and len(m["body"]) == len(m["triangles"])


PILE_CASES = [
    ("no corners", lambda f: f.__delitem__("blocks/corners"), "'blocks/corners': missing"),
    ("millimetres", lambda f: f["blocks/corners"].attrs.__setitem__("units", "mm"),
     "'blocks/corners': units 'mm', expected 'm'"),
    ("triangles for blocks", replace("blocks/corners", np.zeros((3, 3, 2))),
     r"'blocks/corners': shape \(3, 3, 2\), expected \(n, 4, 2\)"),
    ("NaN corner", lambda f: f["blocks/corners"].__setitem__((0, 0, 0), np.nan),
     "'blocks/corners': 1 non-finite values"),
    ("one thickness short", lambda f: replace("blocks/thickness", f["blocks/thickness"][1:])(f),
     "'blocks/thickness': shape"),
    ("text for lengths", replace("blocks/length", np.array([b"a", b"b"])), "'blocks/length': "),
]


@pytest.mark.parametrize("what, edit, message", PILE_CASES, ids=[c[0] for c in PILE_CASES])
def test_a_broken_pile_is_refused_naming_file_and_dataset(tmp_path, what, edit, message):
    path = broken(PILE, tmp_path, edit)
    with pytest.raises(ValueError, match=message) as e:
        read_pile(path)
    assert "pile file" in str(e.value) and path in str(e.value)


def _nodes_in_mm(f):
    f["nodes"][...] = f["nodes"][...] * 1e3
    f["nodes"].attrs["units"] = "mm"


MESH_CASES = [
    ("no triangles", lambda f: f.__delitem__("triangles"), "'triangles': missing"),
    ("no nodes", lambda f: f.__delitem__("nodes"), "'nodes': missing"),
    ("millimetres", _nodes_in_mm, "'nodes': units 'mm', expected 'm'"),
    ("no units", lambda f: f["nodes"].attrs.__delitem__("units"), "'nodes': units None, expected 'm'"),
    ("float triangles", lambda f: replace("triangles", f["triangles"][...].astype(float))(f),
     "'triangles': dtype float64, expected integers"),
    ("node id past the end", lambda f: f["triangles"].__setitem__((0, 0), len(f["nodes"])),
     "'triangles': ids must lie in"),
    ("negative body", lambda f: f["body"].__setitem__(0, -1), "'body': ids must lie in"),
    ("one body short", lambda f: replace("body", f["body"][1:])(f), "'body': shape"),
    ("infinite node", lambda f: f["nodes"].__setitem__((0, 1), np.inf), "'nodes': 1 non-finite"),
    ("no layer top", lambda f: f.__delitem__("node_sets/layer_top"), "'node_sets/layer_top': missing"),
    ("no water line data", lambda f: f.attrs.__delitem__("layer_bottom_y"),
     "root attribute.*layer_bottom_y missing"),
]


@pytest.mark.parametrize("what, edit, message", MESH_CASES, ids=[c[0] for c in MESH_CASES])
def test_a_broken_mesh_is_refused_naming_file_and_dataset(mesh_path, tmp_path, what, edit, message):
    path = broken(mesh_path, tmp_path, edit)
    with pytest.raises(ValueError, match=message) as e:
        read_mesh(path)
    assert "mesh file" in str(e.value) and path in str(e.value)


def test_a_pile_is_not_a_mesh(tmp_path):
    with pytest.raises(ValueError, match="has format 'icerubble-pile', expected 'icerubble-mesh'"):
        read_mesh(PILE)
