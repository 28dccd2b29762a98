"""bench/README.md, the one place measured figures are printed, is what
bench/make_readme.py writes from bench/results/*.json: a result changed
without the page, or the page edited by hand, fails here (issue 27, item 5)."""
import json
import os
import sys

from tests.paths import ROOT

sys.path.insert(0, os.path.join(ROOT, "bench"))
import make_readme  # noqa: E402


def test_bench_readme_is_generated_from_the_results():
    with open(make_readme.OUT) as f:
        shown = f.read()
    assert shown == make_readme.render(), "bench/README.md is stale: run /usr/bin/python3 bench/make_readme.py"


def test_a_result_measured_before_its_scene_changed_says_so():
    """A paper-scene result measured before the paper scene's ridges were
    remade must not read as the current ridges' (and one with bond runs
    measured before the default force direction changed says that); one
    measured since carries no such note."""
    page = make_readme.render()
    for name in make_readme.WITH_BOND_RUNS:
        path = os.path.join(make_readme.RESULTS, name)
        if not os.path.exists(path):
            continue
        with open(path) as f:
            data = json.load(f)
        part = page.split(f"## {name}")[1].split("\n## ")[0]
        day = make_readme.measured_on(name, data)
        assert len(day) == 10, (name, day)
        if name in make_readme.ON_THE_PAPER_SCENE:
            assert ("earlier, dense ridge 1" in part) == (day < make_readme.PAPER_RIDGES_REMADE), (name, day)
        assert ("eq 11 as printed" in part) == (day < make_readme.FORCE_DIRECTION_CHANGED), (name, day)
