"""Broad phase and normal contact pass of ContactSolver against brute force.

The broad phase must return exactly the surface-triangle pairs of different
bodies, sharing no node, whose bounding boxes overlap; the normal pass must add
exactly the pair-kernel forces of the pairs that overlap.
"""
import os
import subprocess
import sys

import numpy as np
import pytest

from icerubble import _engine
from tests.paths import ROOT

S = 2e11


def random_scene(n_nodes, n_tri, n_bodies, seed, box=10.0):
    """Random triangles on a shared node cloud: many share nodes, many overlap."""
    rng = np.random.default_rng(seed)
    pts = rng.uniform(0, box, (n_nodes, 2))
    d2 = ((pts[:, None, :] - pts[None, :, :]) ** 2).sum(-1)
    near = np.argsort(d2, axis=1)[:, 1:8]
    tris = []
    while len(tris) < n_tri:
        i = rng.integers(n_nodes)
        j, k = rng.choice(near[i], 2, replace=False)
        a, b, c = pts[i], pts[j], pts[k]
        a2 = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])
        if abs(a2) < 1e-3:
            continue
        tris.append((i, j, k) if a2 > 0 else (i, k, j))
    tri = np.array(tris, dtype=np.int32)
    body = rng.integers(0, n_bodies, n_tri).astype(np.int32)
    surface = np.sort(rng.choice(n_tri, int(0.7 * n_tri), replace=False)).astype(np.int32)
    return pts, tri, body, surface


def run_normal(pts, tri, body, surface, solver=None, skin_fraction=0.0):
    n = len(pts)
    solver = solver or _engine.ContactSolver(skin_fraction=skin_fraction)
    fx, fy = np.zeros(n), np.zeros(n)
    zero = np.zeros(n)
    solver.compute_normal(pts[:, 0].copy(), pts[:, 1].copy(), zero, zero, np.ones(n), tri, body,
                          surface, fx, fy, penalty=S, mu=0.0, dt=1e-6)
    return solver, fx, fy


def brute_force_candidates(pts, tri, body, surface, skin=0.0):
    lo = pts[tri].min(axis=1) - skin
    hi = pts[tri].max(axis=1) + skin
    out = set()
    for ii, a in enumerate(surface):
        for b in surface[ii + 1:]:
            if body[a] == body[b] or set(tri[a]) & set(tri[b]):
                continue
            if np.all(lo[a] <= hi[b]) and np.all(lo[b] <= hi[a]):
                out.add((min(a, b), max(a, b)))
    return out


@pytest.mark.parametrize("seed", [0, 1])
def test_broad_phase_finds_exactly_the_brute_force_pairs(seed):
    pts, tri, body, surface = random_scene(300, 500, 4, seed)
    solver, fx, fy = run_normal(pts, tri, body, surface)
    cand = [tuple(p) for p in solver.candidates]
    assert len(cand) == len(set(cand)), "a pair was reported twice"
    assert set(cand) == brute_force_candidates(pts, tri, body, surface)
    assert len(cand) > 100  # the scene really has work for the broad phase


def test_broad_phase_skin_grows_every_box():
    # With a skin the list holds exactly the pairs whose boxes, grown by
    # skin = fraction x largest surface-triangle extent, overlap.
    pts, tri, body, surface = random_scene(300, 500, 4, 6)
    solver, _, _ = run_normal(pts, tri, body, surface, skin_fraction=0.2)
    ext = (pts[tri[surface]].max(axis=1) - pts[tri[surface]].min(axis=1)).max()
    exact = brute_force_candidates(pts, tri, body, surface)
    grown = brute_force_candidates(pts, tri, body, surface, skin=0.2 * ext)
    assert set(tuple(p) for p in solver.candidates) == grown
    assert len(grown) > len(exact)


def test_reused_candidate_list_finds_every_touching_pair_while_nodes_move():
    # Nodes jiggle by up to 2 cm per call (triangles ~1 m): the list built
    # with a 10 % skin is reused for many calls, and at every call the
    # touching pairs and forces equal those of a fresh broad phase.
    pts, tri, body, surface = random_scene(300, 500, 4, 8)
    rng = np.random.default_rng(9)
    reused = _engine.ContactSolver(skin_fraction=0.1)
    calls = 40
    for _ in range(calls):
        pts = pts + rng.uniform(-2e-2, 2e-2, pts.shape)
        _, fx, fy = run_normal(pts, tri, body, surface, solver=reused)
        fresh, gx, gy = run_normal(pts, tri, body, surface)
        assert set(tuple(p) for p in reused.pairs["tris"]) == set(tuple(p) for p in fresh.pairs["tris"])
        scale = max(np.abs(gx).max(), np.abs(gy).max())
        # Same pair forces summed in another order: round-off only.
        np.testing.assert_allclose(fx, gx, rtol=0, atol=1e-12 * scale)
        np.testing.assert_allclose(fy, gy, rtol=0, atol=1e-12 * scale)
    assert 1 < reused.rebuilds < calls


