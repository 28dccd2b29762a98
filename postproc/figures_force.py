"""Force figures: F-y_I records and peak loads (paper Figs. 6-11).
Each function takes a Catalog, writes PNG + PDF, returns the paths, or raises Missing."""
import numpy as np

from . import loads, plotting
from .catalog import Missing

PAPER_FIG9_TAU = (5e3, 12.5e3, 25e3, 50e3)


def _records_two_ridges(cat, stem, caption, y_max):
    hi, lo = cat.extreme_ridges()
    ridges = [hi] if hi == lo else [hi, lo]
    if hi == lo:
        cat.notes.append(f"{stem}: only one ridge at tau_cr = {cat.tau_ref / 1e3:g} kPa, one panel")
    fig, axes = plotting.new(ncols=len(ridges), width=5.0 * len(ridges), height=3.6)
    for ax, ridge, tag in zip(axes[0], ridges, "ab"):
        for mu in (cat.mu_low, cat.mu_high):
            run = cat.one(ridge, mu, cat.tau_ref)
            if run is None:
                cat.notes.append(f"{stem}: ridge {ridge}, mu = {mu:g} missing")
                continue
            y, F = loads.record(run, y_max)
            ax.plot(y * 1e3, F / 1e3, color=plotting.mu_style(mu)["color"], lw=0.8, label=f"μ = {mu:g}")
        ax.set(title=f"({tag}) ridge {ridge}", xlabel="indenter displacement $y_I$ [mm]",
               ylabel="indenter force $F$ [kN/m]")
        ax.legend()
    return plotting.save(fig, cat.out_dir, stem, caption)


def fig06(cat):
    """Fig. 6: F-y_I records of the ridges with highest and lowest F^m, both mu, tau_cr = 50 kPa."""
    return _records_two_ridges(cat, "fig06_force_records", f"Fig. 6: F–y_I, τ_cr = {cat.tau_ref / 1e3:g} kPa", None)


def fig07(cat):
    """Fig. 7: close-up of Fig. 6 over the first 20 mm (initial rise and peak F^m)."""
    return _records_two_ridges(cat, "fig07_force_start", f"Fig. 7: F–y_I, first 20 mm, τ_cr = {cat.tau_ref / 1e3:g} kPa", 20e-3)


def fig08(cat):
    """Fig. 8: F^m versus mu for every ridge at tau_cr = 50 kPa."""
    sel = cat.select(tau_cr=cat.tau_ref, stored=True)
    if not sel:
        raise Missing(f"no run with tau_cr = {cat.tau_ref / 1e3:g} kPa")
    fig, axes = plotting.new(width=4.5)
    ax = axes[0, 0]
    for ridge in cat.ridges(sel):
        rs = sorted(cat.select(ridge=ridge, tau_cr=cat.tau_ref, stored=True), key=lambda r: r.mu)
        ax.plot([r.mu for r in rs], [cat.row(r)["F_m_kN_per_m"] for r in rs], "o-", label=f"ridge {ridge}")
    ax.set(xlabel="friction coefficient μ [–]", ylabel="peak load $F^m$ [kN/m]")
    ax.legend()
    return plotting.save(fig, cat.out_dir, "fig08_peak_vs_mu", f"Fig. 8: F^m vs μ, τ_cr = {cat.tau_ref / 1e3:g} kPa")


