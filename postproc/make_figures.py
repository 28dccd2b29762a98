"""Every figure (Figs. 6-20) and table (Tables 2-3) of Polojärvi & Tuhkuri (2013)
from a folder of run results.

    /usr/bin/python3 -m postproc.make_figures RESULTS_DIR [-o OUT_DIR] [--bond-points split|failed]
                                              [--stored-rows SUMMARY_CSV ...]

Reads every complete ``*.h5`` under RESULTS_DIR (recursively; ``*.h5.part`` and
files with complete != 1 are skipped and reported). Runs are grouped by ridge (root
attr ``ridge``), mu and tau_cr (/parameters). Runs of a different scene, ``model``
or ``force_direction`` are never mixed (postproc/variants.py): with more than one
such variant, each gets its own sub-folder of OUT_DIR. Writes PNG + PDF per figure, CSV + Markdown per table,
summary.csv (one row per run), fd_pairs.csv (the (F̄, F_d) pairs of R(F, F_d),
postproc/fd_pairs.py) and MISSING.md (what could not be made and why).
--bond-points picks the points behind alpha and A_p (Figs. 12-15, Table 2's
tau^(3)): 'split' (the failure criterion reached, the paper's; default) or
'failed' (fully failed); docs/postproc.md, "Definitions and choices".
--stored-rows adds runs known by a summary.csv's rows only, made where their files
were (postproc/stored_rows.py): they join Tables 2-3 and Figs. 8, 10, 11, 13-15,
and the summary.csv written here (their pairs the fd_pairs.csv), so that the next
call can take them again.
Exit status: 0 when it ran (even if some items are missing), 1 if a figure failed
with an unexpected error, 2 if no readable run was found.
"""
import argparse
import os
import sys
import traceback

from icerubble import cli
from icerubble.files import results
from icerubble.files.output_path import check_output_folder, whole_file

from . import (failure_plane, fd_pairs, figures_deformation, figures_failure, figures_force, plotting,
               shear_strength, stored_rows, summary, tables)
from .catalog import Catalog, Missing
from .variants import folder as variant_folder, variant

FIGURES = {**figures_force.FIGURES, **figures_failure.FIGURES, **figures_deformation.FIGURES}
FIGURE_STEMS = {
    6: "fig06_force_records", 7: "fig07_force_start", 8: "fig08_peak_vs_mu", 9: "fig09_force_start_tau",
    10: "fig10_peak_vs_tau", 11: "fig11_peak_ratio_mu", 12: "fig12_failure_planes", 13: "fig13_alpha_vs_tau",
    14: "fig14_plug_area", 15: "fig15_forces_vs_plug", 16: "fig16_uy_5mm", 17: "fig17_displaced_area_definition",
    18: "fig18_Fd_vs_travel", 19: "fig19_uy_150mm", 20: "fig20_F_vs_Ad",
}
TABLE_STEMS = {2: "table2_shear_strength", 3: "table3_ratios"}


def promised_files(out_dir):
    """Every file a complete set of runs yields in one variant's folder."""
    out = [os.path.join(out_dir, f"{s}.{e}") for s in FIGURE_STEMS.values() for e in ("png", "pdf")]
    out += [os.path.join(out_dir, f"{s}.{e}") for s in TABLE_STEMS.values() for e in ("csv", "md")]
    return out + [os.path.join(out_dir, "summary.csv"), os.path.join(out_dir, fd_pairs.FILE_NAME)]


def _dedupe(runs, report):
    """One run per case (ridge, mu, tau_cr) of a variant: the one with the longest
    travel, of equal ones the first (shear_strength.longest_per_case: a case run to
    20 mm and, from the same rest state, to 300 mm is read from its 300 mm run;
    runs with records come before stored rows, so of equal travels the file wins)."""
    travel = stored_rows.travel
    kept, dropped = shear_strength.longest_per_case(runs, lambda r: (r.ridge, round(r.mu, 9), round(r.tau_cr, 6)),
                                                    travel)
    def named(r):   # a file and its own stored row share a name: say which of the two is meant
        return f"{r.name} (stored row)" if isinstance(r, stored_rows.StoredRun) else r.name

    for drop, keep in dropped:
        report.append(f"- duplicate run (ridge {drop.ridge}, mu {drop.mu:g}, tau_cr {drop.tau_cr / 1e3:g} kPa): "
                      f"using {named(keep)}, ignoring {named(drop)}"
                      + (f" (the longer travel, {travel(keep) * 1e3:g} mm)"
                         if shear_strength.longer(travel(keep), travel(drop)) else ""))
    return kept


