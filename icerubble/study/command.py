"""`icerubble study`: a study is a yade-batch table of punch-through runs.

    icerubble study check TABLE     every line checked before any runs: exit 2 and
                                    'line N, column C: ...' for each problem
    icerubble study run TABLE [--local] [--out DIR] [--jobs N] [--job-threads T] [--device D]
                                    the table's lines here, through yade-batch; ends
                                    with each line's outcome, exit 1 if any did not finish;
                                    --device cuda: their steps on one GPU (docs/gpu.md)
    icerubble study submit TABLE --slurm [--out DIR] [--cpus-per-task N] [--time T]
                                    [--partition P] [--account A] [--sbatch-arg ARG ...]
                                    one SLURM job-array task per line; prints the job id
    icerubble study status [DIR]    each line of each study in DIR: done (its result),
                                    failed (why), interrupted, running, pending, not run
    icerubble study resubmit [DIR]  sends again, as one job array per study, only the
                                    lines without a complete result that are not queued;
                                    an interrupted line resumes from its checkpoint

Results go to DIR (default runs/ in this checkout; a table's out_dir column
overrides it); each study keeps its table, its job scripts and one log per line
in DIR/logs/<table>/ (icerubble/study/folder.py).
"""
import argparse
import os
import shutil

from .. import exit_status
from .. import parameters as P
from ..engine.model import check_device
from ..files.output_path import check_output_folder
from ..run.punch_through_run import RunOptions
from ..run.scene_cache import ROOT
from . import outcome as SO
from . import progress as study_progress
from . import slurm
from .folder import load_study, open_study, studies, study_dir, study_lock, table_of
from .table_check import check_table, devices

PUNCH_THROUGH = os.path.join(ROOT, "yade_scripts", "punch_through.py")
DEFAULT_OUT = os.path.join(ROOT, "runs")


# the actions of `icerubble study` (`icerubble --help` lists them from here)
ACTIONS = {
    "check": "check a table as a whole",
    "run": "run a table here through yade-batch, then report each line",
    "submit": "submit a table to SLURM as a job array",
    "status": "each line's state",
    "resubmit": "send the lines without a complete result again",
}


def main(argv=None):
    ap = argparse.ArgumentParser(prog="icerubble study", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="action", required=True)
    c = sub.add_parser("check", help=ACTIONS["check"])
    c.add_argument("table")
    r = sub.add_parser("run", help=ACTIONS["run"])
    r.add_argument("table")
    r.add_argument("--local", action="store_true", help="run here (the only way `run` runs)")
    r.add_argument("--out", default=DEFAULT_OUT,
                   help="folder of the results (default runs/ of this checkout; an out_dir column "
                        "overrides it, relative to the current folder)")
    r.add_argument("--jobs", type=int, default=1, help="lines run at once (default 1)")
    r.add_argument("--job-threads", type=int, default=2, help="threads of each line (default 2)")
    r.add_argument("--progress-every", type=float, default=60.0, metavar="S",
                   help="seconds between progress lines on the console (default 60)")
    r.add_argument("--device", choices=("cpu", "cuda"), default=None,
                   help="where the lines' steps run: cpu (default) or cuda, whole steps on one GPU "
                        "(docs/gpu.md); a device column overrides it")
    r.add_argument("--settle-max-time", type=float, default=None, metavar="S",
                   help="simulated seconds a line's settle may take before it stops, saying it is not at "
                        f"rest (default {P.REGISTRY['settle_max_time'].default:g}; not part of a run's identity: "
                        "a settle that ends before the old limit is the same run)")
    s = sub.add_parser("submit", help=ACTIONS["submit"])
    s.add_argument("table")
    s.add_argument("--slurm", action="store_true", required=True, help="the scheduler (SLURM)")
    s.add_argument("--out", default=DEFAULT_OUT, help="folder of the results (default runs/)")
    s.add_argument("--cpus-per-task", type=int, default=2, help="threads of each run (default 2)")
    s.add_argument("--time", help="time limit of each task, e.g. 24:00:00")
    s.add_argument("--partition")
    s.add_argument("--account")
    s.add_argument("--sbatch-arg", action="append", default=[], metavar="ARG",
                   help="any further sbatch option, e.g. --sbatch-arg=--mem=8G (repeatable)")
    st = sub.add_parser("status", help=ACTIONS["status"])
    st.add_argument("out", nargs="?", default=DEFAULT_OUT)
    rs = sub.add_parser("resubmit", help=ACTIONS["resubmit"])
    rs.add_argument("out", nargs="?", default=DEFAULT_OUT)
    a = ap.parse_args(argv)
    if a.action == "run":
        for name, value in (("jobs", a.jobs), ("job-threads", a.job_threads)):
            if value < 1:
                raise ValueError(f"--{name} = {value}: must be a whole number >= 1")
        if a.settle_max_time is not None:   # its range, and settle_min_time below it
            RunOptions(settle_max_time=a.settle_max_time)
    if a.action in ("run", "submit"):
        check_output_folder(a.out, "--out")
    if a.action in ("check", "run", "submit") and not check(a.table):
        return exit_status.USAGE   # refused before any line runs
    if a.action == "run":
        check_devices(a.table, a.device)
        return run_local(a.table, a.out, a.jobs, a.job_threads, a.progress_every, device=a.device,
                         settle_max_time=a.settle_max_time)
    if a.action == "submit":
        job, log_dir = slurm.submit(a.table, a.out, PUNCH_THROUGH, sbatch_options=dict(
            cpus_per_task=a.cpus_per_task, time=a.time, partition=a.partition, account=a.account,
            extra=a.sbatch_arg))
        print(f"[study] submitted {a.table} as SLURM job {job} (logs in {log_dir})")
        print(job)
        return 0
    if a.action == "status":
        return status(a.out)
    if a.action == "resubmit":
        return resubmit(a.out)
    return 0


