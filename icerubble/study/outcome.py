"""What became of each line of a study table: done, failed (and why),
interrupted (a checkpoint to resume from), running, pending or not run.

yade-batch prints each line's exit status as it ends but itself exits 0
whatever its lines did, and a zero exit does not mean a result: a line may
stop early and leave no file, or a partial one. So the outcome of a line is
read from what it left behind: its log (one per table line, ``line<N>.log``
in the study's log folder) names the result file the driver wrote
(RESULT_MARK), and that file must be complete. On a cluster a line's log
holds every attempt (a requeued or resubmitted task appends): only the text
after the last JOB_START counts, and the scheduler's queue says which lines
are pending or running (icerubble/study/slurm.py).
"""
import os

from .. import exit_status
from ..files.h5io import open_complete
from .table_check import read_table

RESULT_FORMAT = "icerubble-run"   # docs/results_format.md
# Printed by yade_scripts/punch_through.py once a line's result is complete ...
RESULT_MARK = "punch_through: result "
# ... or when a signal stopped it after its checkpoint was written; it then
# exits with EXIT_INTERRUPTED (EX_TEMPFAIL: try again)
INTERRUPTED_MARK = "punch_through: interrupted: "
EXIT_INTERRUPTED = exit_status.INTERRUPTED
# yade-batch appends this block to each line's log when the line ends (the
# SLURM job script writes the same); the job script starts each attempt with JOB_START
BATCH_SUMMARY = "=================== JOB SUMMARY"
JOB_START = "=================== JOB START"
# scheduler states (squeue %T) of a line that is still to run or running
QUEUED = {"PENDING", "CONFIGURING", "REQUEUED", "REQUEUE_HOLD", "REQUEUE_FED", "RESIZING", "SUSPENDED"}
RUNNING = {"RUNNING", "COMPLETING", "STAGE_OUT", "SIGNALING"}


def log_path(log_dir, line):
    return os.path.join(log_dir, f"line{line}.log")


# yade-batch's --log format for log_path, relative to the log folder ('%' is the line number)
LOG_PATTERN = "line%.log"


def line_outcomes(table, log_dir, queue=None):
    """[{line, label, state, result, why}] for every line of `table`, state one
    of "done", "failed", "interrupted", "running", "pending", "not run".
    queue: {line: scheduler state} of the study's tasks still known to the
    scheduler (None: no scheduler, e.g. yade-batch here)."""
    _, rows = read_table(table)
    out = []
    for n, row, error in rows:
        entry = dict(line=n, label=_label(row), state="not run", result=None, why="")
        if error:
            entry.update(state="failed", why=error)
        else:
            entry.update(_from_log(log_path(log_dir, n)))
        in_queue = (queue or {}).get(n)
        if in_queue in QUEUED and entry["state"] != "done":
            entry.update(state="pending", why=f"{in_queue.lower()} in the scheduler's queue")
        elif in_queue in RUNNING:
            entry.update(state="running", why=entry["why"])
        elif entry["state"] == "running" and queue is not None:
            # its log never ended and the scheduler no longer has it: killed
            entry.update(state="failed", why="killed: its log has no end (stopped from outside: a time "
                                             "limit, scancel, a node failure, Ctrl-C); run again, it "
                                             "resumes from its checkpoint | " + entry["why"])
        out.append(entry)
    return out


def _label(row):
    if row is None:
        return "?"
    if "description" in row:
        return row["description"]
    return " ".join(f"{c}={v}" for c, v in row.items())


def _from_log(path):
    if not os.path.exists(path):
        return dict(state="not run")
    with open(path, errors="replace") as f:
        lines = f.read().splitlines()
    starts = [i for i, ln in enumerate(lines) if ln.startswith(JOB_START)]
    if starts:   # the last attempt only
        lines = lines[starts[-1]:]
    ended = any(ln.startswith(BATCH_SUMMARY) for ln in lines)
    body = lines[:next((i for i, ln in enumerate(lines) if ln.startswith(BATCH_SUMMARY)), len(lines))]
    results = [ln[len(RESULT_MARK):].strip() for ln in body if ln.startswith(RESULT_MARK)]
    if results:
        try:
            open_complete(results[-1], RESULT_FORMAT, what="result").close()
            return dict(state="done", result=results[-1])
        except ValueError as e:
            return dict(state="failed", result=results[-1], why=str(e))
    interrupted = [ln for ln in body if ln.startswith(INTERRUPTED_MARK)]
    if interrupted:
        return dict(state="interrupted", why=interrupted[-1][len(INTERRUPTED_MARK):])
    if not ended:
        return dict(state="running", why=_tail(body, 1))
    return dict(state="failed", why=_tail(body))


def _tail(lines, n=3):
    """The lines that say why: the last error line and what follows it (a
    multi-line message goes on below it), else the last few lines."""
    lines = [ln for ln in lines if ln.strip()]
    errors = [i for i, ln in enumerate(lines) if "error:" in ln or "Error" in ln]
    keep = lines[errors[-1]:errors[-1] + 2 * n] if errors else lines[-n:]
    return " | ".join(ln.strip() for ln in keep)


def summary(outcomes):
    """Text lines, one per table line, and a count line."""
    rows = []
    for o in outcomes:
        what = o["result"] if o["state"] == "done" else o["why"]
        rows.append(f"line {o['line']:>3}  {o['state']:<8} {o['label']}: {what}")
    counts = {}
    for o in outcomes:
        counts[o["state"]] = counts.get(o["state"], 0) + 1
    rows.append(", ".join(f"{k} {v}" for k, v in sorted(counts.items())) + f" of {len(outcomes)} lines")
    return rows
