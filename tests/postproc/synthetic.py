"""SYNTHETIC run results in the exact docs/results_format.md layout, for tests and
demos of the post-processing. NOT simulation output: the numbers come from simple
closed-form stand-ins chosen so every analysis has something to find.

What a synthetic run contains (per ridge, mu, tau_cr):
- a keel of rectangular blocks on a regular grid (two triangles each), block width
  chosen so the solid fraction is exactly 1 - eta; a consolidated layer of two
  bodies and a 4 m x 1 m indenter;
- bond points on two straight failure planes from the keel top outward at
  known angles ``true_alpha(ridge, tau_cr)`` (exactly on the lines when
  ``jitter=0``), failing at travels spread over 0.5-8.9 mm; bond points under the
  indenter that fail early (the analyses must ignore them); background bond points
  that split after 20 mm, and some that fail only after 40 mm; the traction at each split on
  the boundary of eq 6, tension side for a known share (nt_ns_init_target);
- a u_y field per snapshot: the plug between the planes moves with the indenter and
  the moving zone narrows with travel (faster for small mu);
- F(y_I): a linear rise to the peak at 1 mm, a steep drop until ~20 mm, then the
  buoyancy of the moving rubble.
Bond positions are not tied to mesh nodes (nothing in the analyses needs that).

`python3 -m tests.postproc.synthetic OUT_DIR` (from the repository root) writes a small set.
"""
import argparse
import datetime
import os
import sys

import h5py
import numpy as np

from icerubble.files.results import FailureMode
from icerubble.parameters import GRAVITY as G, RHO_I, RHO_W

H, W_I, T_C, DOMAIN = 4.0, 4.0, 1.0, 20.0
DRAFT = RHO_I / RHO_W * T_C
KEEL_TOP = -DRAFT
SNAPSHOT_TRAVELS_MM = [1, 5, 10] + list(range(20, 301, 10))

_RIDGE = {  # per-ridge stand-ins for "geometry": alpha offset [deg], porosity, strength factor
    0: (-3.0, 0.25, 1.00), 1: (4.0, 0.23, 0.85), 2: (-6.0, 0.27, 1.10), 3: (1.0, 0.24, 0.95),
}


def _ridge_index(ridge):
    digits = "".join(c for c in str(ridge) if c.isdigit())
    return (int(digits) - 1) % 4 if digits else sum(map(ord, str(ridge))) % 4


def ridge_porosity(ridge):
    return _RIDGE[_ridge_index(ridge)][1]


def true_alpha(ridge, tau_cr):
    """(alpha_left, alpha_right) [deg] of the synthetic failure planes."""
    off = _RIDGE[_ridge_index(ridge)][0]
    base = 15.0 + 28.0 * (1.0 - np.exp(-tau_cr / 20e3)) + off
    return base, base + 2.0


def plane_x(side, alpha_deg, y):
    """x of the synthetic failure plane on ``side`` (-1/+1) at height y."""
    return side * (W_I / 2 + (KEEL_TOP - np.asarray(y)) * np.tan(np.radians(alpha_deg)))


def travel_to_time(y, v_final=0.1, ramp=2.0):
    """t [s] at travel y [m] for a linear velocity ramp to v_final over ``ramp`` s."""
    y = np.asarray(y, dtype=float)
    y_ramp = 0.5 * v_final * ramp
    return np.where(y < y_ramp, np.sqrt(2 * ramp * np.maximum(y, 0) / v_final),
                    ramp + (y - y_ramp) / v_final)


def _mesh(porosity):
    """Triangles of the blocks, the layer (2 bodies) and the indenter."""
    nodes, tris, body, kinds = [], [], [], []

    def rect(x0, x1, y0, y1, kind):
        b = len(kinds)
        kinds.append(kind)
        n = len(nodes)
        nodes.extend([(x0, y0), (x1, y0), (x1, y1), (x0, y1)])
        tris.extend([(n, n + 1, n + 2), (n, n + 2, n + 3)])
        body.extend([b, b])

    nx, ny = int(DOMAIN), 16
    cw, ch = DOMAIN / nx, H / ny
    bw = cw * (1.0 - porosity)  # block width: solid fraction exactly 1 - eta
    for j in range(ny):
        y1 = KEEL_TOP - j * ch
        for i in range(nx):
            xc = -DOMAIN / 2 + (i + 0.5) * cw
            rect(xc - bw / 2, xc + bw / 2, y1 - ch, y1, 0)
    top = KEEL_TOP + T_C
    rect(-DOMAIN / 2, -W_I / 2, KEEL_TOP, top, 1)
    rect(W_I / 2, DOMAIN / 2, KEEL_TOP, top, 1)
    rect(-W_I / 2, W_I / 2, KEEL_TOP, top, 2)
    nodes = np.array(nodes, dtype=float)
    tris = np.array(tris, dtype=np.int32)
    p = nodes[tris]
    area = 0.5 * ((p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1])
                  - (p[:, 2, 0] - p[:, 0, 0]) * (p[:, 1, 1] - p[:, 0, 1]))
    return nodes, tris, np.array(body, dtype=np.int32), np.array(kinds, dtype=np.int8), area, p.mean(axis=1)


