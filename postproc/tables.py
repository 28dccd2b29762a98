"""Tables 2 and 3 of the paper as CSV and Markdown (one column per tau_cr present)."""
import csv
import os

import numpy as np

from icerubble.files.output_path import whole_file

from . import loads, shear_strength
from .catalog import Missing

PAPER_TAU = (5e3, 50e3, 100e3)


def _pm(ms, digits=2):
    m, s = ms
    if not np.isfinite(m):
        return "–"
    return f"{m:.{digits}f}" if not np.isfinite(s) else f"{m:.{digits}f} ± {s:.{digits}f}"


def _sums(entry, t, s):
    a, b = entry[t + "_sum"], entry[s + "_sum"]
    return f"{a:.0f} : {b:.0f}" if np.isfinite(a) and np.isfinite(b) else "–"


def _write(out_dir, stem, header, body, caption):
    paths = [os.path.join(out_dir, stem + ".csv"), os.path.join(out_dir, stem + ".md")]
    with whole_file(paths[0], newline="") as fh:
        w = csv.writer(fh)
        w.writerow(header)
        w.writerows(body)
    with whole_file(paths[1]) as fh:
        fh.write(f"{caption}\n\n| " + " | ".join(header) + " |\n|" + "---|" * len(header) + "\n")
        for row in body:
            fh.write("| " + " | ".join(str(c) for c in row) + " |\n")
    return paths


def _note_paper_columns(cat, stem):
    absent = [t for t in PAPER_TAU if not cat.select(tau_cr=t, stored=True)]
    if absent:
        cat.notes.append(f"{stem}: paper column(s) tau_cr = " + ", ".join(f"{t / 1e3:g}" for t in absent) +
                         " kPa have no runs")


def table2(cat):
    """Table 2: tau^(1..3) = (F^m - F_b)/(2h) mean ± sd [kPa] per tau_cr (eq 15), both mu,
    and the ratios tau1/tau3, tau2/tau3 of the means."""
    rows = list(cat.rows.values())
    if not rows:
        raise Missing("no runs")
    _note_paper_columns(cat, "table2")
    t2 = shear_strength.table2(rows)
    header = ["quantity"] + [f"tau_cr = {e['tau_cr_kPa']:g} kPa" for e in t2]
    window = f"{loads.COHESIVE_PEAK_TRAVEL * 1e3:g} mm"
    labels = {"tau1_kPa": "tau(1) [kPa], F_b = 0",
              "tau2_kPa": f"tau(2) [kPa], F_b = {cat.plug_force / 1e3:g} kN/m (cylindrical plug)",
              "tau3_kPa": f"tau(3) [kPa], F_b = F_b(A_p, eta) at y_I = 20 mm (eq 13), {cat.bond_points} bond points",
              "F_m_kN_per_m": f"F^m [kN/m], cohesive peak (maximum over y_I = 0-{window})",
              "F_record_max_kN_per_m": "record maximum [kN/m] (beside F^m)",
              "tau1_record_max_kPa": "tau(1) [kPa] from the record maximum (beside tau(1))"}
    body = [[labels[k]] + [_pm(e[k]) for e in t2] for k in shear_strength.TAU_KEYS]
    body += [[q + " [-]"] + [f"{e[q]:.2f}" if np.isfinite(e[q]) else "–" for e in t2]
             for q in ("tau1/tau3", "tau2/tau3")]
    body += [[labels[k]] + [_pm(e[k]) for e in t2] for k in shear_strength.PEAK_KEYS]
    body.append(["runs"] + [str(e["n_runs"]) for e in t2])
    return _write(cat.out_dir, "table2_shear_strength", header, body,
                  f"Table 2: rubble shear strength tau (eq 15, A_s = 2h) from F^m, the cohesive peak (maximum over "
                  f"the first {window}), mean ± sd over ridges and both mu; the record maximum and tau(1) from it "
                  "below, for runs where a later event beat the peak.")


def table3(cat):
    """Table 3: tau(mu=0.3)/tau(mu=0.05) per tau measure (paired by ridge) and n_t/n_s, mean ± sd."""
    rows = list(cat.rows.values())
    if not rows:
        raise Missing("no runs")
    _note_paper_columns(cat, "table3")
    t3 = shear_strength.table3(rows, cat.mu_low, cat.mu_high)
    if not any(e["n_pairs"] for e in t3):
        cat.notes.append(f"table3: no ridge has both mu = {cat.mu_low:g} and {cat.mu_high:g} at one tau_cr; "
                         "ratio rows are empty")
    header = ["quantity"] + [f"tau_cr = {e['tau_cr_kPa']:g} kPa" for e in t3]
    body = [[f"tau(mu={cat.mu_high:g})/tau(mu={cat.mu_low:g}) [-], {k[:4]}"] + [_pm(e[k + "_ratio"]) for e in t3]
            for k in shear_strength.TAU_KEYS]
    body.append(["n_t/n_s [-], mode at full failure (the paper's)"] + [_pm(e["nt_ns"]) for e in t3])
    body.append(["n_t : n_s summed over runs"] + [_sums(e, "n_t", "n_s") for e in t3])
    body.append(["n_t/n_s [-] at initiation, t_n >= 0 : t_n < 0 at the split"] + [_pm(e["nt_ns_init"]) for e in t3])
    body.append(["n_t : n_s at initiation summed over runs"] + [_sums(e, "n_t_init", "n_s_init") for e in t3])
    body.append(["fully failed / split bond points [-]"] + [_pm(e["failed_fraction"]) for e in t3])
    body.append(["travel of the runs counted [mm]"] + [", ".join(f"{y:g}" for y in e["y_I_end_mm"]) or "–"
                                                        for e in t3])
    body.append(["ridge pairs / runs"] + [f"{e['n_pairs']} / {e['n_runs']}" for e in t3])
    return _write(cat.out_dir, "table3_ratios", header, body,
                  "Table 3: tau ratio between mu values (same ridge); tensile/shear ratio n_t/n_s by mode at full "
                  "failure (delta_n >= |delta_t| at delta_e = delta_f) of the points fully failed within the run "
                  "(of a case run to 20 and to 300 mm, the 300 mm run), "
                  "beside it the ratio by the side of eq 6 at the split and the share of split points that fully "
                  "failed; mean ± sd over runs.")


TABLES = {2: table2, 3: table3}
