"""Freeze-bond state: checkpoints (continue bit-identically in a rebuilt
model), thread-count independence, pre-screening delay bound, and input
validation."""
import json
import os
import subprocess
import sys

import numpy as np
import pytest

from icerubble import engine
from icerubble.geometry.bond_points import find_bond_points
from tests.engine.freeze_bonds_scenes import ICE, pull_bar, two_block_bar
from tests.paths import ROOT

SIGMA, TAU, G = 1e4, 5e4, 1.0


def supports(m, nodes):
    """The pull_bar supports on a model built from a checkpoint's node sets."""
    m.fix("left", x=True, y=False)
    m.fix("pin", x=False, y=True)
    m.prescribe_velocity("right", (1, 0), y=False,
                         table=([0.0, 0.02, 0.07, 0.08], [0.0, 1e-4, 1e-4, 4e-3]))


def test_checkpoint_continues_bit_identically():
    """N steps (bond points split and softening), checkpoint, a new Model from
    the checkpoint's mesh with the same supports, restore, M more steps: the
    same positions, velocities and bond state as N + M steps straight."""
    straight, bp, nodes, H = pull_bar(sigma_cr=SIGMA, tau_cr=TAU, G=G, direction="work_conjugate")
    first, _, _, _ = pull_bar(sigma_cr=SIGMA, tau_cr=TAU, G=G, direction="work_conjugate")
    # split at t ~ 0.056 s, full failure at ~ 0.124 s: checkpoint while softening
    dt = straight.params["dt"]
    N, M = int(0.08 / dt), int(0.06 / dt)
    straight.step(N + M)
    first.step(N)
    assert first.bonds.counts["split"] == len(bp) and first.bonds.counts["failed"] == 0
    cp = first.checkpoint()
    again = engine.Model.from_checkpoint(cp, dict(ICE, damping=0.0))
    again.set(gravity=False, penalty=1e9, dt=first.params["dt"])
    supports(again, nodes)
    again.restore_checkpoint(cp)
    assert again.n_nodes == first.n_nodes and again.step_count == N
    again.step(M)
    np.testing.assert_array_equal(again.positions, straight.positions)
    np.testing.assert_array_equal(again.velocities, straight.velocities)
    a, b = again.bonds.state(), straight.bonds.state()
    for k in ("delta_m", "f0", "delta_f", "t_split", "t_fail", "node_plus", "node_minus"):
        np.testing.assert_array_equal(a[k], b[k])
    assert straight.bonds.counts["failed"] > 0  # the continuation went through failures



def test_a_checkpoint_written_just_after_an_energy_reset_continues_the_same_ledger():
    """A run resets its energy ledger as loading starts; a checkpoint written
    then (before a step) starts the restored ledger at its first step too,
    as the run itself does: the same energies, no false alarm. Before, the
    restored ledger counted the whole strain energy of the bar as made from
    nothing and the run stopped ('energy grew without an energy source')."""
    straight, bp, nodes, H = pull_bar(sigma_cr=SIGMA, tau_cr=TAU, G=G, direction="work_conjugate")
    first, _, _, _ = pull_bar(sigma_cr=SIGMA, tau_cr=TAU, G=G, direction="work_conjugate")
    dt = straight.params["dt"]
    N, M = int(0.04 / dt), int(0.06 / dt)   # reset while the bar is strained, before it splits
    for m in (straight, first):
        m.step(N)
        m.reset_energy()
    straight.step(M)
    cp = first.checkpoint()
    again = engine.Model.from_checkpoint(cp, dict(ICE, damping=0.0))
    again.set(gravity=False, penalty=1e9, dt=first.params["dt"])
    supports(again, nodes)
    again.restore_checkpoint(cp)
    assert again.energies()["elastic"] == 0.0   # reset, not yet stepped
    again.step(M)
    a, b = again.energies(), straight.energies()
    assert b["elastic"] > 0 and b["work_boundary"] > 0
    for k in ("initial", "elastic", "kinetic", "work_boundary", "cohesive", "residual"):
        assert a[k] == b[k], k

SCRIPT = r"""
import sys, json
import numpy as np
from icerubble import engine
from tests.engine.freeze_bonds_scenes import bonded
nodes, tri = engine.rectangle_mesh(96, 48, 0.025)
c = nodes[tri].mean(axis=1)
# 24 x 12 blocks of 4 x 4 cells: ~1900 bond points, so the bond passes run threaded too
body = ((c[:, 0] // 0.1) + 24 * (c[:, 1] // 0.1)).astype(np.int32)
m, bp = bonded(nodes, tri, body, sigma_cr=1e4, tau_cr=5e4, G=0.2, direction="paper")
rng = np.random.default_rng(1)
v = np.zeros((m.n_nodes, 2))
for b in range(body.max() + 1):
    v[np.unique(tri[body == b])] = rng.uniform(-0.05, 0.05, 2)
m.set_velocities(v)
m.set(dt=0.9 * m.stable_time_step()["dt"])
m.step(300)
np.save(sys.argv[1], np.hstack([m.positions, m.velocities]))
print(json.dumps(dict(m.bonds.counts, n=int(m.n_triangles))))
"""


