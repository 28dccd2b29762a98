"""The benchmark case through the whole engine: two 8 m x 8 m blocks, h = 0.1 m
right-triangle meshes (25,600 triangles), head-on at +-1 m/s, penalty 2e11,
mu = 0.3, dt = 1e-6 s. Prints triangle-steps per second and the share of the
step spent in contact detection and contact forces. Timings on a shared
machine are noisy: run it a few times.

    /usr/bin/python3 bench/contact_benchmark_case.py [--steps N] [--threads T]
"""
import argparse
import time

import numpy as np

from icerubble import engine


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=1000)
    ap.add_argument("--threads", type=int, default=0)
    args = ap.parse_args()
    na_, ta = engine.rectangle_mesh(80, 80, 0.1, origin=(-8.0, 0.0))
    nb_, tb = engine.rectangle_mesh(80, 80, 0.1, origin=(1e-4, 0.0))  # 0.1 mm gap: touch at step 50
    nodes, tri = np.r_[na_, nb_], np.r_[ta, tb + len(na_)]
    body = np.r_[np.zeros(len(ta)), np.ones(len(tb))].astype(int)
    m = engine.Model(nodes, tri, body, materials=dict(E=2e9, nu=0.3, rho=920.0, damping=0.0))
    m.set(dt=1e-6, gravity=False, water=False, penalty=2e11, mu=0.3, threads=args.threads)
    v = np.zeros((len(nodes), 2))
    v[: len(na_), 0], v[len(na_):, 0] = 1.0, -1.0
    m.set_velocities(v)
    m.step(100)  # warm-up, and the blocks are in contact from here on
    t0 = m.timings()
    w0 = time.perf_counter()
    m.step(args.steps)
    wall = time.perf_counter() - w0
    t1 = m.timings()
    d = {k: t1[k] - t0[k] for k in t1}
    n = d["steps"]
    print(f"{len(tri)} triangles, {len(m.surface_triangles)} surface triangles, "
          f"{m.touching_pairs} touching pairs, threads {args.threads or 'default'}")
    print(f"{len(tri) * n / wall / 1e6:.2f} M triangle-steps/s ({1e6 * wall / n:.0f} us per step)")
    for k in ("elements", "contact_detection", "contact_forces", "bonds", "integration"):
        print(f"  {k:18s} {1e6 * d[k] / n:8.1f} us/step  {100 * d[k] / d['total']:5.1f} %")


if __name__ == "__main__":
    main()
