"""VTU field files round-trip exactly (what ParaView reads is what we wrote)."""
import numpy as np

from icerubble.files.vtu import read_vtu, write_pvd, write_vtu


def test_vtu_round_trip(tmp_path):
    rng = np.random.default_rng(1)
    nodes = rng.random((7, 2))
    tri = np.array([[0, 1, 2], [2, 3, 4], [4, 5, 6]])
    u = rng.random((7, 2))
    body = np.array([0, 1, 1], dtype=np.int32)
    p = tmp_path / "s.vtu"
    write_vtu(p, nodes, tri, point_data={"u": u}, cell_data={"body": body})
    back = read_vtu(p)
    assert np.array_equal(back["Points"][:, :2], nodes) and np.all(back["Points"][:, 2] == 0)
    assert np.array_equal(back["u"][:, :2], u)
    assert np.array_equal(back["body"], body)
    assert np.array_equal(back["connectivity"].reshape(-1, 3), tri)
    assert np.array_equal(back["offsets"], [3, 6, 9]) and np.all(back["types"] == 5)
    write_pvd(tmp_path / "s.pvd", [(0.0, "s.vtu")])
    assert "s.vtu" in (tmp_path / "s.pvd").read_text()