def fig09(cat):
    """Fig. 9: F-y_I at the start for tau_cr = 5, 12.5, 25, 50 kPa, mu = 0.05, one ridge
    (the ridge with the most of those tau_cr values)."""
    sel = cat.select(mu=cat.mu_low)
    if not sel:
        raise Missing(f"no run with mu = {cat.mu_low:g}")
    wanted = [t for t in PAPER_FIG9_TAU if cat.select(mu=cat.mu_low, tau_cr=t)] or sorted({r.tau_cr for r in sel})
    ridge = max(cat.ridges(sel), key=lambda rd: sum(cat.one(rd, cat.mu_low, t) is not None for t in wanted))
    absent = [t for t in PAPER_FIG9_TAU if cat.one(ridge, cat.mu_low, t) is None]
    if absent:
        cat.notes.append("fig09: tau_cr = " + ", ".join(f"{t / 1e3:g}" for t in absent) +
                         f" kPa missing for ridge {ridge}, mu = {cat.mu_low:g}")
    fig, axes = plotting.new(width=5.0)
    ax = axes[0, 0]
    for t in wanted:
        run = cat.one(ridge, cat.mu_low, t)
        if run is None:
            continue
        y, F = loads.record(run, 20e-3)
        ax.plot(y * 1e3, F / 1e3, lw=0.9, label=f"τ_cr = {t / 1e3:g} kPa")
    ax.set(xlabel="indenter displacement $y_I$ [mm]", ylabel="indenter force $F$ [kN/m]",
           title=f"ridge {ridge}, μ = {cat.mu_low:g}")
    ax.legend()
    return plotting.save(fig, cat.out_dir, "fig09_force_start_tau", "Fig. 9: F–y_I at the start vs τ_cr")


def fig10(cat):
    """Fig. 10: F^m versus tau_cr, marker fill by mu, all ridges."""
    fig, axes = plotting.new(width=4.8)
    ax = axes[0, 0]
    for mu in cat.mus():
        rs = cat.select(mu=mu, stored=True)
        st = plotting.mu_style(mu)
        ax.plot([r.tau_cr / 1e3 for r in rs], [cat.row(r)["F_m_kN_per_m"] for r in rs], ls="none",
                label=f"μ = {mu:g}", **st)
    ax.set(xlabel="bond shear strength $τ_{cr}$ [kPa]", ylabel="peak load $F^m$ [kN/m]")
    ax.legend()
    return plotting.save(fig, cat.out_dir, "fig10_peak_vs_tau", "Fig. 10: F^m vs τ_cr")


def peak_ratios(cat):
    """[(ridge, tau_cr, F^m(mu_high)/F^m(mu_low))] over runs paired by ridge and tau_cr (Fig. 11)."""
    out = []
    for ridge in cat.ridges():
        for t in cat.tau_crs():
            lo, hi = cat.one(ridge, cat.mu_low, t, stored=True), cat.one(ridge, cat.mu_high, t, stored=True)
            if lo is not None and hi is not None:
                out.append((ridge, t, cat.row(hi)["F_m_kN_per_m"] / cat.row(lo)["F_m_kN_per_m"]))
    return out


def fig11(cat):
    """Fig. 11: F^m(mu = 0.3)/F^m(mu = 0.05) versus tau_cr per ridge, and the mean ratio."""
    ratios = peak_ratios(cat)
    if not ratios:
        raise Missing(f"no ridge has runs with both mu = {cat.mu_low:g} and mu = {cat.mu_high:g} at one tau_cr")
    fig, axes = plotting.new(width=4.8)
    ax = axes[0, 0]
    for ridge in sorted({r for r, _, _ in ratios}, key=lambda s: cat.ridges().index(s)):
        pts = sorted((t, q) for rd, t, q in ratios if rd == ridge)
        ax.plot([t / 1e3 for t, _ in pts], [q for _, q in pts], "o", label=f"ridge {ridge}")
    mean = float(np.mean([q for _, _, q in ratios]))
    ax.axhline(mean, color="k", ls="--", lw=0.8, label=f"mean {mean:.3f}")
    ax.set(xlabel="bond shear strength $τ_{cr}$ [kPa]",
           ylabel=f"$F^m$(μ={cat.mu_high:g}) / $F^m$(μ={cat.mu_low:g}) [–]")
    ax.legend()
    return plotting.save(fig, cat.out_dir, "fig11_peak_ratio_mu", "Fig. 11: peak-load ratio vs τ_cr")


FIGURES = {6: fig06, 7: fig07, 8: fig08, 9: fig09, 10: fig10, 11: fig11}