def _moving_fraction(xy, y_I, alphas, mu):
    """phi in [0, 1]: share of the indenter travel a point at xy moves down.
    1 inside the plug, whose planes steepen with travel (faster for low mu),
    falling linearly to 0 over 1.5 m outside it."""
    shrink = (1.0 if mu < 0.15 else 0.35) * max(0.0, y_I - 0.02) / 0.35
    x, y = xy[:, 0], xy[:, 1]
    depth = np.clip(KEEL_TOP - y, 0.0, H)
    phi = np.ones_like(x)
    for side, a in zip((-1, 1), alphas):
        a_eff = a * max(0.15, 1.0 - shrink)
        edge = W_I / 2 + depth * np.tan(np.radians(a_eff))
        out = side * x - edge
        phi = np.minimum(phi, np.clip(1.0 - out / 1.5, 0.0, 1.0))
    return np.where((y <= KEEL_TOP) & (y >= KEEL_TOP - H), phi, 0.0)


def _bonds(rng, ridge, tau_cr, jitter, n_plane=24, n_under=12, n_background=150):
    aL, aR = true_alpha(ridge, tau_cr)
    pos, y_split, y_fail = [], [], []
    for side, a in ((-1, aL), (1, aR)):
        depth = np.linspace(0.05, 1.0, n_plane) * H
        y = KEEL_TOP - depth
        x = plane_x(side, a, y) + side * jitter * rng.standard_normal(n_plane)
        rank = rng.permutation(n_plane)
        # three points per side fail at 0.5 mm (a line at y_I = 1 mm), the rest by ~9 mm
        yf = 0.5e-3 + np.maximum(rank - 2, 0) * 0.4e-3
        pos.extend(zip(x, y)); y_fail.extend(yf); y_split.extend(yf - 0.2e-3)
    # under the indenter: fail early; |x| < w_I/2 so the alpha fit must ignore them
    x = rng.uniform(-0.45 * W_I, 0.45 * W_I, n_under)
    y = KEEL_TOP - rng.uniform(0.1, 0.9, n_under) * H
    yf = rng.uniform(0.5e-3, 5e-3, n_under)
    pos.extend(zip(x, y)); y_fail.extend(yf); y_split.extend(yf - 0.1e-3)
    # background: 30 % split after the initial failure (beyond the 1-20 mm of Figs.
    # 12-15, so the planes alone carry alpha with either bond_points choice), a
    # third of those fail after 40 mm
    x = rng.uniform(-DOMAIN / 2 + 0.5, DOMAIN / 2 - 0.5, n_background)
    y = KEEL_TOP - rng.uniform(0.0, 1.0, n_background) * H
    ys = np.full(n_background, np.nan)
    yf = np.full(n_background, np.nan)
    split = rng.random(n_background) < 0.3
    ys[split] = rng.uniform(21e-3, 250e-3, split.sum())
    late = split & (rng.random(n_background) < 0.33)
    yf[late] = np.maximum(ys[late], 40e-3) + rng.uniform(1e-3, 50e-3, late.sum())
    pos.extend(zip(x, y)); y_fail.extend(yf); y_split.extend(ys)
    return np.array(pos), np.array(y_split), np.array(y_fail)


def nt_ns_target(tau_cr):
    """n_t/n_s the synthetic modes are drawn to (rises with tau_cr as in Table 3)."""
    return 0.3 + 0.022 * tau_cr / 1e3


def nt_ns_init_target(tau_cr):
    """(t_n >= 0)/(t_n < 0) at the split the synthetic tractions are drawn to."""
    return 0.5 + 0.02 * tau_cr / 1e3


