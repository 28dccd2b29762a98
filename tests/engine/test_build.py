"""The compiled modules import from the interpreter YADE uses."""
import sys


def test_interpreter_is_debian_python():
    assert sys.executable.startswith("/usr/bin/python3")


def test_extensions_import():
    from icerubble import _engine, _cohesive_law
    assert _engine.version() and _cohesive_law.version()
