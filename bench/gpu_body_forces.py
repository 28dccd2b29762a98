"""The engine's step cost by thread count, and its body-force stage on the
GPU (not a test; docs/gpu.md). Writes bench/results/gpu_body_forces.json.

    python3 bench/gpu_body_forces.py [--mesh MESH.h5] [--scene paper] [--threads 1 2 4 8 16]

For each thread count, timed in blocks with the counts in turn (--rounds):
the ms per step of the load phase (water, drag,
contact, held layer top, driven indenter; the `fast` preset's numerics) and
its parts (elements with the water loads and the node gather; contact
detection; contact forces and friction; bonds; integration). Then, where the
GPU backend runs: the body-force stage's time on the GPU (a CUDA graph of its
launches, device events) against the elements part of one CPU step, and
whether its fields equal the CPU's bits at the same state. Then (unless
--loaded-steps 0) the same by thread count on a loaded state: the load phase
has a few dozen touching pairs, a loaded pile ~1,000 (open_pairs_by_nudge,
then --settle-steps so that its splits are over), where friction's serial
sweeps are a part the elements' threads do not shrink. Then the node
update's, the normal contact pass's and the bond check's times on the GPU,
and last the wall time of whole GPU steps (gpu.Steps) of the load phase.
The JSON is written after the CPU's parts and again at the end ("complete"
false until then), so a run stopped by a lease's cap keeps what it measured.
"""
import argparse
import os
import re
import subprocess
import time

import numpy as np

import result_file

from icerubble import _engine, parameters as P
from icerubble.engine import gpu
from icerubble.code_identity import code_version, source_hash
from icerubble.machine import cpu_topology, processor
from icerubble.files.mesh_file import read_mesh
from icerubble.run.presets import NUMERICS, scene
from icerubble.run.scene_cache import scene_files
from icerubble.run.loading import smooth_ramp_table
from icerubble.run.scene import Scene

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.join(ROOT, "bench", "results", "gpu_body_forces.json")
PARTS = ("elements", "drag", "contact_detection", "contact_forces", "friction", "bonds", "integration")


def load_phase_model(mesh, scene_name, preset, threads):
    params = P.validate(dict(scene(scene_name)["params"]))
    numerics = NUMERICS[scene_name][preset]
    m = Scene(mesh, params, threads=threads).model
    m.set(contact_reach=numerics.get("contact_reach", float("inf")),
          mass_scaling_dt=numerics.get("mass_scaling_dt") or 0.0)
    m.set(dt_fraction=numerics["dt_fraction"])
    m.fix("layer_top")
    t, v = smooth_ramp_table(0.0, params["v_final"], params["ramp_time"])
    m.prescribe_velocity("indenter_top", direction=(0.0, -1.0), table=(t, v))
    return m


def open_pairs_by_nudge(m):
    """Every node of `m` nudged by up to 0.1 mm (as tools/gpu_check.py nudges
    them), bond failure checked, 20 steps: ~2,800 points of the paper mesh
    pass eq 5 and split (a topology change each: ~0.1 s a step on the CPU),
    their pairs opened, the splits over."""
    xy = m.positions
    m.set_positions(xy + np.random.default_rng(1).uniform(-1e-4, 1e-4, xy.shape))
    m.set_bond_params(check_failure=True)
    m.step(20)


def per_step(m, steps):
    t0 = m.timings()
    w0 = time.perf_counter()
    m.step(steps)
    wall = (time.perf_counter() - w0) / steps
    t1 = m.timings()
    return dict(ms_per_step=1e3 * wall, **{p + "_ms": 1e3 * (t1[p] - t0[p]) / steps for p in PARTS})


