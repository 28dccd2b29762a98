"""Where a whole GPU step's time goes, kernel by kernel (not a test;
docs/gpu.md): the paper mesh in the load phase, as bench/gpu_body_forces.py
steps it, its whole GPU steps (gpu.Steps) run under Nsight Compute (ncu, on
the machine with the GPU) with only a few steps profiled, each kernel's
duration read from the hardware's timer. Writes bench/results/gpu_step_profile.json.

    python3 bench/gpu_step_profile.py [--mesh MESH.h5] [--steps 4]

Two states: the load phase as it starts (few touching pairs, no opened bond
pair) and after every node is nudged by up to 0.1 mm (~2,800 points split, as
bench/gpu_body_forces.py's cohesive measurement), whose opened pairs bring
many faces into touch. Each state's `run` says how many of the profiled
steps coloured friction's touching pairs (a step whose pairs are those of
the step before keeps its colouring: its colouring kernels then take no
time). Also:
    --summarize NAME=CSV ... : the JSON from ncu CSV files made before
"""
import argparse
import collections
import csv
import ctypes
import json
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path[:0] = [ROOT, os.path.join(ROOT, "bench")]
OUT = os.path.join(ROOT, "bench", "results", "gpu_step_profile.json")
import result_file  # noqa: E402
STATES = {"load phase": False, "opened pairs": True}


def inner(mesh, opened, steps):
    """Run under ncu --profile-from-start off: only `steps` whole steps are profiled."""
    from gpu_body_forces import load_phase_model, open_pairs_by_nudge
    from icerubble.engine import gpu
    from icerubble.files.mesh_file import read_mesh
    m = load_phase_model(read_mesh(mesh), "paper", "fast", os.cpu_count())
    m.step(50)
    if opened:
        open_pairs_by_nudge(m)
    s = gpu.Steps(m)
    s.step(700)   # past the splits' host steps and a graph's capture
    h0, c0 = s.host_steps, s.colourings
    try:   # the driver's profiler switch: ncu --profile-from-start off profiles what is between
        cuda = ctypes.CDLL("libcuda.so.1")
    except OSError:   # no driver (the CPU emulation): the steps run unprofiled
        cuda = None
    if cuda:
        cuda.cuProfilerStart()
    t0 = time.perf_counter()
    s.step(steps)
    if cuda:
        cuda.cuProfilerStop()
    # colourings: friction colours only where the touching pairs changed since
    # the step before (docs/gpu.md), so its kernels' time depends on how many
    print(json.dumps(dict(steps=steps, host_steps=s.host_steps - h0, wall_us_per_step=1e6 * (time.perf_counter() - t0) / steps,
                          opened_pairs=int(m.bonds.counts["split"]), colourings=s.colourings - c0)), flush=True)


def summarize(path, steps):
    """Each kernel's mean duration [µs] and launches per step from an ncu --csv file."""
    lines = open(path).read().splitlines()
    # the profiled run's own line (inner): its steps' host steps and colourings
    run = [json.loads(x) for x in lines if x.startswith('{"steps"')]
    rows = [r for r in csv.reader(lines) if len(r) > 10]
    head = rows[0]
    k, v = head.index("Kernel Name"), head.index("Metric Value")
    d = collections.defaultdict(list)
    for r in rows[1:]:
        try:
            d[r[k].split("(")[0].replace("(anonymous namespace)::", "").replace("<unnamed>::", "").replace("unnamed>::", "")].append(float(r[v].replace(",", "")) * 1e-3)
        except ValueError:
            pass
    # a window of launches can start mid-step (ncu --launch-skip): the steps are
    # counted by the update, which runs once a step, and a kernel's launches per
    # step rounded
    steps = len(d.get("update_kernel", [])) or steps
    kernels = []
    for name, x in d.items():
        per_step = max(round(len(x) / steps), 1)
        kernels.append(dict(kernel=name, mean_us=sum(x) / len(x), launches_per_step=per_step,
                            us_per_step=per_step * sum(x) / len(x)))
    kernels.sort(key=lambda r: -r["us_per_step"])
    out = dict(kernels=kernels, us_per_step=sum(r["us_per_step"] for r in kernels))
    if run:
        out["run"] = run[-1]
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--mesh", default=os.path.join(ROOT, "runs", "scenes", "paper_ridge1_pilemu0.3_mesh.h5"))
    ap.add_argument("--steps", type=int, default=4)
    ap.add_argument("--inner", choices=tuple(STATES), help=argparse.SUPPRESS)
    ap.add_argument("--summarize", nargs="+", metavar="STATE=CSV")
    ap.add_argument("--device-name", default=None, help="with --summarize: the GPU the CSV files were made on")
    ap.add_argument("--out", default=OUT)
    a = ap.parse_args(argv)
    if a.inner:
        inner(a.mesh, STATES[a.inner], a.steps)
        return
    from icerubble.code_identity import code_version, source_hash
    out = dict(mesh=os.path.basename(a.mesh), steps_profiled=a.steps, measured=time.strftime("%Y-%m-%d"),
               code_version=code_version(), source_hash=source_hash(), states={})
    if a.summarize:
        out["device"] = a.device_name
        for item in a.summarize:
            state, path = item.split("=", 1)
            out["states"][state] = summarize(path, a.steps)
    else:
        from icerubble.engine import gpu
        out["device"] = gpu.device_name()
        for state in STATES:
            with tempfile.NamedTemporaryFile(suffix=".csv") as f:
                run = subprocess.run(["ncu", "--clock-control", "none", "--profile-from-start", "off", "--metrics",
                                      "gpu__time_duration.sum", "--csv", sys.executable, os.path.abspath(__file__),
                                      "--inner", state, "--mesh", a.mesh, "--steps", str(a.steps)],
                                     stdout=f, stderr=subprocess.PIPE, text=True)
                if run.returncode:
                    sys.exit(f"ncu failed: {run.stderr[-2000:]}")
                out["states"][state] = summarize(f.name, a.steps)
    for state, s in out["states"].items():
        print(f"{state}: {s['us_per_step']:.0f} µs of kernels per step; "
              + ", ".join(f"{r['kernel']} {r['us_per_step']:.1f}" for r in s["kernels"][:6]))
    result_file.write(a.out, out)


if __name__ == "__main__":
    main()
