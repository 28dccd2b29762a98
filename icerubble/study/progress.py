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
import subprocess
import sys
import time

from . import outcome as SO

POLL_S = 2.0
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


def watch(cmd, env, log_dir, table, jobs=1, every_s=60.0, stream=None):
    """Run `cmd` (yade-batch) and report its lines' progress until it ends."""
    stream = stream or sys.stdout
    proc = subprocess.Popen(cmd, env=env, cwd=log_dir)
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
    except KeyboardInterrupt:
        # the lines got the same Ctrl-C and are writing their checkpoints (exit
        # 75); yade-batch must not start the next lines meanwhile
        proc.kill()
        proc.wait()
        raise


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