def check(table):
    problems = check_table(table)
    for p in problems:
        print(f"{table}: {p}")
    if not problems:
        print(f"{table}: every line can run")
    return not problems


def check_devices(table, device):
    """Refuse, before any line runs, a table whose lines ask for the GPU
    (--device cuda, or a device column) where the GPU backend cannot run."""
    for d in devices(table, device):
        check_device(d)


def run_local(table, out, jobs=1, job_threads=2, progress_every=60.0, device=None, settle_max_time=None):
    """Every line of `table` through yade-batch on this machine; prints each
    line's start, end and progress (study_progress.py) and then its outcome,
    and returns the exit status (1 if any line did not finish). device: where
    the lines without a device column run (None: the CPU); settle_max_time:
    the settle's limit [s] of every line (None: the registry's)."""
    if shutil.which("yade-batch") is None:
        raise ValueError("yade-batch is not on PATH (make deps installs YADE)")
    with study_lock(study_dir(out, table)):   # one run of a table into a folder at a time
        return _run_locked(table, out, jobs, job_threads, progress_every, device, settle_max_time)


def _run_locked(table, out, jobs, job_threads, progress_every, device=None, settle_max_time=None):
    log_dir, study = open_study(table, out, "local")
    for name in os.listdir(log_dir):   # a line's old log must not speak for this run
        if name.startswith("line") and name.endswith(".log"):
            os.remove(os.path.join(log_dir, name))
    # yade-batch runs in the log folder and names each log there: a pattern
    # relative to it, as yade-batch rewrites $, % and @ anywhere in --log and
    # renames paths longer than 230 characters
    cmd = ["yade-batch", f"--job-threads={job_threads}", "-j", str(jobs * job_threads),
           "--disable-pynotify", "--log", SO.LOG_PATTERN, table_of(log_dir, study), PUNCH_THROUGH]
    # results in OUT; a relative out_dir column is relative to where the study was started
    env = dict(os.environ, ICERUBBLE_OUT_DIR=study["out"], ICERUBBLE_WORKDIR=os.getcwd())
    if device:   # the lines without a device column (yade_scripts/punch_through.py)
        env["ICERUBBLE_DEVICE"] = device
    if settle_max_time is not None:   # every line's (yade_scripts/punch_through.py)
        env["ICERUBBLE_SETTLE_MAX_TIME"] = repr(float(settle_max_time))
    print("[study] " + " ".join(cmd), flush=True)
    try:
        # its exit status says nothing about the lines
        study_progress.watch(cmd, env, log_dir, table_of(log_dir, study), jobs=jobs, every_s=progress_every)
        status = None
    except KeyboardInterrupt as stop:   # Ctrl-C, or SIGTERM / SIGHUP (study_progress.Stopped)
        by = f" by {stop}" if isinstance(stop, study_progress.Stopped) else ""
        print(f"[study] interrupted{by}: the lines that did not finish say so below", flush=True)
        status = exit_status.INTERRUPTED
    # yade-batch has returned: a log with no end is a line that was killed (queue {})
    outcomes = SO.line_outcomes(table_of(log_dir, study), log_dir, queue={})
    _print(table, log_dir, outcomes)
    if status is not None:
        return status
    return 0 if all(o["state"] == "done" for o in outcomes) else 1


def _print(name, log_dir, outcomes):
    print(f"[study] {name}: each line's outcome (logs in {log_dir})")
    for row in SO.summary(outcomes):
        print("  " + row)


def _outcomes(log_dir):
    study = load_study(log_dir)
    q = None
    if study["scheduler"] == "slurm":
        q = slurm.queue([j["id"] for j in study["jobs"]])
    return study, SO.line_outcomes(table_of(log_dir, study), log_dir, queue=q)


def _studies(out):
    found = studies(out)
    if not found:
        raise ValueError(f"no study in {out!r} (a study is made by `icerubble study run` or `submit`, "
                         f"which keep it in {os.path.join(out, 'logs')})")
    return found


def status(out):
    for log_dir in _studies(out):
        study, outcomes = _outcomes(log_dir)
        jobs = ", ".join(j["id"] for j in study["jobs"])
        _print(f"{study['table']} ({study['scheduler']}{': jobs ' + jobs if jobs else ''})", log_dir, outcomes)
    return 0


def resubmit(out):
    for log_dir in _studies(out):
        study, outcomes = _outcomes(log_dir)
        if study["scheduler"] != "slurm":
            print(f"[study] {study['table']}: run here, not submitted: `icerubble study run` runs it again "
                  "(a complete result is kept, an interrupted one resumes)")
            continue
        lines = [o["line"] for o in outcomes if o["state"] in ("failed", "interrupted", "not run")]
        if not lines:
            print(f"[study] {study['table']}: nothing to resubmit (every line done, running or pending)")
            continue
        job = slurm.send(log_dir, study, lines)
        print(f"[study] {study['table']}: resubmitted lines {', '.join(map(str, lines))} as SLURM job {job}")
    return 0
