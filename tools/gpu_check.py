"""The GPU backend against the CPU engine (docs/gpu.md): run by
tools/gpu_check.sh on a machine with a CUDA GPU, after building there.

Checks, each printed with its outcome:
  1. random states (fresh seeds, printed) of a floating three-block scene
     straddling the water line, with damping, viscosity and each drag model:
     the body-force stage's element and buoyancy fields equal the CPU's bits;
     what it sums per body or over the mesh in another order (quadratic drag,
     the strain energy) the CPU's to round-off;
  2. the same on each --mesh after --steps CPU steps of the load phase (the
     scene's own parameters) and again after a random nudge of every node;
  3. the GPU gives the same bits on a second run (no atomics in any sum);
  4. the node update (central difference and the ledger's sums) on the GPU
     from the forces of the CPU's evaluation against the CPU's step: positions
     and velocities bit for bit, the ledger's terms to round-off;
  5. the normal contact pass (the pair kernel over the CPU's candidates, each
     node's sum in the CPU's order) on pressed blocks and each mesh: the
     contact forces bit for bit, the touching pairs alike, their energy to
     round-off;
  6. the bond check (eqs 5-7) of every intact point on a bonded square and
     each mesh: ratios and tractions the CPU's bits, the same split plan.
  7. friction (eq 4) over the CPU's candidate list: the touching pairs found,
     coloured and solved on the GPU from the CPU's warm start, on rubbing
     blocks and each mesh: the CPU's touching pairs and colour for every pair,
     tangential forces and node forces bit for bit, the power to round-off;
  8. the cohesive forces (eqs 8-12) of the opened pairs of a bonded square,
     for both force directions, just split (rigid phase), softening and failing,
     and of each mesh 20 steps after its points at the criterion split: per
     pair and per node the CPU's bits, the energy sums to round-off;
  9. whole steps on the GPU (gpu.Steps) of a driven block (one body), each
     drag model, 2,000 steps, and of a block sliding on a slab (contact and
     friction; its candidate list rebuilt in steps the model takes itself),
     4,000 steps, against the CPU's: positions,
     velocities and the clock the CPU's bits (quadratic drag: its per-body
     sums to round-off, so the trajectory within 1e-9 of the largest entry of
     each field), the ledger and the
     driven nodes' reaction to round-off; and the GPU's time per step;
 10. whole steps of bonded models: a bar pulled apart (each force direction,
     14,000 steps: its points split in steps the model takes, its pairs
     soften and fail on the GPU) and a square sheared along its bond (3,000
     steps: failures in shear, crack closure): the same as 9, and the bond
     state (split and failure records, the pairs' history, the screening
     flags, the points evaluated) the CPU's bits, the bonds' energy sums to
     round-off;
 11. a model on device 'cuda' (Model.step) against the CPU, in chunks as a
     run steps it: the same bits;
 12. the demo's punch-through (ridge 1, `fast` numerics) settled and loaded
     to --demo-travel on device 'cuda' against the CPU, through the study's
     own run (study.line.run_one), from the demo's pile and mesh in
     --demo-scenes DIR/scenes (made by `make demo`, or carried): the time at
     rest and the bond points split the CPU's, the force record within 0.5 %
     of the CPU's first peak at every sample (the GPU sums the ledger, whose
     work gives F, in another order), and each run's wall time.
Exit status 1 if any check fails.
"""
import argparse
import os
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [ROOT, os.path.join(ROOT, "bench")]
from icerubble.engine import gpu  # noqa: E402
from tests.engine.gpu_scenes import (bonded_square, driven_block, floating_blocks, opened_square,  # noqa: E402
                                    pressed_blocks, pulled_bar, rubbing_blocks, sheared_square, sliding_block,
                                    landing_block_and_a_flyer, scattered_blocks)



