"""Measured punch-through data: peak load, post-peak levels and rubble shear strength
with the three buoyancy assumptions of Polojärvi & Tuhkuri (2013), section 4.1.1.

    /usr/bin/python3 -m postproc.measured CSV --keel-depth H --indenter-width W --porosity ETA
        [--disp-unit mm|m] [--force-unit kN/m|N/m|kN|N --out-of-plane-length L]
        [--interval 20:150 --interval 150:300] [--alpha 43] [--plug-force F]
        [--rho-i 920 --rho-w 1010 --g 9.81] [-o OUT_DIR]

The CSV needs a header row; lines starting with '#' are comments. Columns
(case-insensitive; a unit in brackets, e.g. "y_I [mm]", is read and checked):
  displacement: y_I, yi, y, displacement, disp, penetration, travel   (or --disp-column)
  force:        F, force, load                                       (or --force-column)
Forces are per unit width (plane strain, as the paper's 2D model). A total force
(N or kN) needs --out-of-plane-length L [m] of a plane-strain test to be divided by.

F^m of a measured record is its maximum: in the field tests the paper compares
with (Heinonen 2004) F^m came at y_I = 8.8-18.1 mm, and a test has no numerical
late events to exclude. The maximum over the first 5 mm, which is F^m of the
simulations (loads.cohesive_peak), is reported beside it for comparison only.

tau = (F^m - F_b)/(2 H)  (eq 15) with
  tau(1): F_b = 0
  tau(2): F_b = cylindrical plug: (1 - eta)(rho_w - rho_i) g W H unless --plug-force is given
  tau(3): F_b = (1 - eta)(rho_w - rho_i) g A_p (eq 13), where, without a simulation, A_p is
          ESTIMATED as a trapezoid of width W at the keel top widening by tan(alpha) on each
          side down to the keel bottom: A_p = H (W + H tan alpha), alpha = 43 deg by default
          (the paper's mean failure-plane angle at tau_cr = 50 kPa).
"""
import argparse
import csv
import os
import re
import sys

import numpy as np

from icerubble import cli, exit_status
from icerubble.files.output_path import check_output_folder, whole_file
from icerubble.parameters import GRAVITY, RHO_I, RHO_W

from . import loads, plug, shear_strength

DISP_NAMES = ("y_i", "yi", "y", "displacement", "disp", "penetration", "travel")
FORCE_NAMES = ("f", "force", "load")
DISP_UNITS = {"m": 1.0, "mm": 1e-3}
FORCE_UNITS = {"n/m": (1.0, False), "kn/m": (1e3, False), "n": (1.0, True), "kn": (1e3, True)}
DEFAULT_INTERVALS_MM = ((20.0, 150.0), (150.0, 300.0))


def _split_header(cell):
    """'y_I [mm]' -> ('y_i', 'mm'); 'F' -> ('f', None)."""
    m = re.match(r"^\s*(.*?)\s*(?:[\[(]\s*([^\])]*?)\s*[\])])?\s*$", cell)
    name = m.group(1).strip().lower().replace(" ", "_")
    unit = m.group(2).strip().lower().replace(" ", "") if m.group(2) else None
    return name, unit


def _pick(header, names, explicit, what):
    parsed = [_split_header(h) for h in header]
    if explicit is not None:
        want = explicit.strip().lower()
        for i, (n, u) in enumerate(parsed):
            if n == want or header[i].strip().lower() == want:
                return i, u
        raise ValueError(f"--{what}-column {explicit!r} not in the CSV header {header}")
    for i, (n, u) in enumerate(parsed):
        if n in names:
            return i, u
    raise ValueError(f"no {what} column in the CSV header {header}; accepted names: {', '.join(names)} "
                     f"(or give --{what}-column)")


def _unit(from_header, from_option, table, what, default):
    if from_header is not None and from_header not in table:
        raise ValueError(f"{what} unit {from_header!r} in the CSV header is not one of {', '.join(table)}")
    if from_option is not None:
        opt = from_option.strip().lower()
        if opt not in table:
            raise ValueError(f"--{what}-unit must be one of {', '.join(table)}, got {from_option!r}")
        if from_header is not None and from_header != opt:
            raise ValueError(f"--{what}-unit {opt} contradicts the CSV header unit {from_header}")
        return opt
    return from_header if from_header is not None else default


