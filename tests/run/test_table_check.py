"""A yade-batch table is checked as a whole before any line runs: each
mistake named as 'line N, column C: ...' (before: YADE NameErrors naming no
column, or a failure after that line's pile was made)."""
import os
import subprocess

import pytest

from icerubble.study.table_check import check_table
from tests.commands import env as command_env, icerubble
from tests.paths import ROOT

HEAD = "description ridge mu tau_cr scene\n"
GOOD = "r1 1 0.3 5000 'small'\n"

# (what, table text, expected message fragment)
CASES = [
    ("unknown column, closest name", "description ridge mu_typo tau_cr scene\nr1 1 0.3 5e3 'small'\n",
     "line 1, column mu_typo: not a parameter; did you mean 'mu'?"),
    ("unquoted word", HEAD + "r1 1 abc 5e3 'small'\n", "line 2, column mu: abc does not parse"),
    ("unquoted scene", HEAD + "r1 1 0.3 5e3 small\n", "line 2, column scene: small does not parse"),
    ("unknown scene", HEAD + "r1 1 0.3 5e3 'big'\n", "line 2, column scene: 'big' is not a scene"),
    ("negative strength", HEAD + "r1 1 0.3 -5e3 'small'\n", "line 2, column tau_cr: parameter tau_cr=-5000.0 is out of range"),
    ("negative friction", HEAD + "r1 1 -0.1 5e3 'small'\n", "line 2, column mu: parameter mu=-0.1 is out of range"),
    ("fractional ridge", HEAD + "r1 1.5 0.3 5e3 'small'\n", "line 2, column ridge: 1.5 must be a whole number"),
    ("a choice that is not one", "description force_direction\nr1 'sideways'\n",
     "line 2, column force_direction: parameter force_direction='sideways' is invalid"),
    ("a value too few", HEAD + "r1 1 0.3 'small'\n", "line 2: 4 values for 5 columns"),
    ("duplicate description", HEAD + GOOD + "r1 2 0.3 5e3 'small'\n",
     "line 3, column description: 'r1' also on line 2"),
    ("'=' on the first line", HEAD + "r1 1 = 5e3 'small'\n", "line 2, column mu: '=' but no line above"),
    ("unknown numerical preset", "description scene numerics\nr1 'small' 'fastest'\n",
     "line 2, column numerics: 'fastest' is not a preset of scene small; valid: balanced, fast, paper"),
    ("a law's constant without the law", "description c_w\nr1 1e4\n",
     "line 2: parameter c_w=10000.0 is used only with drag_model='linear'"),
    ("line numbers count comments and blank lines", "# a study\n\n" + HEAD + "\n# next\nr1 1 0.3 0 'small'\n",
     "line 6, column tau_cr"),
    # what YADE's reader (utils.TableParamReader, yade 2023) reads otherwise than written
    ("a last line without its newline", HEAD + "r1 1 0.35 5000 'small'",
     "line 2: \"r1 1 0.35 5000 'small'\" has no final newline; YADE's reader would drop its last character "
     "(\"'small'\" read as \"'small\")"),
    ("a column named twice", "description mu tau_cr mu\nr1 0.3 5e3 0.05\n",
     "line 1, column mu: named twice (columns 2 and 4)"),
    ("column names only", "# to come\n" + HEAD + "# r1 1 0.3 5e3 'small'\n", "line 2: column names only"),
    ("a boolean ridge", HEAD + "r1 True 0.3 5e3 'small'\n", "line 2, column ridge: True must be a whole number"),
    ("a boolean strength", HEAD + "r1 1 0.3 True 'small'\n", "line 2, column tau_cr: parameter tau_cr=True is a boolean"),
    # the geometry is the scene's mesh's: a column would be ignored, so it is refused
    ("a geometry column", "description scene keel_depth\nr1 'small' 4.0\n",
     "line 1, column keel_depth: keel_depth is the scene's geometry, taken from its mesh: not a run parameter; "
     "to change the geometry pick a scene (deep, demo, paper, small, tiny, wide;"),
    ("a description with a folder", HEAD + "runs/r1 1 0.3 5e3 'small'\n",
     "line 2, column description: 'runs/r1' is not a plain file name"),
]


@pytest.mark.parametrize("what, text, message", CASES, ids=[c[0] for c in CASES])
def test_each_mistake_is_named_by_line_and_column(tmp_path, what, text, message):
    path = tmp_path / "t.table"
    path.write_text(text)
    problems = check_table(str(path))
    assert any(message in p for p in problems), problems


def test_the_projects_tables_pass_and_equals_repeats_the_line_above(tmp_path):
    for name in ("study_small.table", "study_reduced.table", "study_paper.table", "water_models.table"):
        assert check_table(os.path.join(ROOT, "data", name)) == [], name
    path = tmp_path / "t.table"
    path.write_text(HEAD + GOOD + "r2 2 = = =\n")
    assert check_table(str(path)) == []


def test_every_problem_is_reported_not_only_the_first(tmp_path):
    path = tmp_path / "t.table"
    path.write_text(HEAD + "r1 1 abc 5e3 'small'\nr2 1 0.3 -1 'small'\nr3 1 0.3 5e3 'big'\n")
    problems = check_table(str(path))
    assert [p.split(",")[0] for p in problems] == ["line 2", "line 3", "line 4"]


def test_the_batch_driver_refuses_a_bad_table_before_any_line_runs(tmp_path):
    """The YADE driver checks the whole table first: a bad line 3 stops line 2
    too, with the message naming it, and nothing is written."""
    table = tmp_path / "t.table"
    table.write_text(HEAD + GOOD + "r2 1 abc 5e3 'small'\n")
    env = command_env(YADE_BATCH=f"{table}:2")
    r = subprocess.run(["yade", "-n", "-x", os.path.join(ROOT, "yade_scripts", "punch_through.py")],
                       env=env, capture_output=True, text=True, timeout=120, cwd=str(tmp_path))
    assert r.returncode != 0
    assert "line 3, column mu: abc does not parse" in r.stdout + r.stderr
    assert [p.name for p in tmp_path.iterdir()] == ["t.table"]


def test_the_study_command_exits_nonzero_listing_the_problems(tmp_path):
    table = tmp_path / "t.table"
    table.write_text(HEAD + "r1 1 abc 5e3 'small'\n")
    r = icerubble("study", "check", table, timeout=60)
    assert r.returncode == 2 and "line 2, column mu" in r.stdout   # refused before any work
    table.write_text(HEAD + GOOD)
    r = icerubble("study", "check", table, timeout=60)
    assert r.returncode == 0 and "every line can run" in r.stdout
