"""A study's statistics side by side with the paper's (docs/model.md §5).

Our random ridges are not the paper's four, so the comparison is between
statistics over ridges, each of docs/model.md §5: where the peak sits, how far F
drops by 20 mm and F^m over the mean load of 150-300 mm, the spread of F^m between
ridges, the effect of μ, the failure-plane angle α and the plug area A_p by τ_cr,
the shear strengths of Table 2 and their μ ratios and the failure-mode ratio of
Table 3, the buoyant share F_b(A_p)/F^m and the correlation of post-peak F with
F_d(K) at K = 0.45 and 0.9.

    /usr/bin/python3 -m postproc.paper_comparison RESULTS_DIR [RESULTS_DIR ...]
        [--label NAME ...] [-o comparison.md] [--bond-points split|failed]
        [--stored-rows SUMMARY_CSV ...]

Two or more folders, or one that holds eq 11's two forms (or both models), give
one table with a column each beside the paper's (e.g. the paper-depth study, the
reduced study, the paper); a statistic a column cannot give is shown as —.

F^m is the cohesive peak (maximum over the first 5 mm), the record maximum beside
it; α and A_p come from the split bond points unless --bond-points failed; n_t/n_s
by mode at full failure, beside it by the side of eq 6 at the split; R(F, F_d)
from F̄, the mean over y_I ± 5 mm (docs/postproc.md, "Definitions and choices").

The cylindrical-plug load of τ^(2) is computed from each run's own geometry,
(1 - η)(ρ_w - ρ_i) g w_I h (the paper's ~11 kN/m is this for w_I = h = 4 m).

--stored-rows adds runs known by a summary.csv's rows, made where their files
were (postproc/stored_rows.py), to the first folder's (with several folders,
e.g. the paper-depth study first, the reduced study beside it): every statistic reads them;
R(F, F_d) reads their (F̄, F_d) pairs where an fd_pairs.csv lies beside the
summary.csv (postproc/fd_pairs.py), and leaves out a run that has none.
"""
import argparse
import os
import sys

import numpy as np

from icerubble import cli
from icerubble.files import results
from icerubble.files.output_path import check_output_file, whole_file

from . import displaced_area as dA
from . import failure_plane, fd_pairs, loads, plug, shear_strength, stored_rows, summary
from .failure_plane import mean_sd
from .variants import label as variant_label, row_variant

# The paper's numbers (section 3, Tables 2 and 3)
PAPER = {
    "y_peak": "~1 mm (Fig. 7)",
    "drop": "steep drop until ~20 mm (Fig. 7)",
    "load_ratio": {0.05: "2.0-3.2", 0.3: "1.9-2.6"},
    "alpha_tau": "grows with τ_cr up to 50 kPa, then levels off (Fig. 13)",
    "Ap_tau": "grows with τ_cr up to 50 kPa, then levels off (Fig. 14); a cylindrical plug: 16 m²",
    "spread": "up to ~50 % between ridges (Fig. 8)",
    "mu_50": "2-7 % (Fig. 8, 11)",
    "mu_5": "up to 28 % (Fig. 11)",
    "alpha_50": {0.05: "43 ± 8°", 0.3: "44 ± 7°"},
    "tau1": {5: "3.6 ± 0.8", 50: "5.8 ± 0.9", 100: "7.0 ± 1.3"},
    "tau2": {5: "2.3 ± 0.8", 50: "4.5 ± 0.9", 100: "5.7 ± 1.3"},
    "tau3": {5: "2.0 ± 0.6", 50: "3.0 ± 0.6", 100: "4.2 ± 1.0"},
    "ntns": {5: "0.38 ± 0.14", 50: "1.44 ± 0.61", 100: "2.54 ± 0.91"},
    "Fb_share": "~50 % (Fig. 15)",
    "tau_ratio": {"tau1": {5: "1.17 ± 0.09", 50: "1.06 ± 0.03", 100: "1.02 ± 0.01"},
                  "tau2": {5: "1.29 ± 0.12", 50: "1.07 ± 0.04", 100: "1.02 ± 0.01"},
                  "tau3": {5: "1.09 ± 0.35", 50: "1.07 ± 0.10", 100: "0.98 ± 0.12"}},
    "R": {0.45: {50.0: "0.88", None: "0.82"}, 0.9: {50.0: "0.13", None: "0.46"}},
}