def _split_tractions(rng, y_split, sigma_cr, tau_cr, mu, tau_cr_top):
    """(split_tn, split_tt) [Pa] on the boundary of eq 6: pure tension t_n = sigma_cr,
    or under compression t_n = -sigma_cr with |t_t| = tau_cr + mu sigma_cr; the
    tension side drawn for round(n r/(1 + r)) of the n split points, r =
    nt_ns_init_target. NaN where the point never split."""
    split = np.flatnonzero(np.isfinite(y_split))
    r = nt_ns_init_target(tau_cr_top)
    tension = rng.permutation(split)[:int(round(len(split) * r / (1 + r)))]
    tn = np.full(len(y_split), np.nan)
    tt = np.full(len(y_split), np.nan)
    tn[split], tt[split] = -sigma_cr[split], tau_cr[split] + mu * sigma_cr[split]
    tn[tension], tt[tension] = sigma_cr[tension], 0.0
    return tn, tt


def write_run(path, ridge, mu, tau_cr, *, jitter=0.12, travel_end=0.3, seed=None,
              snapshots=True, energy=True, complete=True, leave_part=False,
              model="fem-dem", force_direction="paper", sigma_cr=10e3, scene=None):
    """Write one synthetic run to ``path`` (``*.h5``); returns the final path.
    ``complete=False`` writes complete=0; ``leave_part=True`` leaves ``path + '.part'``."""
    if seed is None:
        seed = 1000 * _ridge_index(ridge) + int(round(mu * 100)) * 7 + int(tau_cr / 100)
    rng = np.random.default_rng(seed)
    off, eta, strength = _RIDGE[_ridge_index(ridge)]
    alphas = true_alpha(ridge, tau_cr)
    nodes, tris, body, kinds, area, centroid = _mesh(eta)
    tri_kind = kinds[body]

    # F(y_I), sampled every 0.1 mm
    y = np.round(np.arange(0.0, travel_end + 1e-9, 1e-4), 10)
    blocks = tri_kind == 0
    F_post = np.array([(RHO_W - RHO_I) * G * np.sum(area[blocks] * _moving_fraction(centroid[blocks], yy, alphas, mu))
                       for yy in np.maximum(y, 0.02)])
    tau_rubble = strength * (2.0e3 + 0.05 * tau_cr) * (1.0 + (mu - 0.05) * np.exp(-tau_cr / 20e3))
    F_m = F_post[0] + 2 * H * tau_rubble
    y_p = 1e-3
    F = np.where(y < y_p, F_m * y / y_p,
                 F_post + (F_m - F_post[0]) * np.exp(-(y - y_p) / 3e-3))
    F = F * (1.0 + 0.005 * rng.standard_normal(y.size))
    F[y < y_p] = F_m * y[y < y_p] / y_p  # keep the peak at 1 mm exactly
    t = travel_to_time(y)

    pos, ys, yf = _bonds(rng, ridge, tau_cr, jitter)
    P = len(pos)
    depth = np.clip(KEEL_TOP - pos[:, 1], 0.0, H)
    scale = 1.0 - 0.9 * depth / H
    failed = np.isfinite(yf)
    mode = np.zeros(P, dtype=np.int8)
    idx = np.flatnonzero(failed)
    r = nt_ns_target(tau_cr)
    n_t = int(round(len(idx) * r / (1 + r)))
    tens = rng.permutation(idx)[:n_t]
    mode[idx] = FailureMode.shear
    mode[tens] = FailureMode.tensile
    tensile, shear = mode == FailureMode.tensile, mode == FailureMode.shear
    dn = np.where(tensile, 1.0e-3, np.where(shear, 0.2e-3, np.nan))
    dt_ = np.where(tensile, 0.4e-3, np.where(shear, 1.0e-3, np.nan))
    split_tn, split_tt = _split_tractions(rng, ys, sigma_cr * scale, tau_cr * scale, mu, tau_cr)

    part = path + ".part"
    with h5py.File(part, "w") as f:
        f.attrs.update(format="icerubble-run", format_version=1, code_version="synthetic",
                       created=datetime.datetime.now(datetime.timezone.utc).isoformat(),
                       complete=0, ridge=str(ridge), seed=int(seed), model=model)
        if scene is not None:
            f.attrs["scene"] = scene
        f.create_group("parameters").attrs.update(
            mu=mu, tau_cr=tau_cr, sigma_cr=sigma_cr, G=15.0, E=2e9, nu=0.3, rho_i=RHO_I, rho_w=RHO_W,
            c_w=2.5e4, penalty=2e11, dt=1e-6, v_final=0.1, ramp_time=2.0, indenter_width=W_I,
            indenter_thickness=1.0, layer_thickness=T_C, keel_depth=H, domain_width=DOMAIN, g=G,
            strength_bottom_fraction=0.1, target_travel=travel_end, force_direction=force_direction)
        f.create_group("pile").attrs.update(
            porosity=eta, n_blocks=int(np.sum(kinds == 0)), keel_top_y=KEEL_TOP,
            keel_bottom_y=KEEL_TOP - H, keel_x_min=-DOMAIN / 2, keel_x_max=DOMAIN / 2)

        def ds(group, name, data, units):
            f.require_group(group).create_dataset(name, data=data).attrs["units"] = units

        ds("mesh", "nodes", nodes, "m"); ds("mesh", "triangles", tris, "-")
        ds("mesh", "body", body, "-"); ds("mesh", "body_kind", kinds, "-")
        ds("mesh", "area", area, "m^2"); ds("mesh", "centroid", centroid, "m")
        ds("force", "t", t, "s"); ds("force", "y_I", y, "m"); ds("force", "F", F, "N/m")
        if snapshots:
            f.create_group("snapshots")
            for k, mm in enumerate(m for m in SNAPSHOT_TRAVELS_MM if m * 1e-3 <= travel_end + 1e-12):
                yy = mm * 1e-3
                g = f["snapshots"].create_group(f"{k:04d}")
                g.attrs.update(t=float(travel_to_time(yy)), y_I=yy)

                def u_of(xy, kind):
                    u = np.zeros((len(xy), 2))
                    u[:, 1] = np.where(kind == 2, -yy, np.where(kind == 0, -yy * _moving_fraction(xy, yy, alphas, mu), 0.0))
                    return u
                node_kind = np.zeros(len(nodes), dtype=np.int8)
                node_kind[tris[:, 0]] = tri_kind; node_kind[tris[:, 1]] = tri_kind; node_kind[tris[:, 2]] = tri_kind
                g.create_dataset("u_elem", data=u_of(centroid, tri_kind)).attrs["units"] = "m"
                g.create_dataset("u_node", data=u_of(nodes, node_kind)).attrs["units"] = "m"
        bodies = rng.integers(0, int(np.sum(kinds == 0)), size=(P, 2)).astype(np.int32)
        for name, data, units in (
                ("position", pos, "m"), ("depth", depth, "m"), ("bodies", bodies, "-"),
                ("length", np.full(P, 0.1), "m"), ("sigma_cr", sigma_cr * scale, "Pa"),
                ("tau_cr", tau_cr * scale, "Pa"), ("G", 15.0 * scale, "J/m^2"),
                ("t_split", travel_to_time(ys), "s"), ("y_I_split", ys, "m"),
                ("t_fail", travel_to_time(yf), "s"), ("y_I_fail", yf, "m"),
                ("delta_n_fail", dn, "m"), ("delta_t_fail", dt_, "m"), ("mode", mode, "-"),
                ("split_tn", split_tn, "Pa"), ("split_tt", split_tt, "Pa")):
            ds("bonds", name, data, units)
        if energy:
            te = t[::100]
            ds("energy", "t", te, "s")
            work = np.cumsum(F[::100]) * 1e-2  # stand-in, J/m
            for term in ("kinetic", "elastic", "contact", "friction", "damping", "drag", "cohesive",
                         "work_gravity", "work_buoyancy", "residual"):
                ds("energy", term, np.zeros_like(te), "J/m")
            ds("energy", "work_boundary", work, "J/m")
        if complete:
            f.attrs["complete"] = 1
    if leave_part:
        return part
    os.replace(part, path)
    return path