def report(name, cmp):
    differ = {k: cmp[k][0] for k in gpu.EXACT_FIELDS if cmp[k][0]}
    summed = ", ".join(f"{k} {cmp[k][1]:.1e}" for k in gpu.SUMMED_FIELDS + ("elastic_energy",))
    detail = "element and buoyancy fields the CPU's bits" if not differ else f"entries differing: {differ}"
    print(f"[{'ok' if cmp['ok'] else 'FAIL'}] {name}: {detail}; summed in another order: {summed} relative",
          flush=True)
    return cmp["ok"]


def report_update(name, cmp):
    if cmp is None:
        print(f"[--] {name}: a bond point split in that step (other forces than the evaluation's): not compared")
        return True
    differ = {k: cmp[k][0] for k in ("x", "y", "vx", "vy") if cmp[k][0]}
    detail = "positions and velocities the CPU's bits" if not differ else f"entries differing: {differ}"
    print(f"[{'ok' if cmp['ok'] else 'FAIL'}] {name}, update: {detail}; ledger terms {cmp['ledger']:.1e} relative",
          flush=True)
    return cmp["ok"]


def report_contact(name, cmp):
    differ = {k: cmp[k][0] for k in ("f_con_x", "f_con_y") if cmp[k][0]}
    detail = "contact forces the CPU's bits" if not differ else f"entries differing: {differ}"
    print(f"[{'ok' if cmp['ok'] else 'FAIL'}] {name}, contact: {detail}; touching pairs {cmp['touching']}; "
          f"energy {cmp['energy_rel']:.1e} relative", flush=True)
    return cmp["ok"]


def report_bonds(name, cmp):
    differ = {k: cmp[k] for k in ("ratio", "tn", "tt") if cmp[k]}
    detail = "ratios and tractions the CPU's bits" if not differ else f"entries differing: {differ}"
    print(f"[{'ok' if cmp['ok'] else 'FAIL'}] {name}, bond check: {detail}; split plan {cmp['plan']} points, "
          f"{'the same' if cmp['same_plan'] else 'DIFFERENT'}", flush=True)
    return cmp["ok"]


def report_friction(name, cmp):
    differ = {k: cmp[k][0] for k in ("lambda", "f_x", "f_y") if cmp[k][0]}
    detail = "tangential forces and node forces the CPU's bits" if not differ else f"entries differing: {differ}"
    colours = "the CPU's colours" if cmp["colour"] == 0 else f"{cmp['colour']} pairs in another colour"
    print(f"[{'ok' if cmp['ok'] else 'FAIL'}] {name}, friction: {detail}; touching pairs {cmp['pairs']}, {colours} "
          f"({cmp['colours']}, coloured in {cmp['rounds']} rounds); power {cmp['power_rel']:.1e} relative", flush=True)
    return cmp["ok"]


def report_search(name, cmp):
    print(f"[{'ok' if cmp['same'] else 'FAIL'}] {name}, contact search: "
          f"{'the CPU' + chr(39) + 's candidates and layout' if cmp['same'] else 'candidates or layout DIFFER'} "
          f"(candidates CPU {cmp['candidates'][0]}, GPU {cmp['candidates'][1]}; skin {cmp['skin'][1]:.3g} m)",
          flush=True)
    return cmp["same"]


def report_cohesive(name, cmp):
    differ = {k: cmp[k][0] for k in gpu.COHESIVE_EXACT if cmp[k][0]}
    detail = "forces, openings and failures the CPU's bits" if not differ else f"entries differing: {differ}"
    sums = max(cmp[k][1] for k in gpu.COHESIVE_SUMMED)
    print(f"[{'ok' if cmp['ok'] else 'FAIL'}] {name}, cohesive forces ({cmp['pairs']} opened pairs): {detail}; "
          f"energy sums {sums:.1e} relative", flush=True)
    return cmp["ok"]