def read_csv(path, disp_unit=None, force_unit=None, disp_column=None, force_column=None,
             out_of_plane_length=None):
    """(y_I [m], F [N/m]) from a measured CSV (see module doc). Defaults when neither
    the header nor an option says: mm and kN/m."""
    if not os.path.isfile(path):
        raise ValueError(f"CSV {path!r}: " + ("a folder, not a file" if os.path.isdir(path) else "no such file"))
    with open(path, newline="") as fh:
        rows = [r for r in csv.reader(line for line in fh if line.strip() and not line.lstrip().startswith("#"))]
    if not rows:
        raise ValueError(f"CSV {path!r} is empty")
    header, data = rows[0], rows[1:]
    i_y, u_y = _pick(header, DISP_NAMES, disp_column, "disp")
    i_F, u_F = _pick(header, FORCE_NAMES, force_column, "force")
    du = _unit(u_y, disp_unit, DISP_UNITS, "disp", "mm")
    fu = _unit(u_F, force_unit, FORCE_UNITS, "force", "kn/m")
    if len(data) < 2:
        raise ValueError(f"CSV {path!r} has {len(data)} data row(s); need at least 2")
    y, F = np.empty(len(data)), np.empty(len(data))
    for k, r in enumerate(data):
        try:
            y[k], F[k] = float(r[i_y]), float(r[i_F])
        except (ValueError, IndexError):
            raise ValueError(f"CSV {path!r} data row {k + 1}: not two numbers in columns "
                             f"{header[i_y]!r}, {header[i_F]!r}: {r}") from None
        if not (np.isfinite(y[k]) and np.isfinite(F[k])):
            raise ValueError(f"CSV {path!r} data row {k + 1}: non-finite value {r}")
        if y[k] < 0.0:   # travel counts from first contact, downward (docs/conventions.md)
            raise ValueError(f"CSV {path!r} data row {k + 1}: negative displacement {r[i_y]}; "
                             "the indenter travel must be >= 0 (measured from the start of loading)")
    back = np.flatnonzero(np.diff(y) < 0)
    if back.size:
        raise ValueError(f"CSV {path!r}: displacement decreases at data row {back[0] + 2} "
                         f"({y[back[0]]:g} -> {y[back[0] + 1]:g}); the record must be non-decreasing in displacement")
    scale, total = FORCE_UNITS[fu]
    F = F * scale
    if total:
        if out_of_plane_length is None or not out_of_plane_length > 0:
            raise ValueError(f"force unit {fu} is a total force: give --out-of-plane-length L > 0 [m] "
                             "(the test's length out of plane) to get force per unit width")
        F = F / out_of_plane_length
    return y * DISP_UNITS[du], F


def _check_inputs(H, W, eta, rho_i, rho_w, g, alpha, plug_force):
    if not H > 0:
        raise ValueError(f"--keel-depth must be > 0 m, got {H}")
    if not W > 0:
        raise ValueError(f"--indenter-width must be > 0 m, got {W}")
    if not 0.0 <= eta < 1.0:
        raise ValueError(f"--porosity must be in [0, 1), got {eta}")
    if not rho_i > 0 or not rho_w > rho_i:
        raise ValueError(f"need --rho-w > --rho-i > 0 kg/m^3, got rho_w={rho_w}, rho_i={rho_i}")
    if not g > 0:
        raise ValueError(f"--g must be > 0, got {g}")
    if not 0.0 <= alpha < 90.0:
        raise ValueError(f"--alpha must be in [0, 90) degrees, got {alpha}")
    if plug_force is not None and not plug_force >= 0:
        raise ValueError(f"--plug-force must be >= 0 N/m, got {plug_force}")


def analyse(y, F, keel_depth, indenter_width, porosity, intervals=DEFAULT_INTERVALS_MM, alpha=43.0,
            plug_force=None, rho_i=RHO_I, rho_w=RHO_W, g=GRAVITY):
    """All the numbers of the report as a dict (SI units). ``intervals`` in mm;
    intervals the record does not cover are listed under 'skipped_intervals'."""
    _check_inputs(keel_depth, indenter_width, porosity, rho_i, rho_w, g, alpha, plug_force)
    for a, b in intervals:
        if not 0 <= a < b:
            raise ValueError(f"interval {a}:{b} mm: need 0 <= start < end")
    F_m, y_m = loads.record_maximum(y, F)
    try:
        F_early, y_early = loads.cohesive_peak(y, F)
    except ValueError:   # a record that starts after the window: nothing to compare
        F_early = y_early = np.nan
    means, skipped = [], []
    for a, b in intervals:
        try:
            means.append((a, b, loads.mean_load(y, F, a * 1e-3, b * 1e-3)))
        except ValueError as exc:
            skipped.append((a, b, str(exc)))
    cyl = float(plug.buoyant_load(indenter_width * keel_depth, porosity, rho_w, rho_i, g))
    Fb2 = cyl if plug_force is None else float(plug_force)
    Ap = float(plug.trapezoid_plug_area(indenter_width, keel_depth, alpha))
    Fb3 = float(plug.buoyant_load(Ap, porosity, rho_w, rho_i, g))
    t1, t2, t3 = shear_strength.three_strengths(F_m, keel_depth, Fb2, Fb3)
    return {"F_m": F_m, "y_I_peak": y_m, "F_early": F_early, "y_I_early": y_early, "means": means, "skipped_intervals": skipped,
            "F_b_cylindrical": cyl, "F_b2": Fb2, "F_b2_source": "computed" if plug_force is None else "given",
            "alpha": alpha, "A_p": Ap, "F_b3": Fb3, "tau1": t1, "tau2": t2, "tau3": t3,
            "A_s": 2 * keel_depth, "y_end": float(y[-1])}