def _pm(values, digits=2, unit=""):
    m, s = mean_sd(values)
    if not np.isfinite(m):
        return "—"
    n = np.count_nonzero(np.isfinite(np.asarray(values, dtype=float)))
    sd = f" ± {s:.{digits}f}" if np.isfinite(s) else ""
    return f"{m:.{digits}f}{sd}{unit} (n={n})"


def cylindrical_plug_force(run):
    return float(plug.run_buoyant_load(run, run.indenter_width * run.keel_depth))


def rows_and_runs(folder, bond_points=failure_plane.DEFAULT_BOND_POINTS, stored=()):
    """Summary rows and runs, aligned, one per case (the longer run's); a run
    known by its stored row only (``stored``) is its StoredRun."""
    runs, rows = [], []
    for path in results.find_results(folder)[0]:
        if os.sep + "scenes" + os.sep in path:   # cached piles and meshes, not runs
            continue
        try:
            run = results.load(path)
        except results.ResultFileError as exc:
            print(f"skipped: {exc}", file=sys.stderr)
            continue
        r = summary.summarize(run, plug_force=cylindrical_plug_force(run), bond_points=bond_points)
        r["tau_cr_kPa"] = round(r["tau_cr_kPa"], 6)
        runs.append(run)
        rows.append(r)
    for s in stored:   # after the files: of a case's equal travels, the file is kept
        r = s.with_strengths(None)   # tau^(2) with the row's own cylindrical plug, as above
        r["tau_cr_kPa"] = round(r["tau_cr_kPa"], 6)
        runs.append(s)
        rows.append(r)
    # a case run to 20 and to 300 mm counts once, by its longer run (docs/postproc.md)
    pairs, _ = shear_strength.longest_per_case(list(zip(rows, runs)), lambda p: shear_strength.row_case(p[0]),
                                               lambda p: shear_strength.row_travel(p[0]))
    return [r for r, _ in pairs], [run for _, run in pairs]


def _sel(rows, tau=None, mu=None):
    return [r for r in rows if (tau is None or np.isclose(r["tau_cr_kPa"], tau))
            and (mu is None or np.isclose(r["mu"], mu))]


def mu_ratio(rows, tau, key="F_m_kN_per_m"):
    """column key at μ 0.3 over the same ridge's at μ 0.05, per ridge with both."""
    low = {r["ridge"]: r for r in _sel(rows, tau, 0.05)}
    high = {r["ridge"]: r for r in _sel(rows, tau, 0.3)}
    return [high[k][key] / low[k][key] for k in sorted(set(low) & set(high))]


def mu_effect(rows, tau, key="F_m_kN_per_m"):
    """F(μ 0.3)/F(μ 0.05) - 1 per ridge, in %, of the peak in column key."""
    return [100.0 * (q - 1.0) for q in mu_ratio(rows, tau, key)]


def spread(rows, tau, mu, key="F_m_kN_per_m"):
    F = [r[key] for r in _sel(rows, tau, mu)]
    return 100.0 * (max(F) / min(F) - 1.0) if len(F) >= 2 else np.nan


def r_fd(runs, tau=None, K=0.45, single_sample=False, pairs_of=stored_rows.pairs_of):
    """R(F, F_d(K)) over the snapshots at y_I = 20...150 mm (Fig. 20's), the number of pairs and F/F_d;
    F is F̄, the mean over y_I ± 5 mm, or with ``single_sample`` F(y_I) itself (how
    R was computed before F̄). ``pairs_of(run)``: the run's pairs (stored_rows.pairs_of)."""
    col = "F_sample_kN_per_m" if single_sample else "F_mean_kN_per_m"
    x, y = [], []
    for run in runs:
        if tau is not None and not np.isclose(run.tau_cr / 1e3, tau):
            continue
        for p in filter(fd_pairs.in_fig20, pairs_of(run) or ()):
            x.append(p[fd_pairs.f_d_column(K)] * 1e3)
            y.append(p[col] * 1e3)
    R = dA.correlation(x, y)[0] if len(x) > 2 else np.nan
    ratio = np.asarray(y) / np.asarray(x) if x else np.array([np.nan])
    return R, len(x), ratio