def report_steps(name, cmp, exact):
    differ = {k: cmp[k] for k in ("x", "y", "vx", "vy") if cmp[k][0]}
    detail = "positions and velocities the CPU's bits" if not differ else f"differing (entries, relative): {differ}"
    ok = cmp["ok"] if exact else (max(cmp[k][1] for k in ("x", "y", "vx", "vy")) <= 1e-9 and cmp["time"])
    bonds = ""
    if "bonds" in cmp:
        ok = ok and not cmp["bonds"] and cmp["bond_sums"] <= gpu.ROUND_OFF and cmp["checks"]
        bonds = (f"; bonds (split, failed) CPU {cmp['bond_counts'][0]}, GPU {cmp['bond_counts'][1]}, "
                 f"{'state the CPU bits' if not cmp['bonds'] else 'fields differing: ' + ', '.join(cmp['bonds'])}, "
                 f"sums {cmp['bond_sums']:.1e} relative, points evaluated {'equal' if cmp['checks'] else 'DIFFER'}")
    print(f"[{'ok' if ok else 'FAIL'}] {name}: {detail}; ledger {cmp['ledger']:.1e}, reaction {cmp['reaction']:.1e} "
          f"relative; clock {'equal' if cmp['time'] else 'DIFFERS'}; {cmp['host_steps']} steps taken by the model, "
          f"{cmp['list_rebuilds']} candidate lists rebuilt in place"
          f"{bonds}", flush=True)
    return ok


def demo_run(scenes_dir, travel, device, out_dir):
    """The demo's run on device (cpu or cuda) in out_dir (its pile and mesh
    copied from scenes_dir/scenes): the result's path, or None where no demo
    scene is there."""
    import shutil

    from icerubble.run.scene_cache import scene_paths
    from icerubble.study.line import run_one
    files = scene_paths("demo", 1, root=scenes_dir)   # only where made: the check makes no pile
    if not all(os.path.exists(f) for f in files):
        return None
    os.makedirs(os.path.join(out_dir, "scenes"), exist_ok=True)
    for f in files:
        shutil.copy(f, os.path.join(out_dir, "scenes"))
    return run_one("demo", 1, overrides=dict(target_travel=travel), out_dir=out_dir, description=f"demo_{device}",
                   numerics_name="fast", share_rest=False, device=device)


def read_demo(path):
    """A demo run's record, and its wall time as the run recorded it (settle and loading)."""
    import h5py
    with h5py.File(path, "r") as h:
        return dict(y=h["force/y_I"][()], F=h["force/F"][()], settle=float(h.attrs["settle_time"]),
                    F_rest=float(h.attrs["F_at_rest"]), split=int(np.isfinite(h["bonds/y_I_split"][()]).sum()),
                    wall=float(h.attrs["wall_settle_s"]) + float(h.attrs["wall_load_s"]))


