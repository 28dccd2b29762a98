"""A FEM-DEM state as rigid blocks (rigid_dem/snapshot.py, yade_state.py,
yade_scripts/load_state.py): the deformed ridge of a snapshot, its surviving
bonds, and the same ridge taken up in YADE."""
import json
import os
import shutil
import subprocess

import h5py
import numpy as np
import pytest

from icerubble.rigid_dem.scene import INSET, rigid_scene
from icerubble.rigid_dem.snapshot import fem_dem_state, read_result, result_mesh, result_params
from icerubble.rigid_dem.water import polygon_frame
from icerubble.files.recorder import RunRecorder
from tests.paths import ROOT



def edited(src, dst, edit):
    """A copy of result `src` with `edit(h5py.File)` applied."""
    shutil.copy(src, dst)
    with h5py.File(dst, "r+") as f:
        edit(f)
    return dst


def recorded(base, out, rest, now, tri_now, split=(), y_I=1e-3):
    """A FEM-DEM result of `base`'s ridge written by the run's own recorder:
    rest state `rest` (the mesh's nodes), one snapshot at y_I with the nodes
    at `now` on triangles `tri_now`, bond points `split` split at y_I / 2."""
    run = read_result(base)
    mesh = result_mesh(run)
    sc = rigid_scene(mesh, result_params(run))
    rec = RunRecorder(sc["params"], {k: mesh[k] for k in ("nodes", "triangles", "body", "body_kind")},
                      sc["bond_points"], run.pile, dict(model="fem-dem", ridge="made"))
    rec.set_reference(rest)
    rec.force(0.0, 0.0, 0.0)
    rec.force(0.1, 2 * y_I, 1.0)
    rec.snapshot(0.05, y_I, now, tri_now)
    y_split = np.full(len(sc["bond_points"]), np.nan)
    y_split[list(split)] = 0.5 * y_I
    rec.bond_events(dict(y_I_split=y_split))
    rec.write(out)
    return out


def turned(x, angle, shift, about):
    c, s = np.cos(angle), np.sin(angle)
    d = x - about
    return about + np.column_stack([c * d[:, 0] - s * d[:, 1], s * d[:, 0] + c * d[:, 1]]) + shift


def outline_distance(point, poly):
    """Distance of a point from a polygon's outline [m]."""
    a, b = poly, np.roll(poly, -1, axis=0)
    e = b - a
    t = np.clip(((point - a) * e).sum(axis=1) / (e * e).sum(axis=1), 0.0, 1.0)
    return np.hypot(*(a + t[:, None] * e - point).T).min()


# --- the state, without YADE ---------------------------------------------------------

def test_the_rebuilt_nodes_are_where_the_recorder_had_them(tiny_fem_result, tmp_path):
    """A settle (turn, shift, a smooth strain) and a load with split bond points,
    each body but the highest at a split node on its own copy 0.3 mm away: the
    rebuilt corners are the recorded ones, though the file holds neither the
    settled nodes nor the copies."""
    run = read_result(tiny_fem_result)
    mesh = result_mesh(run)
    X, tri, body = mesh["nodes"], mesh["triangles"], mesh["body"]
    rng = np.random.default_rng(1)
    wave = np.column_stack([np.sin(2 * X[:, 1]), np.cos(3 * X[:, 0])])
    rest = turned(X, 2e-3, (3e-3, -2e-3), X.mean(axis=0)) + 1e-4 * wave + 1e-6 * rng.standard_normal(X.shape)
    now = turned(rest, -1e-3, (1e-3, -4e-3), rest.mean(axis=0)) + 2e-4 * wave[:, ::-1]
    bp = rigid_scene(mesh, result_params(run))["bond_points"]
    split = np.flatnonzero(bp.n_bodies >= 2)[::2]
    tri_now, copies = tri.copy(), []
    for i in bp.node[split]:
        for b in np.unique(body[(tri == i).any(axis=1)])[:-1]:   # the highest body keeps the node
            copies.append(now[i] + 3e-4 * np.array([np.cos(b), np.sin(b)]))
            tri_now[(body == b)[:, None] & (tri == i)] = len(now) + len(copies) - 1
    now = np.vstack([now, copies])
    path = recorded(tiny_fem_result, tmp_path / "made.h5", rest, now, tri_now, split)
    sc = fem_dem_state(path, snapshot=0)
    assert len(sc["nodes"]) == len(now)
    assert np.abs(sc["nodes"][sc["triangles"]] - now[tri_now]).max() < 1e-9
    assert sc["centroid_residual"] < 1e-12
    assert sc["bond_split"].sum() == np.isin(sc["bond_point"], split).sum() > 0


