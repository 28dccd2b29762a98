"""Broad-phase cost per surface triangle as the number of blocks grows (it
should stay flat: linear scaling). Rubble-like scene: k x k small blocks
(0.6 m x 0.3 m, h = 0.1 m) in touching rows, rebuilt every call (skin 0).

    /usr/bin/python3 bench/contact_broad_phase_scaling.py
"""

import numpy as np

from icerubble import _engine, engine


def rubble(k):
    nodes, tris, body = [], [], []
    off = 0
    for i in range(k):
        for j in range(k):
            n, t = engine.rectangle_mesh(6, 3, 0.1, origin=(0.6 * i + 1e-5 * j, 0.3 * j))
            nodes.append(n)
            tris.append(t + off)
            body.append(np.full(len(t), i * k + j))
            off += len(n)
    return np.vstack(nodes), np.vstack(tris).astype(np.int32), np.concatenate(body).astype(np.int32)


def main():
    for k in (5, 10, 20, 40):
        pts, tri, body = rubble(k)
        surf = np.arange(len(tri), dtype=np.int32)  # small blocks: every triangle is on the surface
        n = len(pts)
        s = _engine.ContactSolver(skin_fraction=0.0)
        z = np.zeros(n)
        x, y, mass = pts[:, 0].copy(), pts[:, 1].copy(), np.ones(n)
        fx, fy = np.zeros(n), np.zeros(n)
        reps = max(3, 20000 // len(surf))
        for _ in range(reps):
            s.compute_normal(x, y, z, z, mass, tri, body, surf, fx, fy, penalty=2e11, mu=0.0, dt=1e-6)
        det = s.timings["detection_s"] / reps
        print(f"{k * k:5d} blocks {len(surf):7d} surface triangles {len(s.candidates):7d} candidates: "
              f"detection {1e6 * det:8.1f} us = {1e9 * det / len(surf):6.1f} ns per triangle")


if __name__ == "__main__":
    main()
