"""bench/README.md, the one place measured figures are printed, is what
bench/make_readme.py writes from bench/results/*.json: a result changed
without the page, or the page edited by hand, fails here (issue 27, item 5)."""
import os
import sys

from tests.paths import ROOT

sys.path.insert(0, os.path.join(ROOT, "bench"))
import make_readme  # noqa: E402


def test_bench_readme_is_generated_from_the_results():
    with open(make_readme.OUT) as f:
        shown = f.read()
    assert shown == make_readme.render(), "bench/README.md is stale: run /usr/bin/python3 bench/make_readme.py"


def test_the_paper_scenes_old_ridge_is_said_where_its_figures_are():
    """paper_cost and paper_peak were measured before the paper scene's ridges
    were remade; their figures must not read as the current ridges'."""
    page = make_readme.render()
    for name in ("paper_cost.json", "paper_peak.json"):
        part = page.split(f"## {name}")[1].split("\n## ")[0]
        assert "earlier, dense ridge 1" in part
