"""Deformation figures (paper Figs. 16-20): u_y fields, displaced area A_d(K, y_I),
F_d (eq 14) and the F-A_d correlation."""
import numpy as np
from matplotlib.collections import PolyCollection

from icerubble.files.results import BLOCK

from . import displaced_area as dA
from . import loads, plotting, plug
from .catalog import Missing

FIG18_K = (0.45, 0.9)


def _snapshot_or_missing(run, y_I):
    snap = run.nearest_snapshot(y_I)
    if snap is None:
        why = run.missing.get("snapshots") or f"no snapshot within tolerance of y_I = {y_I * 1e3:g} mm"
        raise Missing(f"{run.name}: {why}")
    return snap


def field_panel(ax, run, y_I, x_lim=10.0, mask_K=None):
    """u_y [mm] per element on the initial mesh, -x_lim <= x <= x_lim (Figs. 16, 19);
    with mask_K, the A_d(K) elements are shaded instead (Fig. 17)."""
    snap = _snapshot_or_missing(run, y_I)
    polys = run.mesh_polygons()
    u_y = run.u_elem(snap)[:, 1]
    keep = (np.abs(run.elem_centroid[:, 0]) <= x_lim) & (run.elem_kind != 2)
    if mask_K is None:
        pc = PolyCollection(polys[keep], array=u_y[keep] * 1e3, cmap="viridis", edgecolors="none", antialiaseds=False)
        pc.set_clim(-snap.y_I * 1e3, 0.0)
        ax.add_collection(pc)
        ax.figure.colorbar(pc, ax=ax, label="$u_y$ [mm]", shrink=0.8)
    else:
        ax.add_collection(PolyCollection(polys[keep], facecolors="0.85", edgecolors="none"))
        for K, color in mask_K:
            sel = keep & (run.elem_kind == BLOCK) & (-u_y > K * snap.y_I)
            ax.add_collection(PolyCollection(polys[sel], facecolors=color, edgecolors="none", alpha=0.8,
                                             label=f"$u_y$ < −{K:g} $y_I$"))
        ax.legend(loc="lower right", fontsize=7)
    w = run.indenter_width
    for x in (-w / 2, w / 2):
        ax.axvline(x, color="w" if mask_K is None else "k", ls="--", lw=1.5)
    ax.grid(False)
    ax.set(xlim=(-x_lim, x_lim), xlabel="x [m]", ylabel="y [m]",
           ylim=(float(run.pile["keel_bottom_y"]) - 0.2, float(run.pile["keel_top_y"]) + 1.2))
    ax.set_aspect("equal")
    return snap


def fig16(cat, y_I=5e-3):
    """Fig. 16: u_y at y_I = 5 mm for the highest- and lowest-F^m ridges (tau_cr = 50 kPa, mu = 0.05)."""
    hi, lo = cat.extreme_ridges()
    ridges = [hi] if hi == lo else [hi, lo]
    fig, axes = plotting.new(nrows=len(ridges), width=7.5, height=2.6 * len(ridges))
    for ax, ridge, tag in zip(axes[:, 0], ridges, "ab"):
        run = cat.one(ridge, cat.mu_low, cat.tau_ref)
        snap = field_panel(ax, run, y_I)
        ax.set_title(f"({tag}) ridge {ridge}, $y_I$ = {snap.y_I * 1e3:g} mm", fontsize=8)
    return plotting.save(fig, cat.out_dir, "fig16_uy_5mm", "Fig. 16: vertical displacement u_y at y_I = 5 mm")


def fig17(cat, y_I=100e-3):
    """Fig. 17: definition of A_d(K, y_I): the rubble with u_y < -K y_I for K = 0.5 and 0.9."""
    run = cat.reference_run()
    fig, axes = plotting.new(width=7.5, height=2.8)
    snap = field_panel(axes[0, 0], run, y_I, mask_K=((0.5, "tab:orange"), (0.9, "tab:blue")))
    axes[0, 0].set_title(f"{run.name}, $y_I$ = {snap.y_I * 1e3:g} mm", fontsize=8)
    return plotting.save(fig, cat.out_dir, "fig17_displaced_area_definition", "Fig. 17: A_d(K, y_I) for K = 0.5, 0.9")