def describe(rows, runs=None):
    """One line naming the runs a column reads and the definitions it uses;
    ``runs``: its runs, files and StoredRuns, to say how many are known by their
    rows only and how many of those R reads by their stored pairs."""
    kept = [r for r in runs or () if isinstance(r, stored_rows.StoredRun)]
    with_pairs = sum(r.fd_pairs is not None for r in kept)
    stored = "" if not kept else (f"; {len(kept)} of them known by stored summary rows only ("
                                  + ("not in R" if not with_pairs else
                                     "in R by their stored (F̄, F_d) pairs" if with_pairs == len(kept) else
                                     f"{with_pairs} in R by their stored (F̄, F_d) pairs, {len(kept) - with_pairs} "
                                     "not in R") + ")")
    taus = sorted({r["tau_cr_kPa"] for r in rows})
    ridges = sorted({r["ridge"] for r in rows})
    mus = sorted({r["mu"] for r in rows})
    window = loads.COHESIVE_PEAK_TRAVEL * 1e3
    return (f"Runs: {len(rows)}{stored} ({len(ridges)} ridges, μ {', '.join(f'{m:g}' for m in mus)}, "
            f"τ_cr {', '.join(f'{t:g}' for t in taus)} kPa); travel up to "
            f"{max(r['y_I_end_mm'] for r in rows):.0f} mm; keel depth "
            f"{_pm([r['keel_depth_m'] for r in rows])} m, indenter width "
            f"{rows[0]['indenter_width_m']:g} m, porosity {_pm([r['porosity'] for r in rows])}. "
            f"F^m: the cohesive peak (maximum over 0-{window:g} mm); α, A_p: "
            f"{failure_plane.BOND_POINTS[rows[0]['bond_points']][1]}.")


