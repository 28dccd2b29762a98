"""`icerubble study`: a study is a yade-batch table of punch-through runs.

    icerubble study check TABLE     every line checked before any runs: exit 1 and
                                    'line N, column C: ...' for each problem
    icerubble study run TABLE [--out DIR] [--jobs N] [--job-threads T]
                                    the table's lines here, through yade-batch; results
                                    in DIR (default runs/), one log per line in
                                    DIR/logs/<table>/; ends with each line's outcome
                                    and exit 1 when any line did not finish
"""
import argparse
import os
import shutil
import subprocess
import sys

from . import study_outcome as SO
from .scene_cache import ROOT
from .table_check import check_table

PUNCH_THROUGH = os.path.join(ROOT, "yade_scripts", "punch_through.py")


def main(argv=None):
    ap = argparse.ArgumentParser(prog="icerubble study", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="action", required=True)
    c = sub.add_parser("check", help="check a table as a whole")
    c.add_argument("table")
    r = sub.add_parser("run", help="run a table here through yade-batch, then report each line")
    r.add_argument("table")
    r.add_argument("--out", default=os.path.join(ROOT, "runs"),
                   help="folder of the results (a table's out_dir column overrides it)")
    r.add_argument("--jobs", type=int, default=1, help="lines run at once (default 1)")
    r.add_argument("--job-threads", type=int, default=2, help="threads of each line (default 2)")
    a = ap.parse_args(argv)
    if not check(a.table):
        sys.exit(1)
    if a.action == "run":
        sys.exit(run_local(a.table, a.out, a.jobs, a.job_threads))


def check(table):
    problems = check_table(table)
    for p in problems:
        print(f"{table}: {p}")
    if not problems:
        print(f"{table}: every line can run")
    return not problems


def study_log_dir(out, table):
    return os.path.join(out, "logs", os.path.splitext(os.path.basename(table))[0])


def run_local(table, out, jobs=1, job_threads=2):
    """Every line of `table` through yade-batch on this machine; prints each
    line's outcome and returns the exit status (1 if any line did not finish)."""
    for name, value in (("jobs", jobs), ("job-threads", job_threads)):
        if value < 1:
            raise ValueError(f"--{name} = {value}: must be a whole number >= 1")
    if shutil.which("yade-batch") is None:
        raise ValueError("yade-batch is not on PATH (make deps installs YADE)")
    logs = study_log_dir(out, table)
    os.makedirs(logs, exist_ok=True)
    for name in os.listdir(logs):   # a line's old log must not speak for this run
        if name.startswith("line") and name.endswith(".log"):
            os.remove(os.path.join(logs, name))
    cmd = ["yade-batch", f"--job-threads={job_threads}", "-j", str(jobs * job_threads),
           "--disable-pynotify", "--log", SO.batch_log_pattern(logs), os.path.abspath(table), PUNCH_THROUGH]
    env = dict(os.environ, ICERUBBLE_OUT_DIR=os.path.abspath(out))
    print("[study] " + " ".join(cmd), flush=True)
    subprocess.run(cmd, env=env, cwd=logs)   # its exit status says nothing about the lines
    outcomes = SO.line_outcomes(table, logs)
    print(f"[study] {table}: each line's outcome (logs in {logs})")
    for row in SO.summary(outcomes):
        print("  " + row)
    return 0 if all(o["state"] == "done" for o in outcomes) else 1
