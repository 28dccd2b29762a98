"""tools/rest_rise.py reads how far a settle moved the indenter and the keel
from a rest state: a constructed one whose indenter was lifted by 50 mm and
whose block under it by 20 mm (docs/study_paper_depth.md, "Run log")."""
import json
import os
import sys

import h5py
import numpy as np

from icerubble import parameters as P
from icerubble.files import mesh_file
from icerubble.geometry import meshing
from tests.geometry.test_meshing import YB, box, pile_dict

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "tools"))
import rest_rise  # noqa: E402


def write_rest_state(folder, lift_indenter, lift_under):
    # one block under the indenter (|x| < 2 m), 1 cm below it (not bonded: no node
    # shared), and none beyond the indenter's width in this
    # 8 m domain (x > 4 m), whose column then says so
    m = meshing.build_mesh(pile_dict([box(-1.0, 1.0, YB - 0.31, YB - 0.01)]), element_size=0.2)
    mesh_path = os.path.join(folder, "case_mesh.h5")
    mesh_file.write_mesh(mesh_path, m, source="test")
    mesh = mesh_file.read_mesh(mesh_path)
    p0 = np.asarray(mesh["nodes"], float)
    tri = np.asarray(mesh["triangles"])
    kind = np.asarray(mesh["body_kind"])[np.asarray(mesh["body"])]
    p = p0.copy()
    p[np.unique(tri[kind == mesh_file.KIND_INDENTER]), 1] += lift_indenter
    p[np.unique(tri[kind == mesh_file.KIND_BLOCK]), 1] += lift_under
    # as a run's checkpoint records them: the table's and the geometry measured on the mesh
    params = dict(P.validate(dict(tau_cr=5000.0, mu=0.05, settle_bonds="checked")), indenter_width=4.0)
    with h5py.File(os.path.join(folder, "case_rest_0123.checkpoint.h5"), "w") as f:
        f["engine/positions"] = p.ravel()
        f["engine/reference_positions"] = p0.ravel()
        f["engine/body"] = np.asarray(mesh["body"])
        f["engine/triangles"] = tri.ravel()
        f["engine/bond_state/point_state"] = np.array([0, 1, 2, 0], np.int8)
        f.create_group("driver").attrs["params"] = json.dumps(params)


def test_the_lift_of_the_indenter_and_of_the_keel_under_it_is_read(tmp_path, capsys):
    write_rest_state(str(tmp_path), 0.050, 0.020)
    assert rest_rise.main([str(tmp_path)]) == 0
    rows = [r for r in capsys.readouterr().out.splitlines() if r.startswith("| case_rest_0123")]
    assert len(rows) == 1
    cells = [c.strip() for c in rows[0].strip("|").split("|")]
    assert cells[1:4] == ["5", "0.05", "checked"]
    assert float(cells[4]) == 50.0 and float(cells[5]) == 20.0
    assert cells[6] == "—"  # no block node beyond the indenter's width
    assert cells[7] == "2"  # the points not intact


def test_a_missing_folder_is_refused_before_any_work(capsys):
    assert rest_rise.main(["/no/such/folder"]) == 2
    assert "no such folder: /no/such/folder" in capsys.readouterr().err