def test_a_real_snapshot_is_rebuilt_to_its_triangle_centroids(tiny_fem_result):
    run = read_result(tiny_fem_result)
    snap = run.snapshots[0]
    sc = fem_dem_state(tiny_fem_result, snapshot=0)
    now = sc["nodes"][sc["triangles"]].mean(axis=1)
    assert np.abs(now - (run.elem_centroid + run.u_elem(snap))).max() < 1e-12
    # one copy per body beyond the highest at every split bond point
    bp = sc["bond_points"]
    split = run.bonds["y_I_split"] <= snap.y_I
    assert split.any()
    assert len(sc["nodes"]) == len(result_mesh(run)["nodes"]) + int((bp.n_bodies[split] - 1).sum())


def test_each_body_is_its_deformed_triangles(tiny_fem_result):
    """Each outline encloses its body's triangles where the snapshot has them:
    their summed area and area-weighted centroid."""
    sc = fem_dem_state(tiny_fem_result, snapshot=0)
    body = result_mesh(read_result(tiny_fem_result))["body"]
    p = sc["nodes"][sc["triangles"]]
    area = 0.5 * np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    centre = p.mean(axis=1)
    assert area.min() > 0.0
    for b, poly in enumerate(sc["polygons"]):
        a, c, _ = polygon_frame(poly)
        mine = body == b
        assert a == pytest.approx(area[mine].sum(), rel=1e-12), b
        assert np.abs(c - (area[mine, None] * centre[mine]).sum(axis=0) / area[mine].sum()).max() < 1e-12, b


def test_a_ridge_moved_rigidly_is_its_meshed_scene_moved(tiny_fem_result, tmp_path):
    """Unmoved (u_node = 0, rest = the mesh), the state is rigid_scene's; turned
    and shifted as a whole, its outlines, bond points and normals turn and
    shift with it, and the pairs, strengths and stiffnesses stay."""
    run = read_result(tiny_fem_result)
    mesh = result_mesh(run)
    X, tri = mesh["nodes"], mesh["triangles"]
    meshed = rigid_scene(mesh, result_params(run))
    for angle, shift in ((0.0, (0.0, 0.0)), (0.02, (0.05, -0.03))):
        about = np.array([0.3, -1.0])
        path = recorded(tiny_fem_result, tmp_path / f"moved{angle}.h5", X, turned(X, angle, shift, about), tri)
        sc = fem_dem_state(path)

        def move(x):
            return turned(np.asarray(x), angle, shift, about)
        for q, q0 in zip(sc["polygons"], meshed["polygons"]):
            assert q.shape == q0.shape and np.abs(q - move(q0)).max() < 1e-12
        assert np.abs(sc["bond_position"] - move(meshed["bond_position"])).max() < 1e-12
        assert np.abs(sc["bond_normal"] - turned(meshed["bond_normal"], angle, 0.0, 0.0)).max() < 1e-9
        for k in ("bond_a", "bond_b", "bond_point", "bond_length", "bond_k", "sigma_cr", "tau_cr", "G", "mu"):
            assert np.array_equal(sc[k], meshed[k]), k
        assert sc["y_w"] == meshed["y_w"] and sc["pairs_failed"] == 0


def test_before_any_failure_the_pairs_are_the_meshed_ones_where_the_points_are(tiny_fem_result):
    run = read_result(tiny_fem_result)
    assert not (run.bonds["y_I_fail"] <= run.snapshots[0].y_I).any()   # the tiny run: none by 1 mm
    sc = fem_dem_state(tiny_fem_result, snapshot=0)
    meshed = rigid_scene(result_mesh(run), result_params(run))
    for k in ("bond_a", "bond_b", "bond_point", "bond_length", "bond_k", "sigma_cr", "tau_cr", "G"):
        assert np.array_equal(sc[k], meshed[k]), k
    # each pair sits on both its bodies' deformed outlines (midway across an
    # opened crack), millimetres from where it was meshed (the settle, the load)
    moved = np.hypot(*(sc["bond_position"] - meshed["bond_position"]).T)
    assert moved.max() > 1e-3
    for k in range(len(sc["bond_point"])):
        p = sc["bond_position"][k]
        gap = [outline_distance(p, sc["polygons"][b]) for b in (sc["bond_a"][k], sc["bond_b"][k])]
        assert max(gap) < (1e-12 if not sc["bond_split"][k] else 1e-3), k
    assert np.allclose(np.hypot(*sc["bond_normal"].T), 1.0, rtol=0, atol=1e-12)