def test_one_and_two_threads_agree():
    """A 9216-triangle scene of 288 blocks (~1900 bond points, junctions
    everywhere; every pass threaded) flung apart through splitting and failures, in subprocesses with
    OMP_NUM_THREADS=1 and 2: same result up to round-off (the bond passes sum
    in a fixed order, so in practice bit for bit; 1e-12 relative allowed)."""
    tmp = os.environ.get("TMPDIR", "/tmp")
    out = {}
    script = SCRIPT
    for nt in (1, 2):
        f = os.path.join(tmp, f"freeze_bonds_threads_{os.getpid()}_{nt}.npy")
        env = dict(os.environ, OMP_NUM_THREADS=str(nt))
        r = subprocess.run([sys.executable, "-c", script, f], env=env, capture_output=True,
                           text=True, timeout=300, cwd=ROOT)
        assert r.returncode == 0, r.stderr
        out[nt] = (np.load(f), json.loads(r.stdout.strip().splitlines()[-1]))
        os.remove(f)
    (a, ca), (b, cb) = out[1], out[2]
    assert ca == cb and ca["n"] >= 2048 and ca["points"] >= 1024 and ca["split"] > 0 and ca["failed"] > 0
    np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12 * np.abs(a).max())


def test_prescreening_delays_a_failure_by_less_than_the_interval():
    """A sudden load: the bar at rest is given a stretched configuration in
    one go (t_e jumps from 0 to above sigma_cr). With screen_interval k every
    point was far from the criterion at its last check, so it is caught at
    its next staggered check: at most k - 1 steps late, and counted as a late
    detection. Without screening (k = 1) all split on the first step."""
    k = 8
    steps = {}
    for interval in (1, k):
        m, bp, nodes = two_block_bar(sigma_cr=SIGMA, tau_cr=TAU, G=G, screen_interval=interval)
        # at rest the energies are round-off, too small for the balance guard
        m.set(dt=0.9 * m.stable_time_step()["dt"], check_energy=False)
        m.step(3)  # every point checked, far below the criterion
        stretched = nodes * [1 + 2 * SIGMA / 2.2e9, 1.0]
        m.set_positions(stretched)
        first = m.step_count
        split_at = np.full(len(bp), -1)
        while (split_at < 0).any() and m.step_count < first + 2 * k:
            m.step(1)
            t = m.bonds.events()["t_split"]
            split_at[(split_at < 0) & np.isfinite(t)] = m.step_count - 1
        steps[interval] = split_at - first
        late = m.bonds.counts["late_detections"]
        if interval == 1:
            assert np.all(steps[1] == 0) and late == 0
        else:
            assert np.all((steps[k] >= 0) & (steps[k] <= k - 1)) and steps[k].max() > 0
            # every point was found at a staggered check (possibly late)
            assert late == len(bp)


def test_prescreening_does_not_change_a_slow_run():
    """Slow loading: screened points reach screen_fraction long before the
    criterion, so a run with screening is bit-identical to one without."""
    a, bp, _, _ = pull_bar(sigma_cr=SIGMA, tau_cr=TAU, G=G, screen_interval=1)
    b, _, _, _ = pull_bar(sigma_cr=SIGMA, tau_cr=TAU, G=G, screen_interval=16)
    n = int(0.07 / a.params["dt"])  # every point splits at t ~ 0.056 s
    a.step(n)
    b.step(n)
    assert a.bonds.counts["split"] == len(bp)
    np.testing.assert_array_equal(a.positions, b.positions)
    assert b.bonds.counts["checks"] < 0.6 * a.bonds.counts["checks"]
    assert b.bonds.counts["late_detections"] == 0


def test_bad_bond_input_raises_clear_value_errors():
    nodes, tri = engine.rectangle_mesh(4, 2, 0.1)
    c = nodes[tri].mean(axis=1)
    body = (c[:, 0] > 0.2).astype(np.int32)
    m = engine.Model(nodes, tri, body, ICE)
    bp = find_bond_points(nodes, tri, body, keel_top_y=0.2, keel_depth=1.0, sigma_cr=SIGMA,
                          tau_cr=TAU, G=G)
    with pytest.raises(ValueError, match="direction must be 'paper' or 'work_conjugate'"):
        m.set_bond_points(bp, direction="ortiz")
    with pytest.raises(ValueError, match="screen_interval must be an integer >= 1"):
        m.set_bond_points(bp, screen_interval=0)
    with pytest.raises(ValueError, match=r"screen_fraction must be in \(0, 1\)"):
        m.set_bond_points(bp, screen_fraction=1.5)
    with pytest.raises(ValueError, match="mu must be >= 0"):
        m.set_bond_points(bp, mu=-0.1)
    m.set_bond_points(bp)
    raw = m._m
    args = m._m.bond_input()
    bad = dict(args, sigma_cr=-args["sigma_cr"])
    with pytest.raises(ValueError, match="sigma_cr must be > 0 Pa"):
        raw.set_bonds(*[bad[k] for k in ("node", "sigma_cr", "tau_cr", "G", "pair_point",
                                         "body_minus", "body_plus", "nx", "ny", "length",
                                         "frame_p", "frame_q")])
    wrong_body = dict(args, body_plus=np.zeros_like(args["body_plus"]))
    with pytest.raises(ValueError, match="two different bodies"):
        raw.set_bonds(*[wrong_body[k] for k in ("node", "sigma_cr", "tau_cr", "G", "pair_point",
                                                "body_minus", "body_plus", "nx", "ny",
                                                "length", "frame_p", "frame_q")])
    far = dict(args, node=np.array([0, 1, 2]))  # nodes not on the interface
    with pytest.raises(ValueError, match="must both have triangles at node"):
        raw.set_bonds(*[far[k] for k in ("node", "sigma_cr", "tau_cr", "G", "pair_point",
                                         "body_minus", "body_plus", "nx", "ny", "length",
                                         "frame_p", "frame_q")])