def statistics(rows, runs):
    """[(statistic, this study, paper), ...] in a fixed order; a statistic the
    runs cannot give (no run at its τ_cr or μ, one ridge for a spread, no
    snapshot at 20-150 mm for R) is left out."""
    mus = sorted({r["mu"] for r in rows})
    window = loads.COHESIVE_PEAK_TRAVEL * 1e3
    S = []
    S.append(("y_I at F^m [mm], all runs", _pm([r['y_I_peak_mm'] for r in rows]), PAPER['y_peak']))
    if _sel(rows, 50.0):
        S.append(("y_I at F^m [mm], τ_cr 50 kPa", _pm([r['y_I_peak_mm'] for r in _sel(rows, 50.0)]),
                  PAPER['y_peak']))
    late = sum(r["y_I_record_max_mm"] > window for r in rows)
    S.append((f"runs whose record maximum lies beyond {window:g} mm", f"{late} of {len(rows)}",
              "none (F^m is the cohesive peak and the maximum)"))
    S.append(("F^m [kN/m]; record maximum [kN/m] at y_I [mm]",
              f"{_pm([r['F_m_kN_per_m'] for r in rows], 1)}; {_pm([r['F_record_max_kN_per_m'] for r in rows], 1)} at "
              f"{_pm([r['y_I_record_max_mm'] for r in rows])}", "one and the same, at ~1 mm"))
    drop = [r["F_20mm_kN_per_m"] / r["F_m_kN_per_m"] for r in rows]
    S.append(("F(20 mm)/F^m, all runs", _pm(drop), PAPER['drop']))
    for mu in mus:   # runs that reach 300 mm
        q = [r["F_m_kN_per_m"] / r["F_mean_150_300mm_kN_per_m"] for r in _sel(rows, mu=mu)
             if np.isfinite(r["F_mean_150_300mm_kN_per_m"])]
        if q:
            S.append((f"F^m / mean F over y_I 150-300 mm, μ {mu:g}", f"{_pm(q)}; range {min(q):.2f} to "
                      f"{max(q):.2f}", PAPER["load_ratio"].get(mu, "—")))
    for key, what in (("F_m_kN_per_m", "F^m"), ("F_record_max_kN_per_m", "record maximum")):
        for mu in mus:
            if len(_sel(rows, 50.0, mu)) >= 2:
                S.append((f"{what} spread between ridges, τ_cr 50 kPa, μ {mu:g} [%]",
                          f"{spread(rows, 50.0, mu, key):.0f}", PAPER['spread']))
    for tau, paper_key in ((50.0, "mu_50"), (5.0, "mu_5"), (100.0, None)):
        eff = mu_effect(rows, tau)
        if eff:
            S.append((f"F^m(μ 0.3)/F^m(μ 0.05) - 1, τ_cr {tau:g} kPa [%]",
                      f"{_pm(eff, 1)}; range {min(eff):.1f} to {max(eff):.1f}",
                      PAPER[paper_key] if paper_key else "~2.5 % (Fig. 11)"))
    for mu in mus:
        sel = _sel(rows, 50.0, mu)
        if sel:
            S.append((f"α over y_I 1-20 mm, τ_cr 50 kPa, μ {mu:g} [°] (run means)",
                      _pm([r["alpha_mean_1_20mm_deg"] for r in sel], 0), PAPER['alpha_50'].get(mu, '—')))
    for tau in (5.0, 50.0, 100.0):   # the trend with τ_cr, both μ
        sel = _sel(rows, tau)
        if sel:
            S.append((f"α over y_I 1-20 mm, τ_cr {tau:g} kPa [°] (run means)",
                      _pm([r["alpha_mean_1_20mm_deg"] for r in sel], 0), PAPER["alpha_tau"]))
    for tau in (5.0, 50.0, 100.0):
        sel = _sel(rows, tau)
        if sel:
            S.append((f"A_p over y_I 1-20 mm, τ_cr {tau:g} kPa [m²] (run means)",
                      _pm([r["A_p_mean_1_20mm_m2"] for r in sel], 0), PAPER["Ap_tau"]))
    for key, label in (("tau1", "τ^(1)"), ("tau2", "τ^(2)"), ("tau3", "τ^(3)")):
        for tau in (5.0, 50.0, 100.0):
            sel = _sel(rows, tau)
            if sel:
                S.append((f"Table 2 {label} [kPa], τ_cr {tau:g} kPa", _pm([r[key + '_kPa'] for r in sel]),
                          PAPER[key][int(tau)]))
    for key, label in (("tau1", "τ^(1)"), ("tau2", "τ^(2)"), ("tau3", "τ^(3)")):
        for tau in (5.0, 50.0, 100.0):
            q = mu_ratio(rows, tau, key + "_kPa")
            if q:
                S.append((f"Table 3 {label}(μ 0.3)/{label}(μ 0.05), τ_cr {tau:g} kPa (per ridge)", _pm(q),
                          PAPER["tau_ratio"][key][int(tau)]))
    for tau in (5.0, 50.0, 100.0):
        sel = _sel(rows, tau)
        if sel:
            S.append((f"τ^(1) from the record maximum [kPa], τ_cr {tau:g} kPa",
                      _pm([r['tau1_record_max_kPa'] for r in sel]), f"{PAPER['tau1'][int(tau)]} (F^m)"))
    for tau in (5.0, 50.0, 100.0):
        sel = _sel(rows, tau)
        if not sel:
            continue
        sums = {k: np.sum([r[k] for r in sel]) for k in ("n_t", "n_s", "n_t_init", "n_s_init")}
        # NaN initiation counts (a file without /bonds/split_tn) make the sum NaN: shown as —
        init = f"{sums['n_t_init']:.0f}:{sums['n_s_init']:.0f}" if np.isfinite(sums["n_t_init"]) else "—"
        S.append((f"Table 3 n_t/n_s (mode at full failure), τ_cr {tau:g} kPa",
                  f"{_pm([r['nt_ns'] for r in sel])}; summed {sums['n_t']:.0f}:{sums['n_s']:.0f}",
                  PAPER['ntns'][int(tau)]))
        S.append((f"n_t/n_s at initiation (t_n ≥ 0 : t_n < 0 at the split), τ_cr {tau:g} kPa",
                  f"{_pm([r['nt_ns_init'] for r in sel])}; summed {init}", "—"))
        S.append((f"fully failed / split bond points, τ_cr {tau:g} kPa", _pm([r['failed_fraction'] for r in sel]), "—"))
    sel = _sel(rows, 50.0)
    if sel:
        share = [r["F_b_Ap_20mm_kN_per_m"] / r["F_m_kN_per_m"] for r in sel]
        S.append(("F_b(A_p, η)/F^m, τ_cr 50 kPa", _pm(share), PAPER['Fb_share']))
    half = dA.LOAD_WINDOW_HALF_WIDTH * 1e3
    cache = {}

    def pairs_of(run):   # each run's snapshots read once for the eight R below
        if id(run) not in cache:
            cache[id(run)] = stored_rows.pairs_of(run)
        return cache[id(run)]
    for K in fd_pairs.R_K:
        for tau in (50.0, None):
            what = "τ_cr 50 kPa" if tau else "all runs"
            R, n, ratio = r_fd(runs, tau, K=K, pairs_of=pairs_of)
            if n == 0:   # no snapshot at 20-150 mm
                continue
            R1 = r_fd(runs, tau, K=K, single_sample=True, pairs_of=pairs_of)[0]
            S.append((f"R(F̄, F_d(K {K:g})), F̄ over y_I ± {half:g} mm, y_I 20-150 mm, {what}",
                      f"{R:.2f} ({n} points; from single samples of F {R1:.2f}); F̄/F_d {np.nanmedian(ratio):.2f} "
                      "(median)", f"{PAPER['R'][K][tau]} (Fig. 20, y_I 20-150 mm)"))
    return S


