"""Figures of one run: its F-y_I record (as Figs. 6-7) and its u_y field (as
Figs. 16, 19) at a chosen indenter travel.

    icerubble run-figures RUN.h5 [-o OUT_DIR] [--y-I-mm 30]
"""
import argparse
import os
import sys

from icerubble import cli
from icerubble.files import results
from icerubble.files.output_path import check_output_folder

from . import loads, plotting
from .catalog import Missing
from .figures_deformation import field_panel


def _stem(run):
    return os.path.splitext(run.name)[0]


def force_record(run, out_dir):
    """F against y_I over the whole run and over the first 20 mm, F^m (the cohesive
    peak) marked, and the record maximum where a later event beat it."""
    y, F = run.force_y * 1e3, run.force_F / 1e3
    Fm, ym = loads.cohesive_peak(run.force_y, run.force_F)
    Fx, yx = loads.record_maximum(run.force_y, run.force_F)
    fig, axes = plotting.new(ncols=2, width=9.0, height=3.4)
    for ax, y_max in zip(axes[0], (None, 20.0)):
        sel = slice(None) if y_max is None else y <= y_max
        ax.plot(y[sel], F[sel], color="k", lw=1)
        ax.plot([ym * 1e3], [Fm / 1e3], "o", color="tab:red",
                label=f"$F^m$ = {Fm / 1e3:.1f} kN/m at {ym * 1e3:.2f} mm")
        if yx != ym and (y_max is None or yx * 1e3 <= y_max):
            ax.plot([yx * 1e3], [Fx / 1e3], "s", mfc="none", color="tab:orange",
                    label=f"record maximum {Fx / 1e3:.1f} kN/m at {yx * 1e3:.2f} mm")
        ax.set(xlabel="$y_I$ [mm]", ylabel="F [kN/m]")
        ax.legend(loc="upper right")
    axes[0, 0].set_title("whole run", fontsize=8)
    axes[0, 1].set_title("first 20 mm", fontsize=8)
    return plotting.save(fig, out_dir, f"{_stem(run)}_force",
                         f"{run.name}: indenter force F against indenter travel y_I")


def displacement_field(run, y_I, out_dir, x_lim=None):
    """u_y per element at the snapshot nearest to y_I [m]."""
    if x_lim is None:
        x_lim = 0.5 * float(run.pile.get("keel_x_max", 10.0) - run.pile.get("keel_x_min", -10.0))
    fig, axes = plotting.new(width=8.0, height=3.2)
    snap = field_panel(axes[0, 0], run, y_I, x_lim=x_lim)
    axes[0, 0].set_title(f"$y_I$ = {snap.y_I * 1e3:.1f} mm", fontsize=8)
    return plotting.save(fig, out_dir, f"{_stem(run)}_uy",
                         f"{run.name}: vertical displacement u_y of the rubble")


def main(argv=None):
    ap = argparse.ArgumentParser(prog="icerubble run-figures", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", help="a result file (.h5)")
    ap.add_argument("-o", "--out-dir", default=None, help="default: beside the run file")
    ap.add_argument("--y-I-mm", type=float, default=None, help="travel of the u_y figure; default: last snapshot")
    a = ap.parse_args(argv)
    run = results.load(a.run)   # a ValueError naming the file: refused before any figure
    out = check_output_folder(a.out_dir or os.path.dirname(os.path.abspath(a.run)), "--out-dir")
    os.makedirs(out, exist_ok=True)
    made = force_record(run, out)
    if run.snapshots:
        y_I = a.y_I_mm * 1e-3 if a.y_I_mm is not None else max(s.y_I for s in run.snapshots)
        try:
            made += displacement_field(run, y_I, out)
        except Missing as e:
            print(f"run_figures: no u_y figure: {e}")
    else:
        print(f"run_figures: no u_y figure: {run.missing.get('snapshots', 'no snapshots')}")
    for p in made:
        print(p)
    return made


if __name__ == "__main__":
    sys.exit(cli.run("run-figures", sys.argv[1:]))
