"""`icerubble study run` on the console (icerubble/study/progress.py): a
line when each table line starts and ends, and periodic lines with each
running line's latest progress line and an ETA of the table. A stand-in for
yade-batch writes the logs, so this takes seconds."""
import io
import os
import signal
import subprocess
import sys
import textwrap
import time

import pytest

from icerubble.study import outcome as SO
from icerubble.study.progress import latest_progress, table_eta, watch

FAKE_BATCH = textwrap.dedent(f"""
    import time
    with open("line2.log", "w") as f:
        f.write("[settle] step 10  t 0.0010 s  max speed 0.1 m/s  wall 0 s  ETA <= 90 s (settle_max_time 5 s)\\n")
        f.flush(); time.sleep(1.5)
        f.write("[punch-through] step 99  t 0.0100 s  y_I 0.100 mm  wall 1 s  ETA 42 s\\n")
        f.flush(); time.sleep(3.0)
        f.write("punch_through: error: the scene did not come to rest\\n{SO.BATCH_SUMMARY}\\n")
    """)


def test_each_line_starts_and_ends_on_the_console_with_its_progress_between(tmp_path):
    table = tmp_path / "t.table"
    table.write_text("description mu\nonly 0.3\n")
    out = io.StringIO()
    status = watch([sys.executable, "-c", FAKE_BATCH], None, str(tmp_path), str(table), every_s=1.0, stream=out)
    text = out.getvalue()
    assert status == 0, text
    assert "[study] line 2 started: only" in text
    assert "line 2: [punch-through] step 99" in text and "table ETA ~42 s" in text, text
    assert "[study] line 2 failed after" in text and "did not come to rest" in text, text


def test_the_loading_eta_is_read_from_a_log_and_a_settles_bound_is_not_an_eta(tmp_path):
    log = tmp_path / "line3.log"
    log.write_text("[settle] step 10  t 0.0010 s  wall 0 s  ETA <= 90 s (settle_max_time 5 s)\n")
    assert latest_progress(log)[1] is None
    log.write_text(log.read_text() + "[punch-through] step 20  t 0.0020 s  y_I 0.01 mm  wall 3 s  ETA 42 s\nother\n")
    text, eta = latest_progress(log)
    assert text.startswith("[punch-through] step 20") and eta == 42.0


def test_the_table_eta_adds_the_running_lines_and_the_waiting_ones_at_the_mean_line():
    # two lines done in 100 s and 200 s, one loading with 30 s left, two waiting, one at a time
    assert table_eta([100.0, 200.0], [(30.0, 50.0)], 2, jobs=1) == 30.0 + 2 * 150.0
    # two at a time: the work shared over two
    assert table_eta([100.0, 200.0], [(30.0, 50.0)], 2, jobs=2) == (30.0 + 2 * 150.0) / 2
    # a line still settling counts as the mean line less what it has run
    assert table_eta([100.0], [(None, 40.0)], 0, jobs=1) == 60.0
    # nothing ended yet: unknown while a line settles or lines wait
    assert table_eta([], [(None, 10.0)], 0, jobs=1) is None
    assert table_eta([], [(30.0, 10.0)], 1, jobs=1) is None
    assert table_eta([], [(30.0, 10.0)], 0, jobs=1) == 30.0


# A stand-in for yade-batch that starts one line as yade-batch does (through a
# shell, a grandchild of the study command): the line writes its pid, and on
# SIGTERM or SIGINT its "checkpoint", and stops with 75 as a run does.
FAKE_LINE = textwrap.dedent("""
    import os, signal, sys, time
    def stop(signum, frame):
        open("checkpoint", "w").write(signal.Signals(signum).name)
        sys.exit(75)
    signal.signal(signal.SIGTERM, stop)
    signal.signal(signal.SIGINT, stop)
    open("line.pid", "w").write(str(os.getpid()))
    for _ in range(900):   # at most 90 s: a failing test leaves no line behind for long
        time.sleep(0.1)
    """)
STUDY = textwrap.dedent("""
    import signal, subprocess, sys
    from icerubble.study.progress import watch
    # a shell without job control starts its background commands with SIGINT
    # ignored, which Python then keeps: a terminal's command gets Ctrl-C
    signal.signal(signal.SIGINT, signal.default_int_handler)
    line = subprocess.list2cmdline([sys.executable, "-c", open("line.py").read()])
    batch = [sys.executable, "-c", f"import subprocess; subprocess.call({line!r}, shell=True)"]
    try:
        watch(batch, None, ".", "t.table", every_s=60.0)
    except KeyboardInterrupt as stop:
        print("stopped by", stop, flush=True)
        sys.exit(75)
    """)


def alive(pid):
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def run_and_stop(tmp_path, signum):
    (tmp_path / "t.table").write_text("description mu\nonly 0.3\n")
    (tmp_path / "line.py").write_text(FAKE_LINE)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    study = subprocess.Popen([sys.executable, "-c", STUDY], cwd=tmp_path, env=env,
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    deadline = time.monotonic() + 30
    while not (tmp_path / "line.pid").exists() or not (tmp_path / "line.pid").read_text():
        assert time.monotonic() < deadline and study.poll() is None, study.stdout.read()
        time.sleep(0.05)
    line_pid = int((tmp_path / "line.pid").read_text())
    study.send_signal(signum)
    out, _ = study.communicate(timeout=60)
    return study.returncode, out, line_pid


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGHUP])
def test_a_killed_study_stops_its_lines_after_their_checkpoints(tmp_path, signum):
    status, out, line_pid = run_and_stop(tmp_path, signum)
    assert status == 75 and f"stopped by {signal.Signals(signum).name}" in out, out
    assert (tmp_path / "checkpoint").read_text() == "SIGTERM"   # the line was told, and wrote it
    assert not alive(line_pid)                                  # and is gone when the command returns


def test_a_ctrl_c_of_the_study_reaches_its_lines_in_their_own_group(tmp_path):
    # the lines run in a process group of their own: a terminal's Ctrl-C reaches
    # the study command alone, which passes it on
    status, out, line_pid = run_and_stop(tmp_path, signal.SIGINT)
    assert status == 75, out
    assert (tmp_path / "checkpoint").read_text() == "SIGINT"
    assert not alive(line_pid)