def test_failed_bond_points_are_left_out(tiny_fem_result, tmp_path):
    """A pair survives exactly when its point's y_I_fail is NaN or beyond the
    snapshot's travel (a point failing at the snapshot itself is gone)."""
    y = read_result(tiny_fem_result).snapshots[0].y_I
    n = len(read_result(tiny_fem_result).bonds["y_I_fail"])
    y_fail = np.tile([np.nan, 0.2 * y, y, 1.5 * y], n)[:n]

    def fail(f):
        f["bonds/y_I_fail"][...] = y_fail
        f["bonds/y_I_split"][...] = np.where(np.isnan(y_fail), f["bonds/y_I_split"][...], 0.1 * y)
    path = edited(tiny_fem_result, tmp_path / "failed.h5", fail)
    sc = fem_dem_state(path, snapshot=0)
    meshed = fem_dem_state(tiny_fem_result, snapshot=0)
    keep = np.isnan(y_fail[meshed["bond_point"]]) | (y_fail[meshed["bond_point"]] > y)
    assert 0 < keep.sum() < len(keep)
    for k in ("bond_a", "bond_b", "bond_point", "sigma_cr"):
        assert np.array_equal(sc[k], meshed[k][keep]), k
    assert np.abs(sc["bond_position"] - meshed["bond_position"][keep]).max() < 1e-12
    assert sc["pairs_failed"] == (~keep).sum()


def test_a_snapshot_is_picked_by_number_or_nearest_travel(tiny_fem_result):
    sc = fem_dem_state(tiny_fem_result, y_I=0.4e-3)
    y = read_result(tiny_fem_result).snapshots[0].y_I
    assert sc["source"]["snapshot"] == "0000" and sc["source"]["y_I"] == y and sc["source"]["y_I_asked"] == 0.4e-3
    assert sc["source"]["file"] == os.path.abspath(tiny_fem_result)


def test_bad_input_is_refused_with_the_parameter_named(tiny_fem_result, tmp_path):
    y = read_result(tiny_fem_result).snapshots[-1].y_I
    with pytest.raises(ValueError, match=r"snapshot=1 is out of range: valid 0 to 0"):
        fem_dem_state(tiny_fem_result, snapshot=1)
    with pytest.raises(ValueError, match=r"snapshot=-1 is out of range"):
        fem_dem_state(tiny_fem_result, snapshot=-1)
    with pytest.raises(ValueError, match=rf"y_I=3 mm is out of range: valid 0 to {y * 1e3:.3g} mm"):
        fem_dem_state(tiny_fem_result, y_I=3e-3)
    with pytest.raises(ValueError, match=r"y_I=-1 mm is out of range"):
        fem_dem_state(tiny_fem_result, y_I=-1e-3)
    with pytest.raises(ValueError, match="not both"):
        fem_dem_state(tiny_fem_result, snapshot=0, y_I=1e-3)

    def rigid(f):
        f.attrs["model"] = "rigid-dem"
    with pytest.raises(ValueError, match="model = 'rigid-dem'; only a fem-dem result"):
        fem_dem_state(edited(tiny_fem_result, tmp_path / "rigid.h5", rigid))

    def no_snapshots(f):
        for k in list(f["snapshots"]):
            del f["snapshots"][k]
    with pytest.raises(ValueError, match="has no snapshots"):
        fem_dem_state(edited(tiny_fem_result, tmp_path / "none.h5", no_snapshots))

    def shifted(f):   # u_node from somewhere else: the nodes no longer fit the centroids
        f["snapshots/0000/u_node"][0] += 1e-3
    with pytest.raises(ValueError, match="miss its triangle centroids"):
        fem_dem_state(edited(tiny_fem_result, tmp_path / "shifted.h5", shifted))


# --- in YADE ---------------------------------------------------------------------------