def report_text(res, csv_path):
    L = [f"Punch-through record: {csv_path}",
         f"  peak load F^m            = {res['F_m'] / 1e3:.3f} kN/m at y_I = {res['y_I_peak'] * 1e3:.2f} mm "
         "(the record maximum)",
         f"  maximum over 0-{loads.COHESIVE_PEAK_TRAVEL * 1e3:g} mm     = {res['F_early'] / 1e3:.3f} kN/m at y_I = "
         f"{res['y_I_early'] * 1e3:.2f} mm (F^m as the simulations define it; for comparison only)"]
    for a, b, m in res["means"]:
        L.append(f"  mean load {a:g}-{b:g} mm   = {m / 1e3:.3f} kN/m  (F^m / mean = {res['F_m'] / m:.2f})")
    for a, b, why in res["skipped_intervals"]:
        L.append(f"  mean load {a:g}-{b:g} mm: not computed ({why})")
    src = ("computed: (1 - eta)(rho_w - rho_i) g W H" if res["F_b2_source"] == "computed" else "given (--plug-force)")
    L += [f"Shear strength tau = (F^m - F_b)/A_s, A_s = 2H = {res['A_s']:g} m (eq 15):",
          f"  tau(1), F_b = 0                         : {res['tau1'] / 1e3:.3f} kPa",
          f"  tau(2), F_b = {res['F_b2'] / 1e3:.3f} kN/m cylindrical plug ({src}): {res['tau2'] / 1e3:.3f} kPa",
          f"  tau(3), F_b = {res['F_b3'] / 1e3:.3f} kN/m from an ASSUMED plug  : {res['tau3'] / 1e3:.3f} kPa",
          f"    A_p = H (W + H tan alpha) = {res['A_p']:.3f} m^2 with alpha = {res['alpha']:g} deg: an estimate "
          "(trapezoid from the indenter edges widening down to the keel bottom), not a measured failure "
          "plane; the paper found alpha = 43 ± 8 deg in simulations (tau_cr = 50 kPa)."]
    return "\n".join(L) + "\n"


def figure(y, F, res, out_dir):
    """F-y_I with the peak, interval means and the three F_b levels; PNG + PDF."""
    from . import plotting
    fig, axes = plotting.new(width=6.0, height=3.8)
    ax = axes[0, 0]
    ax.plot(y * 1e3, F / 1e3, "k-", lw=0.8, label="measured F")
    ax.plot(res["y_I_peak"] * 1e3, res["F_m"] / 1e3, "rv", label=f"$F^m$ = {res['F_m'] / 1e3:.2f} kN/m")
    for a, b, m in res["means"]:
        ax.plot([a, b], [m / 1e3] * 2, "-", lw=2.0, label=f"mean {a:g}–{b:g} mm = {m / 1e3:.2f} kN/m")
    for key, lab, ls in (("F_b2", "$F_b$ cylindrical plug", ":"), ("F_b3", f"$F_b(A_p)$, α = {res['alpha']:g}°", "--")):
        ax.axhline(res[key] / 1e3, color="0.4", ls=ls, lw=0.9, label=f"{lab} = {res[key] / 1e3:.2f} kN/m")
    ax.set(xlabel="indenter displacement $y_I$ [mm]", ylabel="indenter force $F$ [kN/m]")
    ax.legend(fontsize=7)
    return plotting.save(fig, out_dir, "measured_F_y", "Measured punch-through record")


