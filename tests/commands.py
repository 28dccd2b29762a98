"""The project's commands as the tests run them: this checkout's code, not the
`icerubble` installed on PATH (an editable install of another checkout would
answer for it). PYTHONPATH puts this checkout first for `python3 -m
icerubble.cli` and for every `yade` it starts (yade-batch's lines included)."""
import os
import subprocess
import sys

from tests.paths import ROOT

ICERUBBLE = [sys.executable, "-m", "icerubble.cli"]


def env(**extra):
    """os.environ with this checkout first on PYTHONPATH, and `extra`."""
    path = os.pathsep.join(p for p in (ROOT, os.environ.get("PYTHONPATH")) if p)
    return dict(os.environ, PYTHONPATH=path, **extra)


def icerubble(*args, cwd=None, timeout=300, **extra_env):
    """`icerubble ARGS` run to its end: the CompletedProcess (text output)."""
    return subprocess.run([*ICERUBBLE, *map(str, args)], cwd=cwd, env=env(**extra_env),
                          capture_output=True, text=True, timeout=timeout)
