"""The main job on a small default scene, end to end, in a few minutes:

    pile (YADE, phase 1) -> mesh (gmsh) -> punch-through to 30 mm -> figures

    make demo            (or: icerubble demo [--ridge N] [--out-dir DIR] [--travel-mm MM])

Prints where the outputs are. The scene is `demo` of icerubble/run/presets.py:
a 10 m wide, ~1.8 m deep keel, Table 1 parameters (mu = 0.3, tau_cr = 50 kPa).
"""
import argparse
import os
import sys
import time

from postproc import run_figures

from .. import cli, exit_status
from ..files.output_path import check_output_folder

from .punch_through_run import RunInterrupted
from .study import run_one


def main(argv=None):
    ap = argparse.ArgumentParser(prog="icerubble demo", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ridge", type=int, default=1, help="ridge number = pile seed (default 1)")
    ap.add_argument("--out-dir", default=os.path.join("runs", "demo"), help="default runs/demo")
    ap.add_argument("--travel-mm", type=float, default=30.0, help="indenter travel (default 30 mm)")
    a = ap.parse_args(argv)
    check_output_folder(a.out_dir, "--out-dir")
    t0 = time.perf_counter()
    try:   # bad input (a ValueError) is refused by run_one before any work: icerubble says so, exit 2
        out = run_one("demo", ridge=a.ridge, overrides=dict(target_travel=a.travel_mm * 1e-3),
                      out_dir=a.out_dir)
    except RunInterrupted as e:   # a signal: the checkpoint is written, `icerubble demo` again resumes
        print(f"icerubble demo: interrupted: {e} (the same `icerubble demo` command resumes it)", file=sys.stderr)
        return exit_status.INTERRUPTED
    except RuntimeError as e:   # another run in progress, an instability
        print(f"icerubble demo: error: {e}", file=sys.stderr)
        return exit_status.FAILED
    figs = run_figures.main([out, "-o", os.path.join(a.out_dir, "figures")])
    print(f"\ndemo finished in {time.perf_counter() - t0:.0f} s")
    print(f"  result (HDF5, docs/results_format.md): {out}")
    print(f"  ParaView fields:                      {out[:-3]}_fields/*.pvd")
    print(f"  figures:                              {os.path.dirname(figs[0])}")
    print(f"  all figures of the paper from a folder of runs: "
          f"icerubble figures {a.out_dir}")


if __name__ == "__main__":
    sys.exit(cli.run("demo", sys.argv[1:]))