def table(rows, runs):
    L = [describe(rows, runs), "", "| statistic | this study | paper |", "|---|---|---|"]
    L += [f"| {what} | {ours} | {paper} |" for what, ours, paper in statistics(rows, runs)]
    return "\n".join(L)


def side_by_side(columns):
    """One table, a column per (name, rows, runs) and the paper's last: the rows
    are the statistics in statistics()' order, — where a column cannot give one
    (e.g. no run at that τ_cr). Each column's runs are described below the
    table."""
    stats = [(name, statistics(rows, runs)) for name, rows, runs in columns]
    paper = {what: p for _, S in stats for what, _, p in S}
    # statistics()' order: every condition for a row holds on the pooled runs
    # when it holds on one column's, so their list names every row in order
    pooled = statistics([r for _, rows, _ in columns for r in rows], [run for _, _, runs in columns for run in runs])
    order = [what for what, _, _ in pooled if what in paper]
    assert len(order) == len(paper), "a column's statistic the pooled runs do not give"
    L = ["| statistic | " + " | ".join(name for name, _ in stats) + " | paper |",
         "|---|" + "---|" * (len(stats) + 1)]
    values = [{w: v for w, v, _ in S} for _, S in stats]
    for what in order:
        L.append(f"| {what} | " + " | ".join(col.get(what, "—") for col in values) + f" | {paper[what]} |")
    L.append("")
    L += [f"- **{name}**: {describe(rows, runs)}" for name, rows, runs in columns]
    return "\n".join(L)


def columns(folders, labels=None, bond_points=failure_plane.DEFAULT_BOND_POINTS, stored=()):
    """(name, rows, runs) per folder and variant (postproc/variants.py), in the
    folders' order: a folder's name is its label (its path if none), followed
    by the variant when the folder holds more than one, so eq 11's two forms,
    or two scenes found in one folder, are two columns. ``stored``: runs known
    by their rows only (in runs as their StoredRuns), of the first folder: the
    study whose files went with their machines, the others beside it as run here."""
    out = []
    for k, folder in enumerate(folders):
        rows, runs = rows_and_runs(folder, bond_points, stored if k == 0 else ())
        if not rows:
            raise ValueError(f"no complete run results under {folder}")
        name = labels[k] if labels else folder
        keys = sorted({row_variant(r) for r in rows})
        for key in keys:
            sel = [i for i, r in enumerate(rows) if row_variant(r) == key]
            out.append((name if len(keys) == 1 else f"{name} ({variant_label(key, keys)})",
                        [rows[i] for i in sel], [runs[i] for i in sel]))
    return out


def comparison(cols):
    """The table of one column, or the columns side by side."""
    if len(cols) == 1:
        return table(cols[0][1], cols[0][2])
    return side_by_side(cols)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="icerubble compare", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results_dir", nargs="+",
                    help="folders of runs; two or more are put side by side (e.g. the paper-depth and the reduced study)")
    ap.add_argument("--label", action="append",
                    help="a column's name, once per folder in the same order (default: the folder's path)")
    ap.add_argument("-o", "--out", help="also write the Markdown table here")
    summary.add_bond_points_option(ap)
    stored_rows.add_option(ap)
    a = ap.parse_args(argv)
    if a.label and len(a.label) != len(a.results_dir):
        ap.error(f"--label given {len(a.label)} times for {len(a.results_dir)} folders: give one per folder or none")
    for folder in a.results_dir:
        if not os.path.isdir(folder):
            raise ValueError(f"{folder}: no such folder of results")
    if a.out:
        check_output_file(a.out, "--out")
    stored = stored_rows.read_all(a.stored_rows, a.bond_points)
    text = comparison(columns(a.results_dir, a.label, a.bond_points, stored))
    print(text)
    if a.out:
        with whole_file(a.out) as f:
            f.write(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(cli.run("compare", sys.argv[1:]))
