"""Pair kernel of the potential contact force method (paper eqs 1-3, docs/model.md §3.2).

The kernel returns the forces on the three contactor and three target nodes of
one overlapping triangle pair and the stored energy E = s * int (phi_c + phi_t)
over the overlap, phi = 3 * min area coordinate.
"""
import numpy as np
import pytest

from icerubble import _engine

S = 2e11  # paper's penalty [Pa]; the kernel is linear in s


def random_overlapping_pairs(n, seed):
    """Random contactor/target triangles (random orientation of the node order) that overlap."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n:
        xt = rng.uniform(-1, 1, (3, 2))
        xc = rng.uniform(-1, 1, (3, 2)) + rng.uniform(-0.5, 0.5, 2)
        for x in (xt, xc):
            a2 = (x[1, 0] - x[0, 0]) * (x[2, 1] - x[0, 1]) - (x[2, 0] - x[0, 0]) * (x[1, 1] - x[0, 1])
            if abs(a2) < 0.2:  # avoid slivers: the FD check wants well-shaped triangles
                break
        else:
            if _engine.contact_pair(xc, xt, S) is not None:
                out.append((xc, xt))
    return out


def moment(x, f):
    return np.sum(x[:, 0] * f[:, 1] - x[:, 1] * f[:, 0])


def test_no_overlap_gives_no_force():
    xt = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    # Separated by a gap, and touching along an edge with zero overlap area.
    assert _engine.contact_pair(xt + [0.0, 1.5], xt, S) is None
    mirrored = np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])  # shares the hypotenuse, no area
    r = _engine.contact_pair(mirrored, xt, S)
    assert r is None or np.all(r["forces"] == 0.0)


@pytest.mark.parametrize("seed", [1, 2])
def test_equal_opposite_and_zero_moment(seed):
    for xc, xt in random_overlapping_pairs(200, seed):
        r = _engine.contact_pair(xc, xt, S)
        f = r["forces"]
        x = np.vstack([xc, xt])
        scale = np.abs(f).max()
        # Round-off of sums of ~20 terms of size `scale`: 1e-13 relative is
        # ~500 ulp, far below any real imbalance (which would be O(1)).
        assert np.all(np.abs(f.sum(axis=0)) <= 1e-13 * scale)
        assert abs(moment(x, f)) <= 1e-13 * scale * 2.0  # lever arms are <= ~2 m
        # The resultant on the contactor equals minus the one on the target.
        np.testing.assert_allclose(f[:3].sum(0), -f[3:].sum(0), rtol=0, atol=1e-13 * scale)


def mirror_pair(d):
    """Target below y = 0 (apex at y = -1), contactor its mirror image lowered by d."""
    xt = np.array([[-1.0, 0.0], [0.0, -1.0], [1.0, 0.0]])
    xc = np.array([[-1.0, -d], [1.0, -d], [0.0, 1.0 - d]])
    return xc, xt


def test_force_separates_and_grows_with_penetration():
    forces = []
    for d in (1e-6, 1e-4, 1e-3, 1e-2, 0.1):
        xc, xt = mirror_pair(d)
        f = _engine.contact_pair(xc, xt, S)["forces"]
        fc = f[:3].sum(0)
        # Mirror symmetry about x = 0: the resultant is along y, pushing the
        # contactor up (out of the target). 1e-12 relative: round-off only.
        assert abs(fc[0]) <= 1e-12 * abs(fc[1])
        assert fc[1] > 0.0
        forces.append(fc[1])
    assert np.all(np.diff(forces) > 0.0)


def test_small_penetration_matches_analytic_stiffness():
    # For a thin overlap strip of depth d along an edge of length 2 between two
    # triangles of altitude 1, phi_t = 3*depth and phi_c = 3*(d - depth) on the
    # strip, so E = s * 2 * 3 d^2 and the separating force is dE/dd = 12 s d.
    # The strip's two ends reach into the other sub-triangles over a length O(d),
    # so the relative deviation is O(d): 1e-3 tolerance at d = 1e-5.
    d = 1e-5
    xc, xt = mirror_pair(d)
    r = _engine.contact_pair(xc, xt, S)
    assert r["forces"][:3, 1].sum() == pytest.approx(12 * S * d, rel=1e-3)
    assert r["energy"] == pytest.approx(6 * S * d * d, rel=1e-3)


@pytest.mark.parametrize("seed", [3, 4])
def test_force_is_minus_gradient_of_stored_energy(seed):
    # Central differences of E with step h = 1e-6 (triangles of size ~1): the
    # truncation error is O(h^2 E''') ~ 1e-12 relative where E is smooth, the
    # round-off E*eps/h ~ 1e-10 relative; E'' jumps where a vertex crosses a
    # median of the other triangle, giving O(h) = 1e-6 there. Tolerance 1e-5 of
    # the largest nodal force: a wrong distribution to the nodes (e.g. the
    # resultant spread by area coordinates) is off by O(1).
    h = 1e-6
    for xc, xt in random_overlapping_pairs(40, seed):
        r = _engine.contact_pair(xc, xt, S)
        f = r["forces"]
        x = np.vstack([xc, xt])
        fd = np.zeros_like(f)
        for a in range(6):
            for k in range(2):
                xp, xm = x.copy(), x.copy()
                xp[a, k] += h
                xm[a, k] -= h
                rp = _engine.contact_pair(xp[:3], xp[3:], S)
                rm = _engine.contact_pair(xm[:3], xm[3:], S)
                ep = rp["energy"] if rp else 0.0
                em = rm["energy"] if rm else 0.0
                fd[a, k] = -(ep - em) / (2 * h)
        np.testing.assert_allclose(f, fd, rtol=0, atol=1e-5 * np.abs(f).max())


def test_bad_penalty_is_rejected():
    xc, xt = mirror_pair(0.1)
    with pytest.raises(ValueError, match="penalty"):
        _engine.contact_pair(xc, xt, -1.0)


def test_triangles_sharing_a_node_or_a_body_never_contact():
    # Two overlapping triangles with a common corner. As separate nodes of
    # different bodies they push apart; sharing the corner node, or belonging
    # to one body, they must not (docs/model.md §3.2).
    corner = [0.0, 0.0]
    a = [corner, [1.0, 0.0], [0.2, 1.0]]
    b = [corner, [1.0, 0.3], [0.9, 1.0]]

    def forces(pts, tri, body):
        n = len(pts)
        pts = np.asarray(pts, dtype=float)
        fx, fy = np.zeros(n), np.zeros(n)
        s = _engine.ContactSolver()
        s.compute_normal(pts[:, 0].copy(), pts[:, 1].copy(), np.zeros(n), np.zeros(n), np.ones(n),
                         np.asarray(tri, dtype=np.int32), np.asarray(body, dtype=np.int32),
                         np.arange(len(tri), dtype=np.int32), fx, fy, penalty=S, mu=0.3, dt=1e-6)
        return s.touching_pairs, np.abs(fx).max() + np.abs(fy).max()

    separate = forces(a + b, [[0, 1, 2], [3, 4, 5]], [0, 1])
    shared = forces(a + b[1:], [[0, 1, 2], [0, 3, 4]], [0, 1])
    same_body = forces(a + b, [[0, 1, 2], [3, 4, 5]], [0, 0])
    assert separate[0] == 1 and separate[1] > 0.0
    assert shared == (0, 0.0)
    assert same_body == (0, 0.0)
