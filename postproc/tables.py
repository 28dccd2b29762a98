"""Tables 2 and 3 of the paper as CSV and Markdown (one column per tau_cr present)."""
import csv
import os

import numpy as np

from icerubble.files.output_path import whole_file

from . import shear_strength
from .catalog import Missing

PAPER_TAU = (5e3, 50e3, 100e3)


def _pm(ms, digits=2):
    m, s = ms
    if not np.isfinite(m):
        return "–"
    return f"{m:.{digits}f}" if not np.isfinite(s) else f"{m:.{digits}f} ± {s:.{digits}f}"


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
    absent = [t for t in PAPER_TAU if not cat.select(tau_cr=t)]
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
    labels = {"tau1_kPa": "tau(1) [kPa], F_b = 0",
              "tau2_kPa": f"tau(2) [kPa], F_b = {cat.plug_force / 1e3:g} kN/m (cylindrical plug)",
              "tau3_kPa": "tau(3) [kPa], F_b = F_b(A_p, eta) at y_I = 20 mm (eq 13)"}
    body = [[labels[k]] + [_pm(e[k]) for e in t2] for k in shear_strength.TAU_KEYS]
    body += [[q + " [-]"] + [f"{e[q]:.2f}" if np.isfinite(e[q]) else "–" for e in t2]
             for q in ("tau1/tau3", "tau2/tau3")]
    body.append(["runs"] + [str(e["n_runs"]) for e in t2])
    return _write(cat.out_dir, "table2_shear_strength", header, body,
                  "Table 2: rubble shear strength tau (eq 15, A_s = 2h), mean ± sd over ridges and both mu.")


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
    body.append(["n_t/n_s [-]"] + [_pm(e["nt_ns"]) for e in t3])
    body.append(["ridge pairs / runs"] + [f"{e['n_pairs']} / {e['n_runs']}" for e in t3])
    return _write(cat.out_dir, "table3_ratios", header, body,
                  "Table 3: tau ratio between mu values (same ridge) and tensile/shear failure ratio n_t/n_s "
                  "of fully failed bond points, mean ± sd.")


TABLES = {2: table2, 3: table3}