def _interval(text):
    try:
        a, b = (float(v) for v in text.split(":"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"interval {text!r}: expected START:END in mm, e.g. 20:150") from None
    return a, b


def main(argv=None):
    ap = argparse.ArgumentParser(prog="icerubble measured", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv")
    ap.add_argument("--keel-depth", type=float, required=True, metavar="H", help="rubble thickness h [m]")
    ap.add_argument("--indenter-width", type=float, required=True, metavar="W", help="w_I [m]")
    ap.add_argument("--porosity", type=float, required=True, metavar="ETA", help="eta in [0, 1)")
    ap.add_argument("--disp-unit", choices=sorted(DISP_UNITS), help="default: header unit, else mm")
    ap.add_argument("--force-unit", type=str.lower, choices=sorted(FORCE_UNITS),
                    help="default: header unit, else kN/m")
    ap.add_argument("--out-of-plane-length", type=float, metavar="L", help="[m], needed for a total force (N, kN)")
    ap.add_argument("--disp-column")
    ap.add_argument("--force-column")
    ap.add_argument("--interval", type=_interval, action="append", metavar="A:B",
                    help="post-peak interval in mm (repeatable; default 20:150 and 150:300)")
    ap.add_argument("--alpha", type=float, default=43.0, help="assumed failure-plane angle for tau(3) [deg]")
    ap.add_argument("--plug-force", type=float, help="F_b of tau(2) [N/m] (paper: 11e3 for W = H = 4 m); "
                    "default: the cylindrical plug computed from W, H, eta")
    ap.add_argument("--rho-i", type=float, default=RHO_I)
    ap.add_argument("--rho-w", type=float, default=RHO_W)
    ap.add_argument("--g", type=float, default=GRAVITY)
    ap.add_argument("-o", "--out-dir", help="write report.md, result.csv and the figure here")
    args = ap.parse_args(argv)
    try:
        _check_inputs(args.keel_depth, args.indenter_width, args.porosity, args.rho_i, args.rho_w, args.g,
                      args.alpha, args.plug_force)
        y, F = read_csv(args.csv, args.disp_unit, args.force_unit, args.disp_column, args.force_column,
                        args.out_of_plane_length)
        res = analyse(y, F, args.keel_depth, args.indenter_width, args.porosity,
                      args.interval or DEFAULT_INTERVALS_MM, args.alpha, args.plug_force,
                      args.rho_i, args.rho_w, args.g)
        if args.out_dir:
            check_output_folder(args.out_dir, "--out-dir")
    except ValueError as exc:
        print(f"icerubble measured: error: {exc}", file=sys.stderr)
        return exit_status.USAGE
    text = report_text(res, args.csv)
    print(text, end="")
    if args.out_dir:
        os.makedirs(args.out_dir, exist_ok=True)
        with whole_file(os.path.join(args.out_dir, "report.md")) as fh:
            fh.write("```\n" + text + "```\n")
        early_mm = loads.COHESIVE_PEAK_TRAVEL * 1e3
        with whole_file(os.path.join(args.out_dir, "result.csv"), newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["quantity", "value", "unit"])
            w.writerows([["F_m", f"{res['F_m'] / 1e3:.6g}", "kN/m"], ["y_I_peak", f"{res['y_I_peak'] * 1e3:.6g}", "mm"],
                         [f"F_max_0_{early_mm:g}mm", f"{res['F_early'] / 1e3:.6g}", "kN/m"],
                         [f"y_I_max_0_{early_mm:g}mm", f"{res['y_I_early'] * 1e3:.6g}", "mm"]]
                        + [[f"F_mean_{a:g}_{b:g}mm", f"{m / 1e3:.6g}", "kN/m"] for a, b, m in res["means"]]
                        + [["F_b_cylindrical_plug", f"{res['F_b2'] / 1e3:.6g}", "kN/m"],
                           ["alpha_assumed", f"{res['alpha']:g}", "deg"], ["A_p_assumed", f"{res['A_p']:.6g}", "m2"],
                           ["F_b_Ap", f"{res['F_b3'] / 1e3:.6g}", "kN/m"], ["tau1", f"{res['tau1'] / 1e3:.6g}", "kPa"],
                           ["tau2", f"{res['tau2'] / 1e3:.6g}", "kPa"], ["tau3", f"{res['tau3'] / 1e3:.6g}", "kPa"]])
        paths = figure(y, F, res, args.out_dir)
        print("wrote", ", ".join([os.path.join(args.out_dir, "report.md"), os.path.join(args.out_dir, "result.csv")] + paths))
    return 0


if __name__ == "__main__":
    sys.exit(cli.run("measured", sys.argv[1:]))