def check_demo(scenes_dir, travel, cpu_result=None):
    """12.: the demo's run on 'cpu' and on 'cuda' (a fresh folder each):
    True if they agree. cpu_result: the CPU's run made beforehand by this
    code with the same travel (--demo-cpu-run; e.g. beside the checks above,
    on cores of its own), instead of running it here."""
    import tempfile
    runs = {}
    with tempfile.TemporaryDirectory() as tmp:
        for device in ("cpu", "cuda"):
            path = cpu_result if device == "cpu" and cpu_result else \
                demo_run(scenes_dir, travel, device, os.path.join(tmp, device))
            if path is None:
                print(f"[--] demo run skipped: no demo pile and mesh in {scenes_dir}/scenes (make demo there, or "
                      "carry runs/scenes/demo_ridge1_*)", flush=True)
                return True
            runs[device] = read_demo(path)
    c, g = runs["cpu"], runs["cuda"]
    peak = float(np.max(c["F"]))
    same_record = c["y"].shape == g["y"].shape and np.array_equal(c["y"], g["y"])
    dev = float(np.max(np.abs(g["F"] - c["F"]))) / peak if same_record else float("inf")
    ok = same_record and dev <= 0.005 and c["settle"] == g["settle"] and c["split"] == g["split"]
    print(f"[{'ok' if ok else 'FAIL'}] demo to {travel * 1e3:g} mm, 'cuda' against 'cpu': at rest after "
          f"{g['settle']:.4f} / {c['settle']:.4f} s, F at rest {g['F_rest']:.2f} / {c['F_rest']:.2f} N/m, first peak "
          f"{np.max(g['F']) / 1e3:.3f} / {peak / 1e3:.3f} kN/m, largest difference of F {100 * dev:.2g} % of it, "
          f"points split {g['split']} / {c['split']}; wall {g['wall']:.0f} / {c['wall']:.0f} s", flush=True)
    return ok


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mesh", nargs="*", default=[], help="scene mesh files (runs/scenes/*_mesh.h5)")
    ap.add_argument("--scene", nargs="*", default=[], help="each mesh's scene (default: from its file name)")
    ap.add_argument("--steps", type=int, default=200)
    ap.add_argument("--seed", type=int, default=None, help="default: from the clock (printed)")
    ap.add_argument("--demo-scenes", default=os.path.join(ROOT, "runs"),
                    help="a folder whose scenes/ holds the demo's pile and mesh (default: runs/ of this checkout)")
    ap.add_argument("--demo-travel", type=float, default=0.001, help="the demo runs' travel [m] (default 1 mm)")
    ap.add_argument("--demo-cpu-run", metavar="DIR",
                    help="only run the demo on the CPU into DIR (e.g. in the background, on cores of its own) and "
                         "print its result's path; then --demo-cpu-result takes it")
    ap.add_argument("--demo-cpu-result", metavar="H5", help="the CPU's demo run made with --demo-cpu-run")
    ap.add_argument("--demo", choices=("with", "skip", "only"), default="with",
                    help="item 12 with the others (default), left out, or alone")
    a = ap.parse_args(argv)
    if a.demo_cpu_run:   # needs no GPU
        t0 = time.perf_counter()
        path = demo_run(a.demo_scenes, a.demo_travel, "cpu", a.demo_cpu_run)
        print(f"demo on the CPU: {path} ({time.perf_counter() - t0:.0f} s)", flush=True)
        return 0 if path else 1
    if not gpu.available():
        print(f"GPU check skipped: {gpu.why_unavailable()}")
        return 0
    seed = a.seed if a.seed is not None else int(time.time()) % 100000
    print(f"GPU: {gpu.device_name()}; seed {seed}")
    rng = np.random.default_rng(seed)
    if a.demo == "only":
        ok = check_demo(a.demo_scenes, a.demo_travel, a.demo_cpu_result)
        print("GPU check passed" if ok else "GPU check FAILED")
        return 0 if ok else 1
    ok = True
    for drag_model in ("linear", "quadratic", "none"):
        m = floating_blocks(rng, drag_model)
        ok &= report(f"three floating blocks, {drag_model} drag", gpu.compare(m))
        ok &= report_update(f"three floating blocks, {drag_model} drag", gpu.compare_update(m))
    ok &= report_contact("pressed blocks", gpu.compare_contact(pressed_blocks(rng)))
    for far in (0, 12):
        ok &= report_search(f"300 strewn blocks{', 12 more over 2 km' if far else ''}",
                            gpu.compare_broad_phase(scattered_blocks(rng, 300, far)))
    ok &= report_bonds("bonded square", gpu.compare_bond_check(bonded_square(rng)))
    ok &= report_friction("rubbing blocks", gpu.compare_friction(rubbing_blocks(rng)))
    for direction in ("paper", "work_conjugate"):
        for k, m in enumerate(opened_square(rng, direction=direction)):
            state = ("just split (rigid phase)", "softening", "softening later", "failing")[k]
            ok &= report_cohesive(f"opened square, {direction} direction, {state}", gpu.compare_cohesive(m))
    m = floating_blocks(rng, "quadratic")
    stage = gpu.BodyForces(m)
    stage.run()
    f1 = stage.fields()
    stage.run()
    f2 = stage.fields()
    same = all(n == 0 for n, _ in gpu.differences(f1, f2, gpu.FIELDS + ("elastic_energy",)).values())
    print(f"[{'ok' if same else 'FAIL'}] a second GPU run gives the same bits", flush=True)
    ok &= same
    if a.mesh:
        from gpu_body_forces import load_phase_model
        from icerubble.files.mesh_file import read_mesh
        for k, path in enumerate(a.mesh):
            name = a.scene[k] if k < len(a.scene) else os.path.basename(path).split("_")[0]
            m = load_phase_model(read_mesh(path), name, "fast", 0)
            m.step(a.steps)
            ok &= report(f"{os.path.basename(path)} after {a.steps} steps", gpu.compare(m))
            xy = m.positions
            m.set_positions(xy + rng.uniform(-1e-4, 1e-4, xy.shape))
            ok &= report(f"{os.path.basename(path)}, every node nudged", gpu.compare(m))
            ok &= report_contact(os.path.basename(path), gpu.compare_contact(m))
            ok &= report_search(os.path.basename(path), gpu.compare_broad_phase(m))
            ok &= report_bonds(os.path.basename(path), gpu.compare_bond_check(m))
            ok &= report_update(os.path.basename(path), gpu.compare_update(m))
            ok &= report_friction(os.path.basename(path), gpu.compare_friction(m))
            m.set_bond_params(check_failure=True)   # the points at the criterion split and open
            m.step(20)
            ok &= report_cohesive(f"{os.path.basename(path)} 20 steps after its points split",
                                  gpu.compare_cohesive(m))
    # whole steps last: the newest code, so that a failure there leaves every stage's check above reported
    try:
        for drag_model in ("linear", "none", "quadratic"):
            seed_m = int(rng.integers(1 << 30))
            make = lambda: driven_block(np.random.default_rng(seed_m), drag_model)  # noqa: E731
            ok &= report_steps(f"driven block, {drag_model} drag, 2,000 whole GPU steps",
                               gpu.compare_steps(make, 2000, nodes="top"), exact=drag_model != "quadratic")
        seed_m = int(rng.integers(1 << 30))
        ok &= report_steps("block sliding on a slab, 4,000 whole GPU steps",
                           gpu.compare_steps(lambda: sliding_block(np.random.default_rng(seed_m)), 4000,
                                             nodes="slab_bottom"), exact=True)
        seed_m = int(rng.integers(1 << 30))
        ok &= report_steps("block at rest on a slab, a flyer past it, 4,000 whole GPU steps (lists rebuilt on the GPU's turn)",
                           gpu.compare_steps(lambda: landing_block_and_a_flyer(np.random.default_rng(seed_m)), 4000,
                                             nodes="slab_bottom"), exact=True)
        for direction in ("paper", "work_conjugate"):
            ok &= report_steps(f"bonded bar pulled apart ({direction}), 14,000 whole GPU steps",
                               gpu.compare_steps(lambda: pulled_bar(direction), 14000, nodes="right"), exact=True)
        ok &= report_steps("bonded square sheared, 3,000 whole GPU steps",
                           gpu.compare_steps(sheared_square, 3000, nodes="top"), exact=True)
        # 11. a model on device 'cuda' (the GPU's steps kept between calls) against the CPU, in chunks as a run's
        cmp = gpu.compare_device(pulled_bar, 7, 2000, nodes="right")
        print(f"[{'ok' if cmp['same'] else 'FAIL'}] Model(device='cuda'), bonded bar, 7 x 2,000 steps: "
              f"{'the CPU bits' if cmp['same'] else 'differs from the CPU'}; GPU steps {cmp['gpu_steps']}",
              flush=True)
        ok &= cmp["same"]
        if a.demo == "with":
            ok &= check_demo(a.demo_scenes, a.demo_travel, a.demo_cpu_result)
        steps = gpu.Steps(driven_block(rng, "linear"))
        steps.step(100)
        t0 = time.perf_counter()
        steps.step(2000)
        print(f"[--] driven block ({driven_block(rng, 'linear').n_triangles} triangles): "
              f"{1e6 * (time.perf_counter() - t0) / 2000:.1f} us per whole GPU step (wall, read back in batches of up to 32 steps)",
              flush=True)
    except Exception as e:  # reported, and the check fails
        print(f"[FAIL] whole GPU steps: {type(e).__name__}: {e}", flush=True)
        ok = False
    print("GPU check passed" if ok else "GPU check FAILED")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
