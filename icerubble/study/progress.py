"""Progress of `icerubble study run` on the console: yade-batch writes each
line's progress only into its log (OUT/logs/<table>/line<N>.log), so while it
runs the logs are read every few seconds and the console gets a line when a
table line starts and when it ends (with its outcome), and every `every_s` a
line with the lines done of all, each running line's latest progress line
and an ETA for the table.

The table's ETA adds the running lines' own loading ETAs (run/progress.py)
and, for the lines still waiting, the mean wall time of the lines done so far,
over the lines run at once: a rough figure until some lines have ended ("?"
before one has, while a line settles and its length is unknown).
"""
import os
import re
import signal
import subprocess
import sys
import threading
import time

from . import outcome as SO

POLL_S = 2.0
# how long a stopped study waits for its lines to write their checkpoints
STOP_WAIT_S = 120.0
# a run's progress line (run/progress.py): "[label] step N ... ETA <= 12 s ..." or "ETA ?"
PROGRESS = re.compile(r"^\[[a-z -]+\] step +\d+ ")
ETA = re.compile(r" ETA (<= )?(\d+) s")


def latest_progress(log):
    """(the last progress line of a line's log, its loading ETA in seconds or
    None: none yet, or only a settle's upper bound)."""
    try:
        with open(log, errors="replace") as f:
            lines = [ln.rstrip("\n") for ln in f if PROGRESS.match(ln)]
    except OSError:
        return None, None
    if not lines:
        return None, None
    m = ETA.search(lines[-1])
    eta = float(m.group(2)) if m and not m.group(1) else None
    return lines[-1], eta


def table_eta(done_s, running, n_waiting, jobs):
    """Wall seconds left of a table: done_s, the wall times of the lines done;
    running, (seconds left or None, seconds since the line started) per running
    line; n_waiting lines not started; `jobs` lines at once. None if unknown."""
    mean = sum(done_s) / len(done_s) if done_s else None
    left = []
    for eta, elapsed in running:
        if eta is None:   # settling: as long as a finished line took, if one has
            eta = None if mean is None else max(mean - elapsed, 0.0)
        left.append(eta)
    if any(x is None for x in left) or (n_waiting and mean is None):
        return None
    work = sum(left) + n_waiting * (mean or 0.0)
    return work / max(1, min(jobs, len(left) + n_waiting))


class Stopped(KeyboardInterrupt):
    """The study command was sent SIGTERM or SIGHUP (kill, a closed terminal):
    handled as a Ctrl-C is, the lines stopped after their checkpoints."""

    def __init__(self, signum):
        super().__init__(signal.Signals(signum).name)


def _raise_stopped(signum, frame):
    raise Stopped(signum)


def group_alive(pgid):
    """Whether a process of group `pgid` is still running (zombies, which only
    wait to be reaped, do not count)."""
    try:
        pids = [d for d in os.listdir("/proc") if d.isdigit()]
    except OSError:   # no /proc: ask the group itself
        try:
            os.killpg(pgid, 0)
            return True
        except ProcessLookupError:
            return False
    for pid in pids:
        try:
            with open(f"/proc/{pid}/stat") as f:
                fields = f.read().rsplit(")", 1)[1].split()
        except OSError:
            continue   # ended meanwhile
        if int(fields[2]) == pgid and fields[0] != "Z":
            return True
    return False


def stop_lines(proc, signum, stream, wait_s=STOP_WAIT_S):
    """Send `signum` to yade-batch and its lines (their own process group),
    so that each line writes its checkpoint and stops (exit 75) and no
    further line starts; then wait up to wait_s for them to end."""
    try:
        os.killpg(proc.pid, signum)
    except ProcessLookupError:
        return
    proc.kill()   # yade-batch itself must not start the next lines meanwhile
    proc.wait()
    deadline = time.monotonic() + wait_s
    while group_alive(proc.pid):
        if time.monotonic() > deadline:
            print(f"[study] lines still running {wait_s:.0f} s after {signal.Signals(signum).name}: "
                  f"process group {proc.pid}", file=stream, flush=True)
            return
        time.sleep(0.2)


def watch(cmd, env, log_dir, table, jobs=1, every_s=60.0, stream=None):
    """Run `cmd` (yade-batch) and report its lines' progress until it ends.

    yade-batch and its lines run in a process group of their own, to which
    this command passes on a Ctrl-C (SIGINT), SIGTERM or SIGHUP: each line
    then writes its checkpoint and stops. Without it a study command that was
    killed left its lines running on, unseen, beside a new command resuming
    them from the same checkpoints."""
    stream = stream or sys.stdout
    # stdin from /dev/null: a process outside the terminal's foreground group that
    # read it would be stopped (SIGTTIN); the lines read nothing from it
    proc = subprocess.Popen(cmd, env=env, cwd=log_dir, start_new_session=True, stdin=subprocess.DEVNULL)
    handlers = {}
    if threading.current_thread() is threading.main_thread():
        for signum in (signal.SIGTERM, signal.SIGHUP):
            handlers[signum] = signal.signal(signum, _raise_stopped)
    started, ended = {}, {}
    last = time.monotonic()
    try:
        while True:
            finished = proc.poll() is not None
            outcomes = SO.line_outcomes(table, log_dir, queue=None)
            now = time.monotonic()
            for o in outcomes:
                n = o["line"]
                if n not in started and os.path.exists(SO.log_path(log_dir, n)):
                    started[n] = now
                    print(f"[study] line {n} started: {o['label']}", file=stream, flush=True)
                if n in started and n not in ended and o["state"] not in ("running", "not run"):
                    ended[n] = now
                    what = o["result"] if o["state"] == "done" else o["why"]
                    print(f"[study] line {n} {o['state']} after {now - started[n]:.0f} s: {what}",
                          file=stream, flush=True)
            if finished:
                return proc.returncode
            if now - last >= every_s:
                last = now
                _report(outcomes, started, ended, log_dir, jobs, now, stream)
            time.sleep(POLL_S)
    except KeyboardInterrupt as stop:
        # the lines write their checkpoints on SIGINT or SIGTERM (exit 75); a
        # SIGHUP is passed on as the SIGTERM they know
        stop_lines(proc, signal.SIGTERM if isinstance(stop, Stopped) else signal.SIGINT, stream)
        raise
    finally:
        for signum, handler in handlers.items():
            signal.signal(signum, handler)


def _report(outcomes, started, ended, log_dir, jobs, now, stream):
    running = [o["line"] for o in outcomes if o["line"] in started and o["line"] not in ended]
    waiting = sum(1 for o in outcomes if o["line"] not in started)
    done_s = [ended[n] - started[n] for n in ended]
    parts, etas = [], []
    for n in running:
        text, eta = latest_progress(SO.log_path(log_dir, n))
        etas.append((eta, now - started[n]))
        parts.append(f"line {n}: {text or 'starting'}")
    eta = table_eta(done_s, etas, waiting, jobs)
    print(f"[study] {len(ended)}/{len(outcomes)} lines ended, {len(running)} running, {waiting} waiting; "
          f"table ETA {'?' if eta is None else f'~{eta:.0f} s'}", file=stream, flush=True)
    for p in parts:
        print(f"[study]   {p}", file=stream, flush=True)
