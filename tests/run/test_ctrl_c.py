"""Ctrl-C on a table line run by YADE (yade_scripts/punch_through.py): the
run writes its checkpoint, says how to resume and exits 75, like a
scheduler's stop; the same command again resumes it to a complete result.

The tiny scene with 60 mm of travel: its loading takes several seconds, so
the signal sent when the log says loading has begun arrives mid-load. That
the resumed record equals a run in one go is checked in-process, for every
stop signal (test_punch_through.py).
"""
import os
import signal
import subprocess
import time

from icerubble.files.h5io import open_complete
from icerubble.study import outcome as SO
from tests.paths import ROOT

SCRIPT = os.path.join(ROOT, "yade_scripts", "punch_through.py")


def _yade(table, out, **kw):
    env = dict(os.environ, YADE_BATCH=f"{table}:2", ICERUBBLE_OUT_DIR=str(out))
    return subprocess.Popen(["yade", "-j1", "-n", "-x", SCRIPT], env=env, cwd=str(out), text=True,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, **kw)


def test_ctrl_c_mid_load_writes_the_checkpoint_exits_75_and_the_rerun_resumes(tmp_path):
    table = tmp_path / "one.table"
    table.write_text("description scene ridge mu tau_cr target_travel\nctrlc 'tiny' 1 0.3 50e3 0.06\n")
    out = tmp_path / "out"
    out.mkdir()
    p = _yade(table, out)
    text, deadline = [], time.time() + 300
    for line in p.stdout:
        text.append(line)
        if line.startswith("[settle] at rest"):   # loading begins
            time.sleep(0.5)
            p.send_signal(signal.SIGINT)
            break
        assert time.time() < deadline, "".join(text)
    rest, _ = p.communicate(timeout=120)
    text = "".join(text) + rest
    assert p.returncode == SO.EXIT_INTERRUPTED, text
    stopped = [ln for ln in text.splitlines() if ln.startswith(SO.INTERRUPTED_MARK)]
    assert stopped and "stopped by SIGINT" in stopped[0] and "phase load" in stopped[0], text
    assert "run it again to resume" in stopped[0]
    assert (out / "ctrlc.checkpoint.h5").exists() and not (out / "ctrlc.h5").exists()

    again = _yade(table, out)
    text2, _ = again.communicate(timeout=300)
    assert again.returncode == 0, text2
    assert "resumed from" in text2 and "phase load" in text2, text2
    with open_complete(out / "ctrlc.h5", "icerubble-run") as f:
        assert f["force/y_I"][-1] >= 0.06
    assert not (out / "ctrlc.checkpoint.h5").exists()
