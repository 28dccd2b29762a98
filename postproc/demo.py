"""The main job on a small default scene, end to end, in a few minutes:

    pile -> mesh (gmsh) -> punch-through to 30 mm -> figures

    make demo            (or: icerubble demo [--ridge N] [--out-dir DIR] [--travel-mm MM])

Prints the peak load F^m and where the outputs are. The scene is `demo` of
icerubble/run/presets.py: a 10 m wide, ~1.8 m deep keel, Table 1 parameters
(mu = 0.3, tau_cr = 50 kPa). Ridge 1's pile is shipped (data/ridges/, made
in YADE once), so on every machine the demo runs the same ridge, on 2
threads, and prints the same numbers (bench/results/demo_reference.json);
another ridge number is made here by YADE's phase 1.

It is a postproc module because it ends in figures: the run is icerubble's
(study/line.py), the figures postproc's, and icerubble never imports postproc.
"""
import argparse
import os
import sys
import time

from icerubble import cli, exit_status
from icerubble.files.h5io import open_complete
from icerubble.files.output_path import check_output_folder
from icerubble.run.presets import DEFAULT_NUMERICS, numerics
from icerubble.run.driver import RunInterrupted
from icerubble.run.punch_through_run import RunOptions
from icerubble.study.line import run_one

from . import loads, run_figures

# threads of the demo's run, on every machine (its numbers are the README's)
DEMO_THREADS = 2


def main(argv=None):
    ap = argparse.ArgumentParser(prog="icerubble demo", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ridge", type=int, default=1, help="ridge number = pile seed (default 1)")
    ap.add_argument("--out-dir", default=os.path.join("runs", "demo"), help="default runs/demo")
    ap.add_argument("--travel-mm", type=float, default=30.0, help="indenter travel (default 30 mm)")
    a = ap.parse_args(argv)
    check_output_folder(a.out_dir, "--out-dir")
    t0 = time.perf_counter()
    # a fixed thread count: sums over threads round differently, so the demo
    # computes the same bits, and prints the README's numbers, on every machine
    options = RunOptions.from_numerics(numerics("demo"), name=DEFAULT_NUMERICS)
    options.threads = DEMO_THREADS
    try:   # bad input (a ValueError) is refused by run_one before any work: icerubble says so, exit 2
        out = run_one("demo", ridge=a.ridge, overrides=dict(target_travel=a.travel_mm * 1e-3),
                      out_dir=a.out_dir, options=options)
    except RunInterrupted as e:   # a signal: the checkpoint is written, `icerubble demo` again resumes
        print(f"icerubble demo: interrupted: {e} (the same `icerubble demo` command resumes it)", file=sys.stderr)
        return exit_status.INTERRUPTED
    except RuntimeError as e:   # another run in progress, an instability
        print(f"icerubble demo: error: {e}", file=sys.stderr)
        return exit_status.FAILED
    figs = run_figures.main([out, "-o", os.path.join(a.out_dir, "figures")])
    print(f"\ndemo finished in {time.perf_counter() - t0:.0f} s")
    print(f"  {peak_line(out)}")
    print(f"  result (HDF5, docs/results_format.md): {out}")
    print(f"  ParaView fields:                      {out[:-3]}_fields/*.pvd")
    print(f"  figures:                              {os.path.dirname(figs[0])}")
    print(f"  all figures of the paper from a folder of runs: "
          f"icerubble figures {a.out_dir}")


def peak_line(result):
    """The line the demo prints of its peak load, as the README quotes it."""
    with open_complete(result, "icerubble-run") as f:
        Fm, ym = loads.cohesive_peak(f["force/y_I"][:], f["force/F"][:])
    return f"F^m = {Fm / 1e3:.1f} kN/m at y_I = {ym * 1e3:.2f} mm"


if __name__ == "__main__":
    sys.exit(cli.run("demo", sys.argv[1:]))
