"""The run recorder writes the documented layout, and its state round-trips through checkpoints."""
import numpy as np
import pytest

from icerubble import parameters as P
from icerubble.geometry.bond_points import find_bond_points
from icerubble.files.h5io import open_complete
from icerubble.files.recorder import ENERGY_TERMS, RunRecorder, snapshot_travels
from tests.geometry.test_bond_points import grid


def make_recorder():
    nodes, tri, c = grid(4, 2, 2.0, 1.0)
    body = (c[:, 0] > 1.0).astype(int)
    bp = find_bond_points(nodes, tri, body, keel_top_y=1.0, keel_depth=1.0,
                          sigma_cr=10e3, tau_cr=50e3, G=15.0)
    # the run records the geometry measured on its mesh (here Table 1's)
    params = P.recorded(P.validate({"target_travel": 0.03}), {k: p.default for k, p in P.MESH.items()})
    mesh = dict(nodes=nodes, triangles=tri, body=body, body_kind=np.zeros(2, int))
    rec = RunRecorder(params, mesh, bp, dict(porosity=0.25, n_blocks=2),
                      dict(ridge="test", seed=1, model="fem-dem"))
    return rec, nodes, tri


def test_snapshot_schedule():
    assert snapshot_travels(0.03) == pytest.approx([0.001, 0.005, 0.01, 0.02, 0.03])


def test_written_file_has_documented_layout(tmp_path):
    rec, nodes, tri = make_recorder()
    rec.set_reference(nodes)
    shift = np.array([0.0, -0.002])
    for k, y in enumerate(np.linspace(0, 0.03, 301)):
        rec.force(k * 1e-3, y, 1e3 * y)
        if rec.wants_snapshot(y):
            rec.snapshot(k * 1e-3, y, nodes + shift, tri)
    rec.energy(0.0, {"kinetic": 1.0})
    rec.write(tmp_path / "run.h5")
    with open_complete(tmp_path / "run.h5", "icerubble-run") as f:
        assert f["force/F"].attrs["units"] == "N/m" and len(f["force/y_I"]) == 301
        assert f["parameters"].attrs["tau_cr"] == 50e3 and f.attrs["ridge"] == "test"
        assert len(f["snapshots"]) == 5
        # a rigid downward shift gives u = shift everywhere
        assert np.allclose(f["snapshots/0000/u_elem"][:], shift)
        assert np.allclose(f["snapshots/0000/u_node"][:], shift)
        assert f["mesh/area"][:].sum() == pytest.approx(2.0)
        assert np.all(np.isnan(f["bonds/t_fail"][:])) and f["bonds/length"][:].sum() == pytest.approx(1.0)
        assert set(ENERGY_TERMS) <= set(f["energy"].keys())


def test_state_round_trip():
    rec, nodes, tri = make_recorder()
    rec.force(0.0, 0.0, 0.0)
    s = rec.state()
    rec2, _, _ = make_recorder()
    rec2.restore(s)
    assert rec2.force_rows == rec.force_rows and rec2.pending_snaps == rec.pending_snaps


def test_postproc_reads_what_the_recorder_writes(tmp_path):
    from icerubble.files import results
    from postproc import loads
    rec, nodes, tri = make_recorder()
    rec.set_reference(nodes)
    for k, y in enumerate(np.linspace(0, 0.03, 31)):
        rec.force(k * 1e-3, y, 1e3 * (y if y < 0.002 else 0.004 - y))
    rec.write(tmp_path / "run.h5")
    run = results.load(tmp_path / "run.h5")
    assert run.mu == pytest.approx(0.3) and run.tau_cr == pytest.approx(50e3)
    assert run.porosity == pytest.approx(0.25)
    Fm, y_m = loads.cohesive_peak(run.force_y, run.force_F)
    assert Fm == pytest.approx(2.0) and y_m == pytest.approx(0.002)


def test_split_traction_written_read_and_restored_from_an_older_checkpoint(tmp_path):
    """/bonds/split_tn, split_tt go out in Pa; a checkpoint from before they were
    recorded restores with them NaN; the analyses count the initiation side from them."""
    from icerubble.files import results
    from postproc import summary
    rec, nodes, tri = make_recorder()
    P = len(rec.bp)
    old = rec.state()
    for k in ("split_tn", "split_tt"):
        del old["bonds"][k]
    rec.restore(old)
    assert rec.bonds["split_tn"].shape == (P,) and np.isnan(rec.bonds["split_tn"]).all()
    assert P >= 2   # one point split on each side of eq 6, the rest intact
    y_split = np.full(P, np.nan)
    y_split[:2] = [1e-3, 2e-3]
    tn = np.full(P, np.nan)
    tn[:2] = [10e3, -3e3]
    rec.bond_events(dict(y_I_split=y_split, split_tn=tn, split_tt=np.where(np.isfinite(tn), 5e3, np.nan)))
    rec.set_reference(nodes)
    for k, y in enumerate(np.linspace(0, 0.03, 31)):
        rec.force(k * 1e-3, y, 1e3 * y)
    rec.write(tmp_path / "run.h5")
    with open_complete(tmp_path / "run.h5", "icerubble-run") as f:
        assert f["bonds/split_tn"].attrs["units"] == "Pa" and f["bonds/split_tt"].attrs["units"] == "Pa"
        assert f["bonds/split_tn"][:2].tolist() == [10e3, -3e3]
    row = summary.summarize(results.load(tmp_path / "run.h5"))
    assert (row["n_t_init"], row["n_s_init"], row["nt_ns_init"]) == (1, 1, 1.0)
    assert "split_traction" not in row["missing"]