def fig18(cat):
    """Fig. 18: F(y_I), F̄ (mean over y_I ± 5 mm) at the snapshots and F_d(K = 0.45,
    0.9; y_I) for y_I = 20...150 mm, reference run."""
    run = cat.reference_run()
    Fd = dA.displaced_loads(run, FIG18_K, dA.FIG20_TRAVELS)
    if not np.isfinite(Fd).any():
        raise Missing(f"{run.name}: no snapshots at y_I = 20...150 mm")
    fig, axes = plotting.new(width=5.0)
    ax = axes[0, 0]
    y, F = loads.record(run, 155e-3)
    keep = y >= 15e-3
    ax.plot(y[keep] * 1e3, F[keep] / 1e3, "-", color="0.6", lw=0.6, label="F")
    have = [t for t in dA.FIG20_TRAVELS if run.force_y[-1] >= t]
    half = dA.LOAD_WINDOW_HALF_WIDTH * 1e3
    ax.plot(np.array(have) * 1e3, [dA.paired_load(run, t) / 1e3 for t in have], "ks", ms=3,
            label=f"F̄, mean over $y_I$ ± {half:g} mm")
    for j, (K, ls) in enumerate(zip(FIG18_K, ("--", "-."))):
        ax.plot(dA.FIG20_TRAVELS * 1e3, Fd[:, j] / 1e3, ls, marker="o", ms=3, label=f"$F_d$(K = {K:g})")
    ax.set(xlabel="indenter displacement $y_I$ [mm]", ylabel="force [kN/m]", title=run.name)
    ax.legend()
    return plotting.save(fig, cat.out_dir, "fig18_Fd_vs_travel", "Fig. 18: F and F_d (eq 14) vs y_I")


def fig19(cat, y_I=150e-3):
    """Fig. 19: u_y at y_I = 150 mm for the reference run (compare Fig. 16a)."""
    run = cat.reference_run()
    fig, axes = plotting.new(width=7.5, height=2.8)
    snap = field_panel(axes[0, 0], run, y_I)
    axes[0, 0].set_title(f"{run.name}, $y_I$ = {snap.y_I * 1e3:g} mm", fontsize=8)
    return plotting.save(fig, cat.out_dir, "fig19_uy_150mm", "Fig. 19: vertical displacement u_y at y_I = 150 mm")


def f_ad_data(cat, runs):
    """(A_d [m^2] (n, 3), F̄ [N/m] (n,)) of Fig. 20 over runs, K = 0.1, 0.45, 0.9 and
    y_I = 20...150 mm, F̄ the mean load over y_I ± 5 mm (displaced_area.paired_load);
    pairs without a snapshot or force record are dropped."""
    As, Fs = [], []
    for run in runs:
        A = dA.displaced_areas(run, dA.FIG20_K, dA.FIG20_TRAVELS)
        for i, t in enumerate(dA.FIG20_TRAVELS):
            if np.isfinite(A[i]).all() and run.force_y[-1] >= t:
                As.append(A[i])
                Fs.append(dA.paired_load(run, t))
    return np.array(As).reshape(-1, len(dA.FIG20_K)), np.array(Fs)


def fig20(cat):
    """Fig. 20: F against A_d(K, y_I), K = 0.1, 0.45, 0.9, with R, the linear fit, and the
    buoyancy line (1 - mean eta)(rho_w - rho_i) g A: (a) tau_cr = 50 kPa, (b) all runs."""
    panels = [("(a) τ_cr = %g kPa" % (cat.tau_ref / 1e3), cat.select(tau_cr=cat.tau_ref)),
              ("(b) all runs", cat.runs)]
    data = [(title, runs, f_ad_data(cat, runs)) for title, runs in panels]
    if all(F.size == 0 for _, _, (_, F) in data):
        raise Missing("no run has snapshots at y_I = 20...150 mm")
    fig, axes = plotting.new(ncols=2, width=9.5, height=3.8)
    colors = ("tab:green", "tab:red", "tab:blue")
    for ax, (title, runs, (A, F)) in zip(axes[0], data):
        ax.set(title=title, xlabel="displaced area $A_d(K, y_I)$ [m²]",
               ylabel=f"F̄, mean over $y_I$ ± {dA.LOAD_WINDOW_HALF_WIDTH * 1e3:g} mm [kN/m]")
        if F.size == 0:
            cat.notes.append(f"fig20 {title}: no snapshots at y_I = 20...150 mm")
            continue
        for j, (K, c) in enumerate(zip(dA.FIG20_K, colors)):
            R, s, i0 = dA.correlation(A[:, j], F)
            ax.plot(A[:, j], F / 1e3, "o", ms=3, color=c, alpha=0.7,
                    label=f"K = {K:g}: R = {R:.2f}, F = {s / 1e3:.2f}A {i0 / 1e3:+.1f} kN/m")
            xs = np.array([A[:, j].min(), A[:, j].max()])
            if np.isfinite(s):
                ax.plot(xs, (s * xs + i0) / 1e3, "-", color=c, lw=0.8)
        eta = float(np.mean([r.porosity for r in runs]))
        r0 = runs[0]
        xs = np.array([0.0, np.nanmax(A)])
        ax.plot(xs, plug.buoyant_load(xs, eta, r0.param("rho_w", plug.RHO_W), r0.param("rho_i", plug.RHO_I),
                                      r0.param("g", plug.G)) / 1e3, "k--", lw=0.8,
                label=f"(1−η̄)(ρ_w−ρ_i)gA, η̄ = {eta:.3f}")
        ax.legend(fontsize=6)
    return plotting.save(fig, cat.out_dir, "fig20_F_vs_Ad", "Fig. 20: F vs A_d(K, y_I), y_I = 20…150 mm")


FIGURES = {16: fig16, 17: fig17, 18: fig18, 19: fig19, 20: fig20}
