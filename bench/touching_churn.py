"""How often a loaded pile's touching pairs change from one step to the next
(the GPU's friction keeps a step's colouring while they do not, docs/gpu.md
"Friction"), and how many islands they form (pairs joined through shared
nodes, which the CPU's threads share, docs/gpu.md "The CPU engine on a
workstation"): the paper scene loaded from bench/paper_peak.py's rest state
(ridge 1, `fast`), stepped one step at a time over windows of its load, the
touching pairs (the friction's warm-start keys) compared after each step.
Writes bench/results/touching_churn.json.

    /usr/bin/python3 bench/touching_churn.py [--rest PATH] [--windows 0 100000 200000 300000] [--steps 3000]

The rest state is paper_peak.py's (its --settle-only makes it: ~30 min on 2
cores); the steps before a window run as a load does (~30 min for 300,000 on
2 cores)."""
import argparse
import os
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [ROOT, os.path.join(ROOT, "bench")]
import result_file  # noqa: E402
from icerubble import _engine  # noqa: E402

OUT = os.path.join(ROOT, "bench", "results", "touching_churn.json")
REST = os.path.join(ROOT, "runs", "bench", "paper_peak", "ridge1_2mm", "rest_fast.checkpoint.h5")


def touching_keys(model):
    return np.sort(np.asarray(model._m.contact_warm_start()[0]))


def islands(model):
    """The touching pairs' islands (pairs joined through shared nodes; the
    CPU's threads share them, contact/friction_islands.hpp): their count and
    the largest's size."""
    keys = np.asarray(model._m.contact_warm_start()[0], dtype=np.uint64)
    if len(keys) == 0:
        return 0, 0
    tri = np.asarray(model.triangles)
    a, b = (keys >> np.uint64(32)).astype(np.int64), (keys & np.uint64(0xFFFFFFFF)).astype(np.int64)
    nodes = np.concatenate([tri[a], tri[b]], axis=1)
    of_pair = _engine.friction_islands(nodes.astype(np.int32), len(model.positions))["of_pair"]
    return int(of_pair.max()) + 1, int(np.bincount(of_pair).max())


def window(model, steps):
    """`steps` steps one at a time: the touching pairs' counts and the steps where they changed."""
    prev, changed, counts, gaps, last = touching_keys(model), 0, [], [], 0
    for i in range(1, steps + 1):
        model.step(1)
        k = touching_keys(model)
        counts.append(len(k))
        if not np.array_equal(k, prev):
            changed += 1
            gaps.append(i - last)
            last = i
        prev = k
    q = np.percentile(gaps, [10, 50, 90]).tolist() if gaps else []
    n_islands, largest = islands(model)
    return dict(steps=steps, touching_min=int(min(counts)), touching_max=int(max(counts)),
                steps_changed=changed, steps_between_changes_p10_p50_p90=q, touching_at_end=len(prev),
                islands_at_end=n_islands, largest_island_at_end=largest)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rest", default=REST, help="the rest state (bench/paper_peak.py --settle-only)")
    ap.add_argument("--windows", type=int, nargs="+", default=[0, 100000, 200000, 300000],
                    help="load steps before each window (ascending)")
    ap.add_argument("--steps", type=int, default=3000, help="steps of each window")
    ap.add_argument("--out", default=OUT)
    a = ap.parse_args(argv)
    if not os.path.exists(a.rest):
        raise SystemExit(f"touching_churn: no rest state {a.rest}: make it with "
                         "/usr/bin/python3 bench/paper_peak.py --settle-only (~30 min)")
    if a.steps < 2 or any(w < 0 for w in a.windows) or a.windows != sorted(a.windows):
        raise SystemExit("touching_churn: --steps must be >= 2 and --windows ascending, each >= 0")
    from paper_peak import variant_options
    from icerubble.run import checkpoint as ckpt
    from icerubble.run.presets import scene
    from icerubble.run.punch_through_run import PunchThrough
    from icerubble.run.scene_cache import scene_files
    _, mesh = scene_files("paper", 1)
    params = dict(scene("paper")["params"], target_travel=2e-3)
    with tempfile.TemporaryDirectory() as d:
        run = PunchThrough(mesh, os.path.join(d, "churn.h5"), params, variant_options("fast"))
        ckpt.restore(run, a.rest, from_rest=True)
        m = run.model
        rows, done, t0 = [], 0, time.time()
        for w in a.windows:
            m.step(w - done)
            done = w
            row = dict(load_steps_before=w, points_split=int(m.bonds.counts["split"]), **window(m, a.steps))
            done += a.steps
            rows.append(row)
            print(row, flush=True)
    result_file.write(a.out, dict(scene="paper", ridge=1, preset="fast", rest_state=os.path.basename(a.rest),
                                  windows=rows, wall_s=time.time() - t0))


if __name__ == "__main__":
    main()
