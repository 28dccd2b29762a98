"""Throughput benchmark of the FEM-DEM engine: two ice blocks collide head-on.

Two square blocks of n x n cells (h = 0.1 m, each cell cut into two
triangles: 2 n² triangles per block, blocks n h wide), 0.01 m apart, moving
at +-1 m/s; E = 5 GPa, nu = 0.3, rho = 920 kg/m³, plane strain, no gravity,
no water, dt = 1e-6 s, penalty 2e11 Pa, mu = 0.3, 10,000 steps. Each (n,
threads) case runs in its own process with OMP_NUM_THREADS set.

Writes bench/results/collision.json: a list of records with n, triangles,
threads, steps, wall_s, triangle_steps_per_s, the time split (elements,
contact_detection, contact_forces, integration, in s) and the memory per
triangle (engine arrays, and peak RSS of the whole process).

Not a test: figures depend on the machine and its load.
    /usr/bin/python3 bench/collision.py [--quick] [--n 10 20 40 80] [--threads 1 2]
"""
import argparse
import json
import os
import resource
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
RESULTS = os.path.join(ROOT, "bench", "results", "collision.json")


def worker(n, steps):
    import numpy as np
    from icerubble import engine

    h, gap = 0.1, 0.01
    a_nodes, a_tri = engine.rectangle_mesh(n, n, h, origin=(-n * h - gap / 2, 0.0))
    b_nodes, b_tri = engine.rectangle_mesh(n, n, h, origin=(gap / 2, 0.0))
    nodes = np.vstack((a_nodes, b_nodes))
    tri = np.vstack((a_tri, b_tri + len(a_nodes)))
    body = np.repeat([0, 1], len(a_tri))
    m = engine.Model(nodes, tri, body, dict(E=5e9, nu=0.3, rho=920.0, damping=0.0))
    m.set(gravity=False, water=False, dt=1e-6, penalty=2e11, mu=0.3)
    v = np.zeros_like(nodes)
    v[: len(a_nodes), 0] = 1.0
    v[len(a_nodes):, 0] = -1.0
    m.set_velocities(v)
    m.step(1)  # preparation (topology, stable step) outside the timing
    t0 = m.timings()
    start = time.perf_counter()
    m.step(steps)
    wall = time.perf_counter() - start
    t1 = m.timings()
    split = {k: t1[k] - t0[k] for k in ("elements", "contact_detection", "contact_forces",
                                          "integration")}
    e = m.energies()
    return {
        "n": n, "triangles": int(len(tri)), "threads": int(os.environ.get("OMP_NUM_THREADS", "0")),
        "steps": steps, "wall_s": wall, "triangle_steps_per_s": len(tri) * steps / wall,
        **split,
        "engine_bytes_per_triangle": m.memory_bytes() / len(tri),
        "peak_rss_bytes_per_triangle": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 / len(tri),
        "touching_pairs_at_end": int(m.touching_pairs),
        "energy_residual_over_initial": e["residual"] / e["initial"],
    }


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="500 steps instead of 10,000")
    p.add_argument("--steps", type=int, default=None)
    p.add_argument("--n", type=int, nargs="+", default=[10, 20, 40, 80])
    p.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    p.add_argument("--worker", nargs=2, type=int, metavar=("N", "STEPS"), help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.worker:
        print(json.dumps(worker(*args.worker)))
        return
    steps = args.steps or (500 if args.quick else 10000)
    records = []
    print(f"collision benchmark, {steps} steps (load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores: a busy machine gives pessimistic figures)")
    print(f"{'n':>4} {'triangles':>9} {'thr':>3} {'wall s':>8} {'tri-steps/s':>12} "
          f"{'elements':>9} {'detect':>8} {'contact':>8} {'integr':>8} {'B/tri':>6} {'RSS B/tri':>9}")
    for n in args.n:
        for threads in args.threads:
            env = dict(os.environ, OMP_NUM_THREADS=str(threads))
            out = subprocess.run([sys.executable, os.path.abspath(__file__), "--worker", str(n), str(steps)],
                                 env=env, capture_output=True, text=True, check=True)
            r = json.loads(out.stdout.strip().splitlines()[-1])
            records.append(r)
            print(f"{n:>4} {r['triangles']:>9} {threads:>3} {r['wall_s']:>8.2f} "
                  f"{r['triangle_steps_per_s']:>12.3e} {r['elements']:>9.2f} {r['contact_detection']:>8.2f} "
                  f"{r['contact_forces']:>8.2f} {r['integration']:>8.2f} "
                  f"{r['engine_bytes_per_triangle']:>6.0f} {r['peak_rss_bytes_per_triangle']:>9.0f}",
                  flush=True)
    os.makedirs(os.path.dirname(RESULTS), exist_ok=True)
    with open(RESULTS, "w") as f:
        json.dump(records, f, indent=1)
    print("written", os.path.relpath(RESULTS, ROOT))


if __name__ == "__main__":
    main()
