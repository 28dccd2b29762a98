"""The demo prints on every machine the numbers the README shows (issue 25).

Its ridge is shipped (data/ridges/), the engine is built portable and the
demo computes on a fixed 2 threads (docs/reproducibility.md), so its record
does not depend on the processor. bench/demo_reference.py measured the
printed line once; this runs `icerubble demo` as a user does and compares.
A different line here means one of those three no longer holds. About two
minutes.
"""
import json
import os
import re
import sys

from tests.paths import ROOT

sys.path.insert(0, os.path.join(ROOT, "bench"))
import demo_reference  # noqa: E402

with open(demo_reference.OUT) as f:
    REFERENCE = json.load(f)


def test_the_readme_quotes_the_measured_demo():
    with open(os.path.join(ROOT, "README.md")) as f:
        readme = f.read()
    quoted = re.findall(r"F\^m = [0-9.]+ kN/m at y_I = [0-9.]+ mm", readme)
    assert quoted, "the README quotes no demo peak line"
    assert set(quoted) == {REFERENCE["peak_line"]}, "README and bench/results/demo_reference.json differ"


def test_the_demo_prints_the_readmes_numbers(tmp_path):
    line, result = demo_reference.run_demo(str(tmp_path / "demo"))
    assert line == REFERENCE["peak_line"], (
        f"the demo printed {line!r}, the README {REFERENCE['peak_line']!r} (made on "
        f"{REFERENCE['processor']}, {REFERENCE['engine_build']})")


def test_the_reference_was_made_as_every_machine_runs_the_demo():
    """Measured with the portable build on the shipped ridge, not on a pile or
    build only one machine has."""
    assert REFERENCE["engine_build"].startswith("portable")
    assert REFERENCE["pile"].startswith("data/ridges/demo_ridge1_")
