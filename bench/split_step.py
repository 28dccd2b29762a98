"""The cost of a step in which bond points split (not a test; issue 28,
docs/gpu.md). Writes bench/results/split_step.json.

    python3 bench/split_step.py [--mesh MESH.h5] [--threads 1 2] [--steps 12]

A split changes the mesh: the model rebuilds its topology, masses, mass
scaling and stable step before the next step. The GPU backend leaves such a
step to the model on the host (a host step, then the stages made again), so
on a GPU this cost is paid once per step with a split, thousands of times in
a paper run. For each thread count, on a model of its own: the load phase's
plain step, then the steps right after the nudge that opens the paper mesh's
bond points (gpu_body_forces.open_pairs_by_nudge: ~2,900 points split in 20
steps), in which points still reach eq 5 (10-30 a step): their mean wall
time and splits per step.
"""
import argparse
import os
import time

import result_file
from gpu_body_forces import load_phase_model, open_pairs_by_nudge

from icerubble.code_identity import code_version, source_hash
from icerubble.files.mesh_file import read_mesh
from icerubble.machine import processor
from icerubble.run.scene_cache import scene_files

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "bench", "results", "split_step.json")


def measure(mesh, scene, preset, threads, steps):
    m = load_phase_model(mesh, scene, preset, threads)
    m.step(20)
    w0 = time.perf_counter()
    m.step(steps)
    plain = (time.perf_counter() - w0) / steps
    open_pairs_by_nudge(m)
    walls, splits = [], []
    for _ in range(steps):
        before = m.bonds.counts["split"]
        w0 = time.perf_counter()
        m.step(1)
        walls.append(time.perf_counter() - w0)
        splits.append(m.bonds.counts["split"] - before)
    split_walls = [w for w, s in zip(walls, splits) if s > 0]
    return dict(threads=threads, plain_ms=1e3 * plain, split_steps=len(split_walls),
                split_step_ms=1e3 * sum(split_walls) / max(len(split_walls), 1),
                splits_per_step=sum(splits) / max(len(split_walls), 1))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mesh", default=None,
                    help="a scene's mesh file; default: the paper scene's ridge 1 (meshed into runs/scenes "
                         "if it is not there, minutes)")
    ap.add_argument("--scene", default="paper", help="the scene whose parameters it runs with")
    ap.add_argument("--preset", default="fast")
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--steps", type=int, default=12, help="steps timed, plain and with splits")
    ap.add_argument("--out", default=OUT)
    ap.add_argument("--quick", action="store_true", help="6 steps timed")
    a = ap.parse_args(argv)
    if a.quick:
        a.steps = 6
    if a.steps < 1:
        ap.error(f"--steps must be at least 1, got {a.steps}")
    if a.mesh is None:
        a.mesh = scene_files("paper", 1, root=os.path.join(ROOT, "runs"))[1]
    mesh = read_mesh(a.mesh)
    rows = []
    for k in a.threads:
        r = measure(mesh, a.scene, a.preset, k, a.steps)
        rows.append(r)
        print(f"{k:3d} threads: plain step {r['plain_ms']:.1f} ms; a step with splits {r['split_step_ms']:.1f} ms "
              f"({r['split_steps']} steps, {r['splits_per_step']:.0f} points split a step)", flush=True)
    result_file.write(a.out, dict(mesh=os.path.basename(a.mesh), scene=a.scene, preset=a.preset,
                                  n_triangles=len(mesh["triangles"]), processor=processor(),
                                  cpu_count=os.cpu_count(), code_version=code_version(),
                                  source_hash=source_hash(), measured=time.strftime("%Y-%m-%d"), rows=rows))


if __name__ == "__main__":
    main()
