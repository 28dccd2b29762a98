"""Folders the tests read from or run in (the repository root: subprocesses
run there so `tests.*` helper modules import as in the suite)."""
import os

TESTS = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(TESTS)
DATA = os.path.join(TESTS, "data")
