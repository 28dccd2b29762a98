"""Cost of the contact passes on the benchmark case: two 8 m x 8 m blocks,
h = 0.1 m right-triangle meshes (25,600 triangles), pressed together head-on.

Times ContactSolver.compute_normal + apply_friction alone (no elements), per
call, and prints it against the 2.56 ms per step that 10 M triangle-steps/s
allows for 25,600 triangles. The wall time also includes the Python binding's
input checks (all 25,600 triangles every call), which the engine does not pay.
Timings on a shared machine are noisy.

    /usr/bin/python3 bench/contact_two_blocks.py [--steps N]
"""
import argparse
import os
import time

import numpy as np

from icerubble import _engine


def block(x0, y0, size, h):
    n = int(round(size / h))
    gx, gy = np.meshgrid(np.arange(n + 1) * h + x0, np.arange(n + 1) * h + y0)
    pts = np.c_[gx.ravel(), gy.ravel()]
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    tri = np.r_[np.c_[a, b, c], np.c_[a, c, d]]
    on_edge = (idx == idx) & False
    on_edge[0, :] = on_edge[-1, :] = on_edge[:, 0] = on_edge[:, -1] = True
    surf = np.nonzero(on_edge.ravel()[tri].any(axis=1))[0]
    return pts, tri, surf


def two_blocks(size=8.0, h=0.1, overlap=1e-7):
    pa, ta, sa = block(-size, 0.0, size, h)
    pb, tb, sb = block(-overlap, 0.0, size, h)
    pts = np.r_[pa, pb]
    tri = np.r_[ta, tb + len(pa)].astype(np.int32)
    body = np.r_[np.zeros(len(ta)), np.ones(len(tb))].astype(np.int32)
    surf = np.r_[sa, sb + len(ta)].astype(np.int32)
    return pts, tri, body, surf


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=200)
    args = ap.parse_args()
    pts, tri, body, surf = two_blocks()
    n = len(pts)
    mass = np.full(n, 920 * 0.01 / 2 * 6 / 6)  # ~ rho h^2 per node
    v = np.zeros(n)
    v[: n // 2] = 1.0
    v[n // 2:] = -1.0
    x, y = pts[:, 0].copy(), pts[:, 1].copy()
    solver = _engine.ContactSolver()
    fx, fy = np.zeros(n), np.zeros(n)
    t0 = time.perf_counter()
    for _ in range(args.steps):
        fx[:] = 0.0
        fy[:] = 0.0
        solver.compute_normal(x, y, v, np.zeros(n), mass, tri, body, surf, fx, fy,
                              penalty=2e11, mu=0.3, dt=1e-6)
        solver.apply_friction(x, y, v, np.zeros(n), mass, tri, body, surf, fx, fy,
                              penalty=2e11, mu=0.3, dt=1e-6)
    wall = (time.perf_counter() - t0) / args.steps
    det, frc = solver.timings["detection_s"], solver.timings["forces_s"]  # cumulative
    print(f"triangles {len(tri)}, surface triangles {len(surf)}, "
          f"candidate pairs {len(solver.candidates)}, touching pairs {solver.touching_pairs}, "
          f"threads {os.environ.get('OMP_NUM_THREADS', 'default')}")
    print(f"per step: detection {1e6 * det / args.steps:.1f} us, forces {1e6 * frc / args.steps:.1f} us, "
          f"wall incl. Python glue {1e6 * wall:.1f} us")
    print(f"share of the 2560 us step budget (10 M triangle-steps/s): "
          f"{100 * (det + frc) / args.steps / 2.56e-3:.1f} %")


if __name__ == "__main__":
    main()
