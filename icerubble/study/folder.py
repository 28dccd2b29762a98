"""The folder of one study (a table run into an output folder OUT):

    OUT/logs/<table>/<table>.table   the table as first run (every later run or
                                     resubmit runs the same lines)
    OUT/logs/<table>/study.json      the table's name, where it runs (local or
                                     slurm), the sbatch options and every job id
    OUT/logs/<table>/line<N>.log     table line N's log, one per line
    OUT/logs/<table>/run.lock        held (flock) by the `icerubble study run` of
                                     this table into OUT, with its host and pid

so that `icerubble study status OUT` can tell each line's outcome afterwards.
"""
import contextlib
import fcntl
import json
import os
import socket
import time

STUDY_FILE = "study.json"


def study_dir(out, table):
    return os.path.join(os.path.abspath(out), "logs", os.path.splitext(os.path.basename(table))[0])


def open_study(table, out, scheduler, **settings):
    """(log folder, study dict) of `table` in `out`, made on first use. The
    same table name with other contents in the same folder is refused for a
    cluster study (its queued tasks and logs would mix); a local run, which
    is over when it returns, takes the new contents."""
    log_dir = study_dir(out, table)
    os.makedirs(log_dir, exist_ok=True)
    name = os.path.basename(table) if table.endswith(".table") else os.path.basename(table) + ".table"
    kept = os.path.join(log_dir, name)
    with open(table) as f:
        text = f.read()
    if os.path.exists(os.path.join(log_dir, STUDY_FILE)):
        study = load_study(log_dir)
        with open(kept) as f:
            same = f.read() == text
        if not same and scheduler == "local" and study["scheduler"] == "local":
            with open(kept, "w") as f:
                f.write(text)
        elif not same:
            raise ValueError(f"{log_dir} holds a study of another table named {name!r}: rename the "
                             "table or use another --out")
        if study["scheduler"] != scheduler:
            raise ValueError(f"{log_dir} holds this table's study run with {study['scheduler']}, not "
                             f"{scheduler}: use another --out")
        return log_dir, study
    with open(kept, "w") as f:
        f.write(text)
    study = dict(table=name, out=os.path.abspath(out), scheduler=scheduler, jobs=[], workdir=os.getcwd(),
                 **settings)
    save_study(log_dir, study)
    return log_dir, study


@contextlib.contextmanager
def study_lock(log_dir):
    """Held while this table runs into this folder: a second run of it at once
    would delete the first one's line logs (each run starts afresh) and read
    the other's lines as its own, so it is refused at once, naming the first.
    An flock is released by the kernel when its process ends, however it ends:
    no stale lock to clear by hand."""
    os.makedirs(log_dir, exist_ok=True)
    path = os.path.join(log_dir, "run.lock")
    f = open(path, "a+")
    try:
        try:
            fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            f.seek(0)
            holder = f.read().strip() or "another process"
            raise ValueError(f"this table is already being run into {os.path.dirname(os.path.dirname(log_dir))} "
                             f"by {holder} (lock {path}): wait for it to end (`icerubble study status` "
                             "tells its lines), or run into another --out") from None
        f.seek(0)
        f.truncate()
        f.write(f"process {os.getpid()} on {socket.gethostname()}, started "
                f"{time.strftime('%Y-%m-%d %H:%M:%S')}\n")
        f.flush()
        yield
    finally:
        f.close()   # releases the lock


def table_of(log_dir, study):
    return os.path.join(log_dir, study["table"])


def load_study(log_dir):
    with open(os.path.join(log_dir, STUDY_FILE)) as f:
        return json.load(f)


def save_study(log_dir, study):
    tmp = os.path.join(log_dir, STUDY_FILE + ".part")
    with open(tmp, "w") as f:
        json.dump(study, f, indent=1)
    os.replace(tmp, os.path.join(log_dir, STUDY_FILE))


def studies(out):
    """Every study folder under OUT/logs."""
    root = os.path.join(out, "logs")
    if not os.path.isdir(root):
        return []
    return sorted(os.path.join(root, d) for d in os.listdir(root)
                  if os.path.exists(os.path.join(root, d, STUDY_FILE)))
