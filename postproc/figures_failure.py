"""Failure-plane figures (paper Figs. 12-15): alpha, plug area A_p, F_b(A_p, eta)."""
import numpy as np

from . import failure_plane, plotting, plug
from .catalog import Missing

W_H_NOTE = "cylindrical plug $w_I h$"


def fig12(cat, y_I=20e-3):
    """Fig. 12: failed bond points (cat.bond_points) at y_I = 20 mm of the reference run, the two
    least-squares lines, alpha on each side and the plug polygon A_p."""
    run = cat.reference_run()
    if run is None:
        raise Missing(f"no reference run (highest-F^m ridge at tau_cr = {cat.tau_ref / 1e3:g} kPa, mu = {cat.mu_low:g})")
    label = failure_plane.BOND_POINTS[cat.bond_points][1]
    pts = failure_plane.failed_points(run.bonds, y_I, cat.bond_points)
    left, right = failure_plane.fit_planes(pts, run.indenter_width)
    if left is None or right is None:
        raise Missing(f"{run.name}: fewer than {failure_plane.MIN_POINTS} {label} on a side at y_I = 20 mm")
    corners = plug.plug_polygon(left, right)
    fig, axes = plotting.new(width=8.0, height=3.6)
    ax = axes[0, 0]
    if corners is not None:
        ax.fill(corners[:, 0], corners[:, 1], color="0.8", label=f"$A_p$ = {plug.polygon_area(corners):.1f} m²")
    ax.plot(pts[:, 0], pts[:, 1], "x", color="tab:red", ms=4, label=label)
    for f in (left, right):
        ys = np.array([f.y_top, f.y_bottom])
        ax.plot(f.x_at(ys), ys, "k--", lw=1.0)
        ym = 0.5 * (f.y_top + f.y_bottom)
        ax.annotate(f"α = {f.alpha:.1f}°", (f.x_at(ym), ym), textcoords="offset points",
                    xytext=(-55 if f.side < 0 else 8, 0))
    w = run.indenter_width
    top = float(run.pile["keel_top_y"])
    ax.plot([-w / 2, w / 2, w / 2, -w / 2, -w / 2], [top, top, top + 1, top + 1, top], color="tab:blue",
            lw=1.2, label="indenter")
    ax.set(xlabel="x [m]", ylabel="y [m]", title=f"{run.name}, $y_I$ = 20 mm")
    ax.set_aspect("equal")
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0))
    return plotting.save(fig, cat.out_dir, "fig12_failure_planes", "Fig. 12: failure planes α and plug A_p")


def _yerr(sds):
    """Error bars for errorbar(): None when no sd is defined (one sample per point),
    since matplotlib 3.6 fails on an all-NaN yerr."""
    sds = np.asarray(sds, dtype=float)
    return None if not np.isfinite(sds).any() else np.nan_to_num(sds)


def _by_tau(cat, key):
    """{mu: [(tau_cr, values)]} of a per-run value (key(run)), over every run of the
    catalog, those known by their rows included."""
    out = {}
    for mu in cat.mus():
        out[mu] = [(t, np.array([key(r) for r in cat.select(mu=mu, tau_cr=t, stored=True)], dtype=float))
                   for t in cat.tau_crs() if cat.select(mu=mu, tau_cr=t, stored=True)]
    return out


def fig13(cat):
    """Fig. 13: mean +- sd of alpha over y_I = 1...20 mm (all ridges, both sides) versus tau_cr, per mu:
    the samples of the runs pooled, from each run's count, mean and sd (its summary row)."""
    parts = _by_tau(cat, lambda r: [cat.row(r)[k] for k in ("alpha_n_1_20mm", "alpha_mean_1_20mm_deg",
                                                              "alpha_sd_1_20mm_deg")])
    stats = {mu: [(t, failure_plane.pooled_mean_sd(v.reshape(-1, 3))) for t, v in rows] for mu, rows in parts.items()}
    stats = {mu: [(t, ms) for t, ms in rows if np.isfinite(ms[0])] for mu, rows in stats.items()}
    if not any(stats.values()):
        raise Missing(f"no run has {failure_plane.BOND_POINTS[cat.bond_points][1]} on a side "
                      "for y_I = 1...20 mm")
    fig, axes = plotting.new(width=4.8)
    ax = axes[0, 0]
    for i, (mu, rows) in enumerate(stats.items()):
        if not rows:
            continue
        st = plotting.mu_style(mu)
        t = np.array([tc for tc, _ in rows]) / 1e3
        ms = [m for _, m in rows]
        ax.errorbar(t * (1 + 0.02 * (i - 0.5)), [m for m, _ in ms], yerr=_yerr([s for _, s in ms]), ls="none",
                    capsize=3, label=f"μ = {mu:g}", **st)
    ax.set(xlabel="bond shear strength $τ_{cr}$ [kPa]", ylabel="failure-plane angle α [°]")
    ax.legend()
    return plotting.save(fig, cat.out_dir, "fig13_alpha_vs_tau", "Fig. 13: α, mean ± sd over y_I = 1…20 mm")


