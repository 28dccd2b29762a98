"""`make bench`: run every benchmark bench/*.py (each prints its figures and
writes bench/results/<name>.json), stamp each result it rewrote with the code
and machine (bench/stamps.py) and write bench/README.md from the results
(bench/make_readme.py). Extra arguments (e.g. --quick) are passed on."""
import glob
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [HERE, os.path.dirname(HERE)]
import stamps  # noqa: E402

# Benchmarks of many hours, run alone (each says how in its docstring).
LONG = {"paper_peak.py": "the paper scene's cohesive peak under each preset: ~0.7-1 h for `fast` "
                         "and `balanced`, ~5 h for `paper`, after a ~0.5 h settle",
        "force_direction.py": "it measures finished runs of the paper-depth study (--measure RESULT.h5 ...), "
                              "each ~30-60 min on one core",
        "touching_churn.py": "it loads the paper scene from paper_peak.py's rest state (made first with its "
                             "--settle-only) for ~25 min on 2 cores",
        "gpu_paper_run.py": "a punch-through timed whole on a device (--device cuda on a GPU machine: "
                            "tools/gpu_lease.sh runs it; hours on a CPU)"}
# The GPU backend's benchmarks, run where a GPU is visible (make gpu-check runs
# them too): elsewhere they would replace a GPU machine's figures with none.
GPU_ONLY = {"gpu_body_forces.py", "gpu_friction.py", "gpu_step_profile.py"}
# Not benchmarks: the stamps and the measured figures' page.
HELPERS = {"run_all.py", "stamps.py", "make_readme.py", "result_file.py"}
RESULTS = os.path.join(HERE, "results")


def result_times():
    return {os.path.basename(p): os.path.getmtime(p) for p in glob.glob(os.path.join(RESULTS, "*.json"))}


def main():
    scripts = sorted(p for p in glob.glob(os.path.join(HERE, "*.py"))
                     if os.path.basename(p) not in LONG and os.path.basename(p) not in HELPERS)
    for name, what in LONG.items():
        print(f"=== {name}: not run by make bench ({what}); /usr/bin/python3 bench/{name}", flush=True)
    failed = []
    from icerubble.engine import gpu
    for path in scripts:
        name = os.path.basename(path)
        if name in GPU_ONLY and not gpu.available():
            print(f"=== {name}: not run here ({gpu.why_unavailable()}; its figures are a GPU machine's)\n",
                  flush=True)
            continue
        print(f"=== {name}", flush=True)
        start, before = time.time(), result_times()
        rc = subprocess.call([sys.executable, path] + sys.argv[1:])
        rewritten = [n for n, t in result_times().items() if before.get(n) != t and n != "stamps.json"]
        if rc == 0 and rewritten:
            stamps.stamp(rewritten)
        print(f"=== {name}: {'ok' if rc == 0 else f'FAILED (exit {rc})'} in {time.time() - start:.0f} s\n",
              flush=True)
        if rc:
            failed.append(name)
    subprocess.check_call([sys.executable, os.path.join(HERE, "make_readme.py")])
    if failed:
        sys.exit(f"benchmarks failed: {', '.join(failed)}")


if __name__ == "__main__":
    main()