def by_threads(m, threads, steps, rounds):
    """ms per step and per part for each thread count, the `steps` of each
    taken in `rounds` blocks, the thread counts in turn in each round: every
    count sees the same stretch of the run (a loaded state's touching pairs
    grow from step to step) and the same spells of a shared machine's
    slowness. Two untimed steps after each change of the count (its gather
    plan is made again). Also the touching pairs after each block, averaged."""
    block = max(1, steps // rounds)
    sums = {k: dict(wall=0.0, steps=0, touching=0, busy=np.zeros(k), wait=np.zeros(k), **{p: 0.0 for p in PARTS})
            for k in threads}
    for _ in range(rounds):
        for k in threads:
            m.set(threads=k)
            m.step(2)
            t0, w0 = m.timings(), time.perf_counter()
            m.step(block)
            w, t1, acc = time.perf_counter() - w0, m.timings(), sums[k]
            acc["wall"] += w
            acc["steps"] += block
            acc["touching"] += int(m.touching_pairs)
            for p in PARTS:
                acc[p] += t1[p] - t0[p]
            # the element pass by thread (a team of one below 2,048 triangles); the lists grow with
            # the team, i.e. in the untimed steps above, so t0's and t1's are as long
            for w in ("busy", "wait"):
                spent = np.asarray(t1["element_" + w]) - np.asarray(t0["element_" + w])
                n = min(k, len(spent))
                acc[w][:n] += spent[:n]
    rows = []
    for k in threads:
        acc = sums[k]
        rows.append(dict(threads=k, ms_per_step=1e3 * acc["wall"] / acc["steps"], steps=acc["steps"], rounds=rounds,
                         touching_pairs=round(acc["touching"] / rounds),
                         # each thread's time in the element pass: its own triangles, and waiting for the others
                         element_busy_ms=[1e3 * x / acc["steps"] for x in acc["busy"]],
                         element_wait_ms=[1e3 * x / acc["steps"] for x in acc["wait"]],
                         **{p + "_ms": 1e3 * acc[p] / acc["steps"] for p in PARTS}))
    return rows


def element_pass(r):
    """A row's element pass by thread, in words: the busiest thread's time
    against the mean (1 = balanced), and the mean wait at its barrier."""
    busy, wait = np.asarray(r["element_busy_ms"]), np.asarray(r["element_wait_ms"])
    if not busy.size or not busy.mean() > 0.0:
        return "element pass by thread: not timed"
    return (f"element pass by thread: busy mean {busy.mean():.3f} max {busy.max():.3f} ms, "
            f"wait mean {wait.mean():.3f} ms")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mesh", default=None,
                    help="a scene's mesh file (runs/scenes/*_mesh.h5); default: the paper scene's ridge 1, "
                         "meshed from its shipped pile into runs/scenes if it is not there (minutes)")
    ap.add_argument("--scene", default="paper", help="the scene whose parameters it runs with")
    ap.add_argument("--preset", default="fast")
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--warmup", type=int, default=50)
    ap.add_argument("--repeats", type=int, default=2000, help="GPU evaluations timed")
    ap.add_argument("--loaded-steps", type=int, default=100,
                    help="steps timed per thread count on the loaded state (0: not measured)")
    ap.add_argument("--settle-steps", type=int, default=300,
                    help="steps after the nudge before the loaded state is timed (its splits over)")
    ap.add_argument("--rounds", type=int, default=5,
                    help="blocks each thread count's steps are timed in, the counts in turn (a shared machine's "
                         "speed drifts, a loaded state's pairs grow)")
    ap.add_argument("--triad", help="a compiled bench/stream_triad.cpp: the memory bandwidth by thread count")
    ap.add_argument("--out", default=OUT)
    ap.add_argument("--quick", action="store_true", help="100 steps and 200 GPU evaluations timed")
    a = ap.parse_args(argv)
    if a.rounds < 1 or a.steps < a.rounds or (a.loaded_steps and a.loaded_steps < a.rounds):
        ap.error("--rounds must be >= 1 and at most --steps (and --loaded-steps, unless 0)")
    if a.quick:
        a.steps, a.repeats = 100, 200
    if a.mesh is None:
        a.mesh = scene_files("paper", 1, root=os.path.join(ROOT, "runs"))[1]
    mesh = read_mesh(a.mesh)
    m = load_phase_model(mesh, a.scene, a.preset, a.threads[0])
    m.step(a.warmup)
    rows = by_threads(m, a.threads, a.steps, a.rounds)
    for r in rows:
        parts = "  ".join(f"{p} {r[p + '_ms']:.3f}" for p in PARTS)
        print(f"{r['threads']:3d} threads: {r['ms_per_step']:.3f} ms/step ({parts}; {element_pass(r)})", flush=True)
    out = dict(mesh=os.path.basename(a.mesh), scene=a.scene, preset=a.preset, n_triangles=m.n_triangles,
               n_nodes=m.n_nodes, processor=processor(), cpu_count=os.cpu_count(), cpu_topology=cpu_topology(),
               code_version=code_version(), source_hash=source_hash(), measured=time.strftime("%Y-%m-%d"), cpu=rows, gpu=None,
               complete=False)
    if a.loaded_steps > 0:
        loaded = load_phase_model(mesh, a.scene, a.preset, a.threads[-1])
        loaded.step(20)
        open_pairs_by_nudge(loaded)
        loaded.step(a.settle_steps)
        split = loaded.bonds.counts["split"]
        out["cpu_loaded"] = by_threads(loaded, a.threads, a.loaded_steps, a.rounds)
        splits = int(loaded.bonds.counts["split"] - split)  # over all the timed blocks
        for r in out["cpu_loaded"]:
            r["splits"] = splits
            parts = "  ".join(f"{p} {r[p + '_ms']:.3f}" for p in PARTS)
            print(f"{r['threads']:3d} threads, loaded (~{r['touching_pairs']} touching pairs, {splits} splits in "
                  f"all the blocks): {r['ms_per_step']:.3f} ms/step ({parts}; {element_pass(r)})", flush=True)
        del loaded
    if a.triad:
        text = subprocess.run([a.triad] + [str(k) for k in a.threads], capture_output=True, text=True,
                              check=True).stdout
        print(text, end="")
        out["triad_GBps"] = [dict(mb_per_array=float(mb), threads=int(k), GBps=float(g)) for mb, k, g in
                             re.findall(r"triad\s+([\d.]+) MB per array,\s+(\d+) threads:\s+([\d.]+) GB/s", text)]
    result_file.write(a.out, out)   # the CPU's parts, kept if the GPU's are cut short
    if gpu.available():
        cmp = gpu.compare(m)
        stage = gpu.BodyForces(m)
        s = stage.seconds_per_run(a.repeats)
        parts = {k: 1e6 * v for k, v in stage.stage_seconds(max(a.repeats // 10, 10)).items()}
        update_us = 1e6 * gpu.NodeUpdate(m).seconds_per_run(a.repeats)
        contact = gpu.ContactNormal(m)
        contact_us = 1e6 * contact.seconds_per_run(a.repeats)
        bond_us = 1e6 * gpu.BondCheck(m).seconds_per_run(a.repeats)
        # the candidate list's search (a list rebuild): on the GPU, its wait for
        # the count included, against the CPU's search and layout on one thread
        m._m.prepare()
        search_us = 1e6 * _engine.DeviceBroadPhase(m._m).seconds_per_search(m._m, a.repeats)
        w0 = time.perf_counter()
        for _ in range(3):
            _engine.broad_phase_layout(m._m)
        search_cpu_ms = 1e3 * (time.perf_counter() - w0) / 3
        m.evaluate()   # the friction's input: the forces before it, the touching pairs, the warm start
        friction = gpu.Friction(m)
        friction_us = 1e6 * friction.seconds_per_run(a.repeats)
        friction_fields = friction.fields()
        friction_colours, friction_pairs = int(friction_fields["colours"]), len(friction_fields["lambda"])
        out["gpu"] = dict(device=gpu.device_name(), body_forces_us=1e6 * s, stages_us=parts, compare=cmp,
                          node_update_us=update_us, contact_normal_us=contact_us,
                          contact_candidates=contact.candidates, bond_check_us=bond_us,
                          bond_points_intact=int(m.bonds.counts["points"] - m.bonds.counts["split"]),
                          friction_us=friction_us, friction_pairs=friction_pairs,
                          friction_colours=friction_colours, search_us=search_us, search_cpu_ms=search_cpu_ms)
        print(f"GPU {gpu.device_name()}: body-force stage {1e6 * s:.1f} us per evaluation "
              f"({m.n_triangles / s / 1e9:.2f} G triangles/s); launched one by one: "
              + ", ".join(f"{k} {v:.1f}" for k, v in parts.items()) + " us")
        print(f"  node update (central difference, ledger sums) {update_us:.1f} us; against {a.threads[-1]} "
              f"threads' integration part {rows[-1]['integration_ms']:.3f} ms")
        print(f"  normal contact ({contact.candidates} candidates) {contact_us:.1f} us; against {a.threads[-1]} "
              f"threads' contact forces part {rows[-1]['contact_forces_ms']:.3f} ms (friction included)")
        print(f"  contact search (a list rebuild, laid out) {search_us:.1f} us; against the CPU's on one thread "
              f"{search_cpu_ms:.2f} ms")
        print(f"  friction ({friction_pairs} touching pairs of {friction.candidates} candidates, in "
              f"{friction_colours} colours) {friction_us:.1f} us")
        print(f"  bond check ({out['gpu']['bond_points_intact']} intact points, all of them) {bond_us:.1f} us; "
              f"against {a.threads[-1]} threads' bonds part {rows[-1]['bonds_ms']:.3f} ms (screened, and the "
              f"cohesive forces)")
        # last, as it splits bond points: the cohesive forces of the pairs the
        # nudge opens, against the CPU's bonds part over the same steps
        open_pairs_by_nudge(m)
        cpu_coh = dict(threads=a.threads[-1], **per_step(m, 20))
        m._m.evaluate_before_cohesive()
        coh = gpu.CohesiveForces(m)
        out["gpu"].update(cohesive_us=1e6 * coh.seconds_per_run(a.repeats), cohesive_pairs=int(coh._d.open_pairs),
                          cohesive_points_split=int(m.bonds.counts["split"]), cohesive_cpu=cpu_coh)
        m.evaluate()
        print(f"  cohesive forces ({coh._d.open_pairs} opened pairs) {out['gpu']['cohesive_us']:.1f} us; against "
              f"{a.threads[-1]} threads' bonds part {cpu_coh['bonds_ms']:.3f} ms (check and cohesive forces)")
        result_file.write(a.out, out)   # the stages' figures, kept if the whole steps are cut short
        # whole steps on the GPU (gpu.Steps) from here: the load phase with its
        # opened pairs, the preset's contact reach; steps the model takes itself
        # (list rebuilds, splits) counted and timed with them (wall clock)
        try:
            steps = gpu.Steps(m)
            steps.step(a.warmup)
            h0, w0 = steps.host_steps, time.perf_counter()
            hs0, ms0 = steps.host_step_seconds, steps.make_seconds
            l0, ls0 = steps.list_rebuilds, steps.list_seconds
            gi0, gu0 = steps.graph_instantiations, steps.graph_updates
            steps.step(a.steps * 10)
            whole_us = 1e6 * (time.perf_counter() - w0) / (a.steps * 10)
            out["gpu"].update(whole_step_us=whole_us, whole_steps=a.steps * 10,
                              whole_host_steps=int(steps.host_steps - h0),
                              whole_host_step_s=steps.host_step_seconds - hs0, whole_make_s=steps.make_seconds - ms0,
                              whole_list_rebuilds=int(steps.list_rebuilds - l0), whole_list_s=steps.list_seconds - ls0,
                              whole_graph_instantiations=int(steps.graph_instantiations - gi0),
                              whole_graph_updates=int(steps.graph_updates - gu0))
            print(f"  whole steps {whole_us:.1f} us per step over {a.steps * 10} steps "
                  f"({steps.host_steps - h0} of them the model's own (splits), "
                  f"{steps.host_step_seconds - hs0:.2f} s; the stages made again {steps.make_seconds - ms0:.2f} s; "
                  f"{steps.list_rebuilds - l0} candidate lists rebuilt in place, {steps.list_seconds - ls0:.2f} s; "
                  f"graphs instantiated {steps.graph_instantiations - gi0}, updated in place "
                  f"{steps.graph_updates - gu0}); against "
                  + ", ".join(f"{r['threads']} threads {r['ms_per_step']:.3f} ms" for r in rows))
        except Exception as e:   # the newest code: reported, the figures above kept
            out["gpu"]["whole_step_error"] = f"{type(e).__name__}: {e}"
            print(f"  whole steps: FAILED: {type(e).__name__}: {e}")
        for r in rows:
            print(f"  against {r['threads']:2d} threads' elements part {r['elements_ms']:.3f} ms: "
                  f"{r['elements_ms'] * 1e-3 / s:.0f}x")
        print(f"  as the CPU: {'yes' if cmp['ok'] else 'NO'} ({cmp})")
    else:
        print(f"GPU: {gpu.why_unavailable()}")
    out["complete"] = True
    result_file.write(a.out, out)


if __name__ == "__main__":
    main()