def fig14(cat):
    """Fig. 14: mean A_p over y_I = 1...20 mm versus tau_cr: (a) per ridge, (b) mean over ridges per mu."""
    if not np.isfinite([cat.row(r)["A_p_mean_1_20mm_m2"] for r in cat.every_run]).any():
        raise Missing("no run yields a plug polygon for y_I = 1...20 mm")
    fig, axes = plotting.new(ncols=2, width=9.0)
    a, b = axes[0]
    for ridge in cat.ridges():
        for mu in cat.mus():
            rs = sorted(cat.select(ridge=ridge, mu=mu, stored=True), key=lambda r: r.tau_cr)
            if rs:
                st = plotting.mu_style(mu)
                a.plot([r.tau_cr / 1e3 for r in rs], [cat.row(r)["A_p_mean_1_20mm_m2"] for r in rs], "-",
                       marker=st["marker"], mfc=st["mfc"], lw=0.7, label=f"ridge {ridge}, μ = {mu:g}")
    for mu, rows in _by_tau(cat, lambda r: cat.row(r)["A_p_mean_1_20mm_m2"]).items():
        ms = [(t / 1e3,) + failure_plane.mean_sd(v) for t, v in rows]
        b.errorbar([m[0] for m in ms], [m[1] for m in ms], yerr=_yerr([m[2] for m in ms]), capsize=3,
                   label=f"μ = {mu:g}", **plotting.mu_style(mu))
    wh = cat.every_run[0].indenter_width * cat.every_run[0].keel_depth
    for ax, tag in ((a, "(a) per ridge"), (b, "(b) mean over ridges")):
        ax.axhline(wh, color="k", ls=":", lw=0.8, label=f"{W_H_NOTE} = {wh:g} m²")
        ax.set(xlabel="bond shear strength $τ_{cr}$ [kPa]", ylabel="plug area $A_p$ [m²]", title=tag)
        ax.legend(fontsize=6)
    return plotting.save(fig, cat.out_dir, "fig14_plug_area", "Fig. 14: plug area A_p, mean over y_I = 1…20 mm")


def fig15(cat):
    """Fig. 15: F^m, F(y_I = 20 mm) and F_b(A_p, eta) versus A_p at y_I = 20 mm, tau_cr = 50 kPa."""
    sel = [r for r in cat.select(tau_cr=cat.tau_ref, stored=True) if np.isfinite(cat.row(r)["A_p_20mm_m2"])]
    if not sel:
        raise Missing(f"no run at tau_cr = {cat.tau_ref / 1e3:g} kPa with a plug polygon at y_I = 20 mm")
    fig, axes = plotting.new(width=5.0)
    ax = axes[0, 0]
    rows = [cat.row(r) for r in sel]
    Ap = np.array([r["A_p_20mm_m2"] for r in rows])
    for key, lab, mk in (("F_m_kN_per_m", "$F^m$ (cohesive peak)", "o"), ("F_20mm_kN_per_m", "$F(y_I$ = 20 mm)", "s"),
                         ("F_b_Ap_20mm_kN_per_m", "$F_b(A_p, η)$ (eq 13)", "^")):
        ax.plot(Ap, [r[key] for r in rows], mk, label=lab)
    ax.set(xlabel="plug area $A_p$ at $y_I$ = 20 mm [m²]", ylabel="force [kN/m]")
    ax.legend()
    return plotting.save(fig, cat.out_dir, "fig15_forces_vs_plug",
                         f"Fig. 15: F^m, F(20 mm), F_b vs A_p, τ_cr = {cat.tau_ref / 1e3:g} kPa")


FIGURES = {12: fig12, 13: fig13, 14: fig14, 15: fig15}
