"""Products of 2-vectors in plain arithmetic, for the meshing of a pile
(geometry/) and the polygons below it (polygon.py).

numpy's `@`, `dot` and the norm of a 1-D vector call the BLAS library, whose
kernels are chosen by the processor (OpenBLAS: Zen, Haswell, SkylakeX, ...)
and may round otherwise (fused multiply-adds, another order). Measured: an AMD
EPYC meshed every shipped ridge into another mesh than the Intel Xeon that
made them, and into the same one with OPENBLAS_CORETYPE=Prescott (SSE3 kernels).
Elementwise products and sums are single IEEE operations: the same bits on every
x86-64 processor, in the order the BLAS kernels without fused operations take
(a0 b0 + a1 b1), so the meshes made before are the meshes made now
(docs/reproducibility.md).
"""
import numpy as np


def dot2(a, b):
    """a . b over the last axis of length 2 (either may be a stack of vectors)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    return a[..., 0] * b[..., 0] + a[..., 1] * b[..., 1]


def norm2(v):
    """|v| of a 2-vector (or of each in a stack)."""
    return np.sqrt(dot2(v, v))


def rotated(local, rot):
    """local @ rot.T for points local (N, 2) and a 2 x 2 rotation rot."""
    local, rot = np.asarray(local, float), np.asarray(rot, float)
    return np.stack((dot2(local, rot[0]), dot2(local, rot[1])), axis=-1)