@pytest.fixture(scope="module")
def loaded(tiny_fem_result, tmp_path_factory):
    out = tmp_path_factory.mktemp("loaded") / "loaded.json"
    env = dict(os.environ, RESULT=str(tiny_fem_result), SNAPSHOT="0", RUN_TIME="0.05", OUT=str(out),
               OMP_NUM_THREADS="1")
    r = subprocess.run(["yade", "-n", "-x", os.path.join("tests", "rigid_dem", "yade_state_scene.py")],
                       cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    return json.loads(out.read_text())


def test_yade_bodies_are_the_deformed_bodies_made_convex_and_inset(tiny_fem_result, loaded):
    sc = fem_dem_state(tiny_fem_result, snapshot=0)
    pl = loaded["placed"]
    for b, poly in enumerate(sc["polygons"]):
        placed = np.array(pl["polygons"][b])
        a, c, _ = polygon_frame(placed)
        # YADE's body: the placed prism's area (mass / rho, 1 m deep) and centroid
        assert pl["mass"][b] / pl["rho_i"] == pytest.approx(a, rel=1e-9), b
        assert np.abs(np.array(pl["pos"][b][:2]) - c).max() < 1e-9 and abs(pl["pos"][b][2]) < 1e-12, b
        # the placed outline is the deformed outline's hull moved in by INSET:
        # its area plus INSET x perimeter is the hull's (to INSET^2 per corner)
        a0, c0, _ = polygon_frame(poly)
        perimeter = np.hypot(*(np.roll(placed, -1, axis=0) - placed).T).sum()
        hull = a0 * (1.0 + pl["hull_gain"][b])
        assert abs(a + INSET * perimeter - hull) < 10 * INSET ** 2 * len(placed), b
        assert np.abs(c - c0).max() < 10 * INSET, b   # where the FEM-DEM had it
    # the tiny ridge's bodies are convex to the strain: the hulls add ~nothing
    assert 0.0 <= pl["hull_added_area"] == max(pl["hull_gain"]) < 1e-4


def test_yade_bonds_start_unloaded_where_the_bodies_are(loaded):
    f, peak = loaded["first"], np.array(loaded["first"]["peak"])
    assert len(peak) == loaded["placed"]["n_pairs"] > 0
    assert np.abs(f["f_n"]).max() < 1e-9 * peak.min() and np.abs(f["f_t"]).max() < 1e-9 * peak.min()


def test_a_loaded_snapshot_runs_on_in_yade(loaded):
    """0.05 s with gravity, water, friction and bonds from the tiny ridge at 1 mm:
    near its balance (what is lost is the indenter's push, and the contact
    forces, as the inset bodies start apart), so nothing jumps: no body reaches
    a tenth of the free-fall speed g t, none moves a millimetre, no bond breaks."""
    r = loaded["run"]
    assert r["time"] == pytest.approx(0.05, rel=0.01)
    for k in ("move", "speed", "spin", "turn"):
        assert np.isfinite(r[k]).all(), k
    assert max(r["speed"]) < 0.1 * 9.81 * r["time"]
    assert max(r["move"]) < 1e-3
    assert 2 not in r["state"]


def test_load_state_prints_what_it_loaded_and_saves_the_bodies(tiny_fem_result, tmp_path):
    out = tmp_path / "scene.yade.gz"
    r = subprocess.run(["yade", "-n", "-x", "yade_scripts/load_state.py", str(tiny_fem_result), "--y-I-mm", "0.8",
                        "--save", str(out)], cwd=ROOT, capture_output=True, text=True, timeout=120,
                       env=dict(os.environ, OMP_NUM_THREADS="1"))
    assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
    n = len(fem_dem_state(tiny_fem_result)["bond_point"])
    assert f"bond pairs intact {n} " in r.stdout and "failed 0 (left out)" in r.stdout
    assert "y_I = 1.01" in r.stdout and "largest hull area gain" in r.stdout
    assert out.exists() and out.stat().st_size > 0


@pytest.mark.parametrize("args, message", [(["--snapshot", "4"], "snapshot=4 is out of range: valid 0 to 0"),
                                           (["--y-I-mm", "30"], "y_I=30 mm is out of range")])
def test_load_state_refuses_bad_arguments_without_a_traceback(tiny_fem_result, args, message):
    r = subprocess.run(["yade", "-n", "-x", "yade_scripts/load_state.py", str(tiny_fem_result)] + args,
                       cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert r.returncode == 1 and f"load_state: error: {message}" in r.stderr
    assert "Traceback" not in r.stderr + r.stdout