def make_variant(runs, out_dir, tau_ref, plug_force, report, bond_points=failure_plane.DEFAULT_BOND_POINTS,
                 stored=()):
    """Figures, tables and summary for one variant (``stored``: its runs known by
    their rows only); appends MISSING lines to ``report``. Returns the number of
    unexpected errors."""
    os.makedirs(out_dir, exist_ok=True)
    cat = Catalog(runs=runs, out_dir=out_dir, tau_ref=tau_ref, plug_force=plug_force, bond_points=bond_points,
                  stored=list(stored))
    rows = [cat.row(r) for r in cat.every_run]
    summary.write_csv(rows, os.path.join(out_dir, "summary.csv"))
    # R(F, F_d)'s pairs beside the rows, so that R, too, can be made where the files are not
    fd_pairs.write_csv([p for r, row in zip(cat.every_run, rows)
                        for p in stored_rows.pairs_of(r, row["file"], row["run_id"]) or ()],
                       os.path.join(out_dir, fd_pairs.FILE_NAME))
    if stored:
        report.append(f"- {len(stored)} run(s) known by their stored rows only ("
                      + ", ".join(sorted({s.source for s in stored})) + "): in Tables 2-3 and Figs. 8, 10, 11, "
                      "13-15, not in the figures drawn from records (6, 7, 9, 12, 16-20): "
                      + ", ".join(s.name for s in stored))
    errors = 0
    items = [(f"Fig. {n}", fn) for n, fn in sorted(FIGURES.items())]
    items += [(f"Table {n}", fn) for n, fn in sorted(tables.TABLES.items())]
    for label, fn in items:
        try:
            fn(cat)
        except Missing as exc:
            report.append(f"- {label}: not made: {exc}")
        except Exception as exc:  # one broken item must not stop the others
            errors += 1
            report.append(f"- {label}: ERROR {type(exc).__name__}: {exc}")
            traceback.print_exc()
        finally:
            plotting.discard_open()   # a figure stopped half-drawn by Missing stays open otherwise
    report.extend(f"- partial: {n}" for n in cat.notes)
    for r in runs:
        for group, why in sorted(r.missing.items()):
            if group != "fields":  # /fields is for ParaView only; no analysis needs it
                report.append(f"- {r.name}: {why}")
    return errors


def main(argv=None):
    ap = argparse.ArgumentParser(prog="icerubble figures", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results_dir", help="folder of run results (*.h5), searched recursively")
    ap.add_argument("-o", "--out-dir", default="figures", help="output folder (default ./figures)")
    ap.add_argument("--tau-ref-kPa", type=float, default=50.0,
                    help="bond strength of the single-strength figures (paper: 50 kPa)")
    ap.add_argument("--plug-force", type=float, default=11e3,
                    help="F_b of tau^(2), the cylindrical plug [N/m] (paper: ~11e3)")
    summary.add_bond_points_option(ap)
    stored_rows.add_option(ap)
    args = ap.parse_args(argv)
    if not os.path.isdir(args.results_dir):
        ap.error(f"RESULTS_DIR {args.results_dir!r} is not a folder")
    if args.tau_ref_kPa <= 0 or args.plug_force < 0:
        ap.error("--tau-ref-kPa must be > 0 and --plug-force >= 0")
    check_output_folder(args.out_dir, "--out-dir")
    stored = stored_rows.read_all(args.stored_rows, args.bond_points)   # read before OUT_DIR is written

    runs, skipped = results.load_folder(args.results_dir)
    skipped = [f"- skipped: {why}" for why in skipped]
    os.makedirs(args.out_dir, exist_ok=True)
    lines = ["# Items not made, and why", "", f"Results folder: `{args.results_dir}`; "
             f"{len(runs)} run(s) read, {len(skipped)} file(s) skipped"
             + (f", {len(stored)} stored row(s) from " + ", ".join(f"`{p}`" for p in args.stored_rows)
                if stored else "") + ". Bond points behind alpha and A_p: "
             f"{failure_plane.BOND_POINTS[args.bond_points][1]} (--bond-points {args.bond_points}).", ""]
    if skipped:
        lines += ["## Skipped files", ""] + skipped + [""]
    errors = 0
    variants = {}
    for r in runs + stored:   # files first: of a case's equal travels, the file is kept
        variants.setdefault(variant(r), []).append(r)
    for key, vruns in sorted(variants.items()):
        scene, model, fdir = key
        sub = args.out_dir if len(variants) == 1 else os.path.join(args.out_dir, variant_folder(key, variants))
        report = []
        vruns = _dedupe(vruns, report)
        vstored = [r for r in vruns if isinstance(r, stored_rows.StoredRun)]
        vruns = [r for r in vruns if not isinstance(r, stored_rows.StoredRun)]
        errors += make_variant(vruns, sub, args.tau_ref_kPa * 1e3, args.plug_force, report, args.bond_points,
                               vstored)
        lines += [f"## scene `{scene}`, model `{model}`, force_direction `{fdir}` -> `{sub}` "
                  f"({len(vruns) + len(vstored)} runs)", ""]
        lines += report or ["- nothing missing"]
        lines.append("")
    if not runs and not stored:
        lines.append("No readable run result: nothing could be made.")
    text = "\n".join(lines) + "\n"
    with whole_file(os.path.join(args.out_dir, "MISSING.md")) as fh:
        fh.write(text)
    print(text)
    if not runs and not stored:
        return 2
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(cli.run("figures", sys.argv[1:]))