def run_name(ridge, mu, tau_cr):
    return f"ridge{ridge}_mu{mu:g}_tau{tau_cr / 1e3:g}kPa.h5"


def write_set(folder, ridges=("1", "2"), mus=(0.05, 0.3), tau_crs=(5e3, 12.5e3, 25e3, 50e3, 100e3), **kw):
    """Write ridges x mus x tau_crs synthetic runs into ``folder``; returns the paths."""
    os.makedirs(folder, exist_ok=True)
    return [write_run(os.path.join(folder, run_name(r, m, tc)), r, m, tc, **kw)
            for r in ridges for m in mus for tc in tau_crs]


def main(argv=None):
    ap = argparse.ArgumentParser(prog="python3 -m tests.postproc.synthetic", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out_dir")
    ap.add_argument("--ridges", default="1,2,3,4")
    ap.add_argument("--mu", default="0.05,0.3")
    ap.add_argument("--tau-cr-kPa", default="5,12.5,25,50,100")
    args = ap.parse_args(argv)
    paths = write_set(args.out_dir, args.ridges.split(","), [float(v) for v in args.mu.split(",")],
                      [float(v) * 1e3 for v in args.tau_cr_kPa.split(",")])
    print(f"{len(paths)} SYNTHETIC run file(s) -> {args.out_dir}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