def test_broad_phase_with_far_apart_clusters():
    # Two clusters 1e5 m apart: the grid is capped and coarsened, and must
    # still find every pair.
    pts, tri, body, surface = random_scene(200, 300, 3, 5, box=5.0)
    pts = pts.copy()
    pts[100:] += 1e5
    keep = np.all((tri < 100), axis=1) | np.all((tri >= 100), axis=1)
    tri, body = tri[keep], body[keep]
    surface = np.arange(len(tri), dtype=np.int32)
    solver, _, _ = run_normal(pts, tri, body, surface)
    assert set(tuple(p) for p in solver.candidates) == brute_force_candidates(pts, tri, body, surface)


def test_normal_pass_equals_sum_of_pair_kernels():
    pts, tri, body, surface = random_scene(300, 500, 4, 2)
    solver, fx, fy = run_normal(pts, tri, body, surface)
    n = len(pts)
    ref = np.zeros((n, 2))
    touching = set()
    energy = 0.0
    for a, b in brute_force_candidates(pts, tri, body, surface):
        r = _engine.contact_pair(pts[tri[a]], pts[tri[b]], S)
        if r is None:
            continue
        touching.add((a, b))
        np.add.at(ref, np.concatenate([tri[a], tri[b]]), r["forces"])
        energy += r["energy"]
    assert touching == set(tuple(p) for p in solver.pairs["tris"])
    assert solver.touching_pairs == len(touching) > 20
    # Same terms summed in a different order: round-off only.
    scale = np.abs(ref).max()
    np.testing.assert_allclose(np.c_[fx, fy], ref, rtol=0, atol=1e-12 * scale)
    assert solver.stored_energy == pytest.approx(energy, rel=1e-12)
    # Pairs whose triangles share a node or a body never appear.
    for a, b in solver.pairs["tris"]:
        assert body[a] != body[b] and not set(tri[a]) & set(tri[b])


def test_repeat_and_reuse_are_bit_identical():
    pts, tri, body, surface = random_scene(300, 500, 4, 3)
    solver, fx1, fy1 = run_normal(pts, tri, body, surface)
    _, fx2, fy2 = run_normal(pts, tri, body, surface, solver)  # reused buffers
    s3, fx3, fy3 = run_normal(pts, tri, body, surface, skin_fraction=0.1)
    _, fx4, fy4 = run_normal(pts, tri, body, surface, s3)  # reused candidate list
    assert s3.rebuilds == 1
    assert np.array_equal(fx3, fx4) and np.array_equal(fy3, fy4)
    assert np.array_equal(fx1, fx2) and np.array_equal(fy1, fy2)


SNIPPET = """
import hashlib, numpy as np
from tests.engine.test_contact_broad_phase import random_scene, run_normal
pts, tri, body, surface = random_scene(400, 800, 5, 7)
s, fx, fy = run_normal(pts, tri, body, surface, skin_fraction=0.1)
print(hashlib.sha256(fx.tobytes() + fy.tobytes() + s.candidates.tobytes()).hexdigest())
"""


def test_results_do_not_depend_on_thread_count():
    code = SNIPPET
    digests = []
    for threads in ("1", "2"):
        env = dict(os.environ, OMP_NUM_THREADS=threads)
        out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                             check=True, cwd=ROOT)
        digests.append(out.stdout.strip())
    assert digests[0] == digests[1]


def test_non_finite_position_is_reported():
    pts, tri, body, surface = random_scene(50, 60, 2, 4)
    pts[tri[surface[0]][0], 0] = np.nan
    with pytest.raises(RuntimeError, match="non-finite"):
        run_normal(pts, tri, body, surface)


def test_bad_parameters_are_rejected():
    pts, tri, body, surface = random_scene(50, 60, 2, 4)
    n = len(pts)
    z = np.zeros(n)
    s = _engine.ContactSolver()
    with pytest.raises(ValueError, match="penalty"):
        s.compute_normal(pts[:, 0], pts[:, 1], z, z, np.ones(n), tri, body, surface, z.copy(),
                         z.copy(), penalty=0.0, mu=0.3, dt=1e-6)
    with pytest.raises(ValueError, match="mu"):
        s.compute_normal(pts[:, 0], pts[:, 1], z, z, np.ones(n), tri, body, surface, z.copy(),
                         z.copy(), penalty=S, mu=-0.1, dt=1e-6)
    with pytest.raises(ValueError, match="fx"):
        s.compute_normal(pts[:, 0], pts[:, 1], z, z, np.ones(n), tri, body, surface,
                         np.zeros(n, dtype=np.float32), z.copy(), penalty=S, mu=0.3, dt=1e-6)
