"""Malformed input, entry point by entry point: the commands a user types
(`icerubble ...`, the YADE scripts), the Python API, and every file the
project reads (pile, mesh, checkpoint, result, table, measured record).

Each case must be refused with a message that names what is wrong, before any
work: a command exits non-zero with no traceback, the API raises ValueError,
and no file that looks complete is left behind (no new HDF5 file that opens as
complete, no mesh, no result, no figure). The readers' own tests
(tests/files/test_readers.py, tests/run/test_checkpoint_reader.py,
tests/run/test_table_check.py) go through each dataset; this catalogue goes
through each door.
"""
import os
import re
import subprocess
import sys

import h5py
import numpy as np
import pytest

from icerubble.files.h5io import open_complete
from tests.commands import ICERUBBLE, env as command_env, icerubble
from tests.h5_edits import broken, replace
from tests.paths import DATA, ROOT

PILE = os.path.join(DATA, "demo_pile.h5")
QUICK = dict(penalty=2e10, target_travel=0.001, ramp_time=0.05)

CASES = {}


def case(door, message):
    """Register a case: `door` is "cli" (the function returns icerubble's
    arguments), "yade" (returns (script, table text)) or "api" (returns a
    callable that must raise ValueError); `message` a regex the refusal must match."""
    def register(fn):
        CASES[fn.__name__] = (door, message, fn)
        return fn
    return register


@pytest.fixture(scope="module")
def good(tmp_path_factory):
    """Intact inputs: the demo pile, a one-row bonded mesh, a complete result
    and the checkpoint of a run stopped while loading."""
    from icerubble.geometry import meshing
    from icerubble.run.punch_through_run import PunchThrough, RunOptions
    from tests.run.punch_through_scenes import brick_pile
    d = tmp_path_factory.mktemp("good")
    brick_pile(d / "pile.h5", width=6.0, rows=1)
    meshing.mesh_pile_file(str(d / "pile.h5"), str(d / "mesh.h5"), element_size=0.3)
    opts = dict(threads=1, progress_every_s=1e9, vtu=False, dt_fraction=0.8)
    PunchThrough(d / "mesh.h5", d / "result.h5", params=QUICK, options=RunOptions(**opts)).run()
    stopped = PunchThrough(d / "mesh.h5", d / "stopped.h5", params=QUICK,
                           options=RunOptions(stop_after_steps=8000, **opts))
    with pytest.raises(KeyboardInterrupt):
        stopped.run()
    return dict(pile=PILE, bricks=str(d / "pile.h5"), mesh=str(d / "mesh.h5"), result=str(d / "result.h5"),
                checkpoint=str(d / "stopped.checkpoint.h5"))


def _text(d, name, text):
    p = os.path.join(str(d), name)
    with open(p, "w") as f:
        f.write(text)
    return p


def _table(d, text):
    return _text(d, "study.table", text)


# ---- icerubble (command lines) -------------------------------------------

@case("cli", "unknown command 'punch'")
def cli_unknown_command(d, g):
    return ["punch"]


@case("cli", r"pile file .*missing\.h5.* does not exist")
def cli_mesh_of_a_missing_pile(d, g):
    return ["mesh", os.path.join(d, "missing.h5"), os.path.join(d, "mesh.h5")]


@case("cli", r"pile file .*'blocks/corners': missing")
def cli_mesh_of_a_pile_without_corners(d, g):
    return ["mesh", broken(g["pile"], d, lambda f: f.__delitem__("blocks/corners")), os.path.join(d, "mesh.h5")]


@case("cli", r"'blocks/corners': units 'mm', expected 'm'")
def cli_mesh_of_a_pile_in_millimetres(d, g):
    return ["mesh", broken(g["pile"], d, lambda f: f["blocks/corners"].attrs.__setitem__("units", "mm")),
            os.path.join(d, "mesh.h5")]


@case("cli", "not an HDF5 file")
def cli_mesh_of_a_text_file(d, g):
    return ["mesh", _text(d, "pile.h5", "corners 0 0 1 1\n"), os.path.join(d, "mesh.h5")]


@case("cli", "element_size")
def cli_mesh_with_a_negative_element_size(d, g):
    return ["mesh", g["pile"], os.path.join(d, "mesh.h5"), "--element-size", "-0.1"]


@case("cli", "indenter_width")
def cli_mesh_with_an_indenter_wider_than_the_domain(d, g):
    return ["mesh", g["pile"], os.path.join(d, "mesh.h5"), "--indenter-width", "50"]


@case("cli", "has format 'icerubble-mesh', expected 'icerubble-pile'")
def cli_mesh_of_a_mesh(d, g):
    return ["mesh", g["mesh"], os.path.join(d, "mesh.h5")]


@case("cli", r"result .*missing\.h5.* does not exist")
def cli_run_figures_of_a_missing_result(d, g):
    return ["run-figures", os.path.join(d, "missing.h5"), "-o", os.path.join(d, "fig")]


@case("cli", "format 'icerubble-mesh'")
def cli_run_figures_of_a_mesh(d, g):
    return ["run-figures", g["mesh"], "-o", os.path.join(d, "fig")]


@case("cli", "incomplete")
def cli_run_figures_of_an_incomplete_result(d, g):
    return ["run-figures", broken(g["result"], d, lambda f: f.attrs.__setitem__("complete", 0)),
            "-o", os.path.join(d, "fig")]


@case("cli", "'force/F'")
def cli_run_figures_of_a_result_without_its_force_record(d, g):
    return ["run-figures", broken(g["result"], d, lambda f: f.__delitem__("force/F")),
            "-o", os.path.join(d, "fig")]


@case("cli", "non-finite")
def cli_run_figures_of_a_result_with_nan_forces(d, g):
    def nan(f):
        F = f["force/F"][...]
        F[3] = np.nan
        replace("force/F", F)(f)
    return ["run-figures", broken(g["result"], d, nan), "-o", os.path.join(d, "fig")]


@case("cli", "no result files to summarise")
def cli_summary_of_an_empty_folder(d, g):
    os.makedirs(os.path.join(d, "runs"))
    return ["summary", os.path.join(d, "runs"), "-o", os.path.join(d, "summary.csv")]


@case("cli", "is not a folder")
def cli_figures_of_a_missing_folder(d, g):
    return ["figures", os.path.join(d, "no_such_runs"), "-o", os.path.join(d, "fig")]


@case("cli", "no_such_runs: no such folder of results")
def cli_compare_of_a_missing_folder(d, g):
    return ["compare", os.path.join(d, "no_such_runs")]


@case("cli", "no complete run results under")
def cli_compare_of_a_folder_without_runs(d, g):
    os.makedirs(os.path.join(d, "empty_runs"))
    return ["compare", os.path.join(d, "empty_runs")]


@case("cli", "--label given 1 times for 2 folders")
def cli_compare_with_labels_not_one_per_folder(d, g):
    return ["compare", d, d, "--label", "one"]


def _measured(d, text, *extra):
    return ["measured", _text(d, "record.csv", text), "--keel-depth", "4", "--indenter-width", "4",
            "--porosity", "0.3", "-o", os.path.join(d, "report"), *extra]


@case("cli", "data row 1: negative displacement")
def cli_measured_negative_travel(d, g):
    return _measured(d, "y_I [mm],F [kN/m]\n-5,9\n0,0\n1,1\n")


@case("cli", "decreases at data row 3")
def cli_measured_travel_going_back(d, g):
    return _measured(d, "y_I [mm],F [kN/m]\n0,0\n2,1\n1,3\n")


@case("cli", "row 2")
def cli_measured_a_word_for_a_force(d, g):
    return _measured(d, "y_I [mm],F [kN/m]\n0,0\n1,x\n")


@case("cli", "--porosity")
def cli_measured_porosity_above_one(d, g):
    return _measured(d, "y_I [mm],F [kN/m]\n0,0\n1,1\n", "--porosity", "1.2")


@case("cli", r"line 1, column mu_typo: not a parameter; did you mean 'mu'")
def cli_study_check_unknown_column(d, g):
    return ["study", "check", _table(d, "description mu_typo\na 0.3\n")]


@case("cli", r"line 2, column mu: abc does not parse")
def cli_study_check_unquoted_word(d, g):
    return ["study", "check", _table(d, "description mu\na abc\n")]


@case("cli", r"line 3, column description: 'a' also on line 2")
def cli_study_check_duplicate_description(d, g):
    return ["study", "check", _table(d, "description mu\na 0.3\na 0.05\n")]


@case("cli", r"line 2, column tau_cr: .*valid range")
def cli_study_run_out_of_range_value(d, g):
    return ["study", "run", _table(d, "description scene tau_cr\na 'tiny' -5e3\n"), "--out", os.path.join(d, "out")]


@case("cli", r"--jobs = 0")
def cli_study_run_zero_jobs(d, g):
    return ["study", "run", _table(d, "description scene\na 'tiny'\n"), "--out", os.path.join(d, "out"),
            "--jobs", "0"]


@case("cli", r"table .*no_such\.table.* cannot be read: No such file")
def cli_study_check_missing_table(d, g):
    return ["study", "check", os.path.join(d, "no_such.table")]


@case("cli", "ridge")
def cli_demo_negative_ridge(d, g):
    return ["demo", "--ridge", "-1", "--out-dir", os.path.join(d, "demo")]


@case("cli", "travel")
def cli_demo_negative_travel(d, g):
    return ["demo", "--travel-mm", "-3", "--out-dir", os.path.join(d, "demo")]


# ---- the YADE scripts ------------------------------------------------------

@case("yade", r"line 1, column mu_typo: not a parameter; did you mean 'mu'")
def yade_punch_through_unknown_column(d, g):
    return "punch_through.py", f"description scene mu_typo out_dir\na 'tiny' 0.3 '{d}'\n"


@case("yade", r"line 2, column numerics: 'turbo' is not a preset")
def yade_punch_through_unknown_preset(d, g):
    return "punch_through.py", f"description scene numerics out_dir\na 'tiny' 'turbo' '{d}'\n"


@case("yade", r"line 2, column device: 'gpu' is not a device; valid: cpu, cuda")
def yade_punch_through_unknown_device(d, g):
    return "punch_through.py", "scene device\n'tiny' 'gpu'\n"


@case("api", r"device='gpu' is unknown: valid values are cpu, cuda")
def api_model_on_an_unknown_device(d, g):
    from icerubble import engine
    nodes, tri = engine.rectangle_mesh(2, 2, 0.1)
    return lambda: engine.Model(nodes, tri, [0] * len(tri), dict(E=2e9, nu=0.3, rho=920.0), device="gpu")


@case("api", r"device='cuda': the rigid-dem model runs on YADE's engines, on the CPU only")
def api_study_rigid_model_on_the_gpu(d, g):
    from icerubble.study.line import run_one
    return lambda: run_one("tiny", 1, out_dir=d, model="rigid-dem", device="cuda")


@case("yade", r"domain_width")
def yade_make_pile_negative_width(d, g):
    return "make_pile.py", f"seed domain_width out\n1 -10.0 '{os.path.join(d, 'pile.h5')}'\n"


# ---- the Python API ----------------------------------------------------------

@case("api", r"mu.*valid range")
def api_validate_negative_friction(d, g):
    from icerubble import parameters as P
    return lambda: P.validate(dict(mu=-0.1))


@case("api", r"unknown parameter\(s\) tau; known:")
def api_validate_unknown_parameter(d, g):
    from icerubble import parameters as P
    return lambda: P.validate(dict(tau=5e3))


@case("api", "c_w")
def api_validate_drag_constant_without_its_law(d, g):
    from icerubble import parameters as P
    return lambda: P.validate(dict(c_w=1e3, drag_model="quadratic"))


@case("api", r"dt_fraction=2 must be in \(0, 1\]")
def api_run_options_step_above_stable(d, g):
    from icerubble.run.punch_through_run import RunOptions
    return lambda: RunOptions(dt_fraction=2)


@case("api", r"must end in \.h5")
def api_result_not_h5(d, g):
    from icerubble.run.punch_through_run import PunchThrough
    return lambda: PunchThrough(g["mesh"], os.path.join(d, "result.txt"), params=QUICK)


@case("api", "has format 'icerubble-pile', expected 'icerubble-mesh'")
def api_run_on_a_pile(d, g):
    from icerubble.run.punch_through_run import PunchThrough
    return lambda: PunchThrough(g["pile"], os.path.join(d, "r.h5"), params=QUICK)


@case("api", r"'triangles': missing")
def api_run_on_a_mesh_without_triangles(d, g):
    from icerubble.run.punch_through_run import PunchThrough
    mesh = broken(g["mesh"], d, lambda f: f.__delitem__("triangles"))
    return lambda: PunchThrough(mesh, os.path.join(d, "r.h5"), params=QUICK)


@case("api", r"'nodes': units 'mm', expected 'm'")
def api_run_on_a_mesh_in_millimetres(d, g):
    from icerubble.run.punch_through_run import PunchThrough

    def mm(f):
        f["nodes"][...] = f["nodes"][...] * 1e3
        f["nodes"].attrs["units"] = "mm"
    mesh = broken(g["mesh"], d, mm)
    return lambda: PunchThrough(mesh, os.path.join(d, "r.h5"), params=QUICK)


@case("api", r"'triangles': ids must lie in")
def api_run_on_a_mesh_with_a_node_id_past_the_end(d, g):
    from icerubble.run.punch_through_run import PunchThrough
    mesh = broken(g["mesh"], d, lambda f: f["triangles"].__setitem__((0, 0), len(f["nodes"])))
    return lambda: PunchThrough(mesh, os.path.join(d, "r.h5"), params=QUICK)


@case("api", r"checkpoint .*'engine/velocities'.*non-finite")
def api_resume_from_a_checkpoint_with_nan_velocities(d, g):
    from icerubble.run.punch_through_run import PunchThrough, RunOptions

    def nan(f):
        v = f["engine/velocities"][...]
        v[3, 0] = np.nan
        replace("engine/velocities", v)(f)
    broken(g["checkpoint"], d, nan, name="stopped.checkpoint.h5")
    run = PunchThrough(g["mesh"], os.path.join(d, "stopped.h5"), params=QUICK,
                       options=RunOptions(threads=1, progress_every_s=1e9, vtu=False, dt_fraction=0.8))
    return lambda: run.run(resume=True)


@case("api", r"checkpoint .*'engine/positions'.*missing")
def api_resume_from_a_checkpoint_without_positions(d, g):
    from icerubble.run.punch_through_run import PunchThrough, RunOptions
    broken(g["checkpoint"], d, lambda f: f.__delitem__("engine/positions"), name="stopped.checkpoint.h5")
    run = PunchThrough(g["mesh"], os.path.join(d, "stopped.h5"), params=QUICK,
                       options=RunOptions(threads=1, progress_every_s=1e9, vtu=False, dt_fraction=0.8))
    return lambda: run.run(resume=True)


@case("api", "scene='huge' is unknown")
def api_study_unknown_scene(d, g):
    from icerubble.study.line import run_one
    return lambda: run_one("huge", 1, out_dir=os.path.join(d, "runs"))


@case("api", r"settle_max_time=9.0 and options.settle_max_time=5.0 differ: options, when given, carry the "
             r"settle's limit")
def api_study_settle_limit_beside_options(d, g):
    from icerubble.run.punch_through_run import RunOptions
    from icerubble.study.line import run_one
    return lambda: run_one("tiny", 1, out_dir=os.path.join(d, "runs"), options=RunOptions(settle_max_time=5.0),
                           settle_max_time=9.0)


@case("api", "numerics='turbo' is unknown")
def api_study_unknown_preset(d, g):
    from icerubble.study.line import run_one
    return lambda: run_one("tiny", 1, out_dir=os.path.join(d, "runs"), numerics_name="turbo")


@case("api", "ridge=-2")
def api_study_negative_ridge(d, g):
    from icerubble.study.line import run_one
    return lambda: run_one("tiny", -2, out_dir=os.path.join(d, "runs"))


@case("api", "element_size")
def api_mesh_zero_element_size(d, g):
    from icerubble.geometry import meshing
    return lambda: meshing.mesh_pile_file(g["pile"], os.path.join(d, "mesh.h5"), element_size=0.0)


@case("api", r"sigma_cr_top must be finite and > 0")
def api_cohesive_law_negative_strength(d, g):
    from icerubble import cohesive_law
    return lambda: cohesive_law.strength_at_depth(np.array([0.5]), 2.0, -1.0, 5e3, 15.0)


def _square_model():
    from icerubble.engine import Model, rectangle_mesh
    nodes, tris = rectangle_mesh(2, 2, 0.5)
    return Model(nodes, tris, np.zeros(len(tris), dtype=np.int32), [dict(E=2e9, rho=920.0)])


@case("api", "penalty")
def api_engine_negative_penalty(d, g):
    m = _square_model()
    return lambda: m.set(penalty=-1.0)


@case("api", r"nodes must be finite")
def api_engine_nan_node(d, g):
    from icerubble.engine import Model, rectangle_mesh
    nodes, tris = rectangle_mesh(2, 2, 0.5)
    nodes[4, 1] = np.nan
    return lambda: Model(nodes, tris, np.zeros(len(tris), dtype=np.int32), [dict(E=2e9, rho=920.0)])


@case("api", r"'force/y_I'")
def api_results_reader_without_travel(d, g):
    from icerubble.files import results
    path = broken(g["result"], d, lambda f: f.__delitem__("force/y_I"))
    return lambda: results.load(path)


# ---- issue 25: no wrong answer, lost file or traceback at any edge -----------
# Tables YADE's reader would read otherwise than they are written (checked
# against yade 2023: utils.TableParamReader cuts each line's last character and
# keeps a column's last value), and descriptions that would write outside --out.

@case("cli", r"t\.table: line 2: .*has no final newline; YADE's reader would drop its last character "
             r"\('0\.35' read as '0\.3'\)")
def cli_study_check_last_line_without_its_newline(d, g):
    return ["study", "check", _text(d, "t.table", "description scene mu\na 'tiny' 0.35")]


@case("yade", r"line 2: .*has no final newline.*'0\.35' read as '0\.3'")
def yade_punch_through_last_line_without_its_newline(d, g):
    return "punch_through.py", f"description scene out_dir mu\na 'tiny' '{d}' 0.35"


@case("yade", r"line 2: .*has no final newline")
def yade_make_pile_last_line_without_its_newline(d, g):
    return "make_pile.py", f"seed out\n1 '{os.path.join(d, 'pile.h5')}'"


@case("yade", r"seed=1\.5 must be a whole number >= 0")
def yade_make_pile_fractional_seed(d, g):
    return "make_pile.py", f"seed out\n1.5 '{os.path.join(d, 'pile.h5')}'\n"


@case("cli", r"line 1, column mu: named twice \(columns 3 and 4\)")
def cli_study_check_a_column_named_twice(d, g):
    return ["study", "check", _table(d, "description scene mu mu\na 'tiny' 0.3 0.05\n")]


@case("cli", r"line 2: column names only, no lines to run")
def cli_study_check_column_names_only(d, g):
    return ["study", "check", _table(d, "# a study\ndescription scene mu\n\n# to come\n")]


@case("cli", r"line 2, column ridge: True must be a whole number >= 0")
def cli_study_check_a_boolean_ridge(d, g):
    return ["study", "check", _table(d, "description scene ridge\na 'tiny' True\n")]


@case("cli", r"line 2, column mu: parameter mu=True is a boolean, not a number; valid range")
def cli_study_check_a_boolean_friction(d, g):
    return ["study", "check", _table(d, "description scene mu\na 'tiny' True\n")]


@case("cli", r"line 2, column resume: 'no' must be True or False")
def cli_study_check_a_word_for_resume(d, g):
    return ["study", "check", _table(d, "description scene resume\na 'tiny' 'no'\n")]


@case("cli", r"line 1, column mu!: not a parameter.*keeps the '!'")
def cli_study_check_a_marked_column_beside_a_description(d, g):
    return ["study", "check", _table(d, "description scene mu!\na 'tiny' 0.3\n")]


@case("cli", r"line 2, column description: '\.\./x' is not a plain file name: use only letters, digits")
def cli_study_run_description_up_a_folder(d, g):
    return ["study", "run", _table(d, "description scene\n../x 'tiny'\n"), "--out", os.path.join(d, "out")]


@case("cli", r"line 2, column description: '/\S*/abs' is not a plain file name")
def cli_study_check_absolute_description(d, g):
    return ["study", "check", _table(d, f"description scene\n{d}/abs 'tiny'\n")]


@case("cli", r"line 2, column description: 'sub/a' is not a plain file name")
def cli_study_submit_description_in_a_subfolder(d, g):
    return ["study", "submit", _table(d, "description scene\nsub/a 'tiny'\n"), "--slurm",
            "--out", os.path.join(d, "out")]


@case("cli", r"line 2: the result's name YADE makes of the values, 'scene=tiny,out_dir=o/p', is not a plain "
             r"file name.*add a description column")
def cli_study_check_a_made_description_with_a_slash(d, g):
    return ["study", "check", _table(d, "scene out_dir\n'tiny' 'o/p'\n")]


@case("api", r"description '\.\./escaped' is not a plain file name")
def api_study_description_up_a_folder(d, g):
    from icerubble.study.line import run_one
    return lambda: run_one("tiny", 1, out_dir=os.path.join(d, "runs"), description="../escaped")


@case("api", r"ridge=True must be a whole number >= 0")
def api_study_boolean_ridge(d, g):
    from icerubble.study.line import run_one
    return lambda: run_one("tiny", True, out_dir=os.path.join(d, "runs"))


# Operating-system errors: a file where a folder is wanted and the reverse, a
# damaged file where a result goes, an input found bad only after a figure was
# written; each named in one line (exit 2: checked before any work).

def _runs(d, g):
    os.makedirs(os.path.join(d, "runs"))
    os.link(g["result"], os.path.join(d, "runs", "result.h5"))
    return os.path.join(d, "runs")


@case("cli", r"icerubble summary: error: --output '.*dir' is a folder, not a file")
def cli_summary_into_a_folder(d, g):
    os.makedirs(os.path.join(d, "dir"))
    return ["summary", _runs(d, g), "-o", os.path.join(d, "dir")]


@case("cli", r"icerubble figures: error: argument --bond-points: invalid choice: 'broken' "
            r"\(choose from 'split', 'failed'\)")
def cli_figures_with_unknown_bond_points(d, g):
    return ["figures", _runs(d, g), "-o", os.path.join(d, "fig"), "--bond-points", "broken"]


@case("cli", r"icerubble compare: error: --out '.*f/c\.md': '.*f' is a file, not a folder")
def cli_compare_under_a_file(d, g):
    return ["compare", _runs(d, g), "-o", os.path.join(_text(d, "f", "x\n"), "c.md")]


@case("cli", r"icerubble run-figures: error: --out-dir '.*f' is a file, not a folder")
def cli_run_figures_into_a_file(d, g):
    return ["run-figures", g["result"], "-o", _text(d, "f", "x\n")]


@case("cli", r"icerubble figures: error: --out-dir '.*f' is a file, not a folder")
def cli_figures_into_a_file(d, g):
    return ["figures", _runs(d, g), "-o", _text(d, "f", "x\n")]


@case("cli", r"icerubble mesh: error: mesh file '.*f/mesh\.h5': '.*f' is a file, not a folder")
def cli_mesh_under_a_file(d, g):
    return ["mesh", g["pile"], os.path.join(_text(d, "f", "x\n"), "mesh.h5")]


@case("cli", r"icerubble mesh: error: mesh file '.*dir' is a folder, not a file")
def cli_mesh_into_a_folder(d, g):
    os.makedirs(os.path.join(d, "dir"))
    return ["mesh", g["pile"], os.path.join(d, "dir")]


@case("cli", r"icerubble measured: error: --out-dir '.*f' is a file, not a folder")
def cli_measured_into_a_file(d, g):
    return _measured(d, "y_I [mm],F [kN/m]\n0,0\n1,1\n2,3\n3,1\n") + ["-o", _text(d, "f", "x\n")]


@case("cli", r"icerubble measured: error: CSV '.*dir': a folder, not a file")
def cli_measured_of_a_folder(d, g):
    os.makedirs(os.path.join(d, "dir"))
    return ["measured", os.path.join(d, "dir"), "--keel-depth", "4", "--indenter-width", "4", "--porosity", "0.3"]


@case("cli", r"icerubble study: error: --out '.*f' is a file, not a folder")
def cli_study_run_into_a_file(d, g):
    return ["study", "run", _table(d, "description scene\na 'tiny'\n"), "--out", _text(d, "f", "x\n")]


@case("cli", r"icerubble demo: error: --out-dir '.*f' is a file, not a folder")
def cli_demo_into_a_file(d, g):
    return ["demo", "--out-dir", _text(d, "f", "x\n")]


@case("cli", r"icerubble study: error: table '.*dir' cannot be read: Is a directory")
def cli_study_check_of_a_folder(d, g):
    os.makedirs(os.path.join(d, "dir"))
    return ["study", "check", os.path.join(d, "dir")]


@case("cli", r"icerubble summary: error: No space left on device: /dev/full")
def cli_summary_onto_a_full_disk(d, g):
    if not os.path.exists("/dev/full"):
        pytest.skip("no /dev/full here")
    return ["summary", _runs(d, g), "-o", "/dev/full"]


@case("cli", r"icerubble run-figures: error: result file '.*r\.h5', dataset 'mesh/triangles': dtype float64, "
             r"expected integers")
def cli_run_figures_of_float_triangle_ids(d, g):
    # before: the force figure was written, then an IndexError traceback
    def floats(f):
        replace("mesh/triangles", f["mesh/triangles"][...].astype(float))(f)
    return ["run-figures", broken(g["result"], d, floats, name="r.h5"), "-o", os.path.join(d, "fig")]


@case("yade", r"punch_through: error: .*bad\.h5 exists but cannot be read as a result.*move it away")
def yade_punch_through_damaged_file_at_the_result(d, g):
    _text(d, "bad.h5", "not a result\n")
    return "punch_through.py", f"description scene out_dir\nbad 'tiny' '{d}'\n"


@case("api", r"r\.h5 exists but cannot be read as a result")
def api_study_truncated_file_at_the_result(d, g):
    from icerubble.study.line import run_one
    with open(g["result"], "rb") as f:
        head = f.read(4096)
    with open(os.path.join(d, "r.h5"), "wb") as f:   # a copy cut short
        f.write(head)
    return lambda: run_one("tiny", 1, out_dir=d, description="r")


@case("cli", r"icerubble run-figures: error: result file '.*dir' is a folder, not a file")
def cli_run_figures_of_a_folder(d, g):
    os.makedirs(os.path.join(d, "dir"))
    return ["run-figures", os.path.join(d, "dir"), "-o", os.path.join(d, "fig")]


@case("cli", r"icerubble mesh: error: pile file '.*dir' is a folder, not a file")
def cli_mesh_of_a_folder(d, g):
    os.makedirs(os.path.join(d, "dir"))
    return ["mesh", os.path.join(d, "dir"), os.path.join(d, "mesh.h5")]


# Command-line conventions: one exit status per kind of outcome, every usage
# line names `icerubble <command>`.

@case("cli", r"usage: icerubble COMMAND")
def cli_no_command(d, g):
    return []


# ---- the checks -------------------------------------------------------------

def _files(d):
    return {os.path.join(r, n) for r, _, ns in os.walk(d) for n in ns}


def _looks_complete(path):
    if not path.endswith(".h5"):
        return path.endswith((".png", ".pdf", ".csv", ".md", ".pvd", ".vtu"))
    try:
        open_complete(path).close()
        return True
    except ValueError:
        return False


def test_the_commands_exit_0_when_the_input_is_good(good, tmp_path):
    """The other side of the catalogue: the same doors with good input succeed."""
    runs = tmp_path / "runs"
    runs.mkdir()
    os.link(good["result"], runs / "result.h5")
    for args in (["run-figures", good["result"], "-o", str(tmp_path / "fig")],
                 ["summary", str(runs), "-o", str(tmp_path / "summary.csv")],
                 ["study", "check", os.path.join(ROOT, "data", "study_tiny.table")]):
        r = subprocess.run([*ICERUBBLE, *args], cwd=tmp_path, env=command_env(), capture_output=True, text=True,
                           timeout=300)
        assert r.returncode == 0, f"{args}: exit {r.returncode}\n{r.stdout}{r.stderr}"
    assert list((tmp_path / "fig").glob("*.png")) and (tmp_path / "summary.csv").exists()


def test_the_catalogue_covers_every_door_with_at_least_40_cases():
    doors = {door for door, _, _ in CASES.values()}
    assert len(CASES) >= 40 and doors == {"cli", "yade", "api"}


# cases met while a command works, not before: exit 1
WHILE_WORKING = ("cli_summary_onto_a_full_disk",)


@pytest.mark.parametrize("name", sorted(CASES))
def test_malformed_input_is_refused_clearly_before_any_work(name, good, tmp_path):
    door, message, make = CASES[name]
    d = str(tmp_path)
    what = make(d, good)
    before = _files(d)
    if door == "api":
        with pytest.raises(ValueError) as e:
            what()
        text = str(e.value)
    else:
        if door == "cli":
            cmd, env = [*ICERUBBLE, *what], command_env()
        else:
            script, table = what
            env = command_env(YADE_BATCH=_table(d, table) + ":2")
            before = _files(d)
            cmd = ["yade", "-n", "-x", os.path.join(ROOT, "yade_scripts", script)]
        r = subprocess.run(cmd, env=env, cwd=d, capture_output=True, text=True, timeout=300)
        text = r.stdout + r.stderr
        # refused before any work: exit 2 (icerubble/exit_status.py), whichever
        # door; a disk found full while writing fails while working: exit 1
        expected = 1 if name in WHILE_WORKING else 2
        assert r.returncode == expected, f"{name}: exit {r.returncode}, not {expected}\n{text}"
        assert "Traceback" not in text, f"{name}: a traceback\n{text}"
    assert re.search(message, text), f"{name}: the message does not say {message!r}:\n{text}"
    made = sorted(p for p in _files(d) - before if _looks_complete(p))
    assert not made, f"{name}: left files that look complete: {made}"
    with h5py.File(good["result"], "r") as f:   # the intact inputs are untouched
        assert int(f.attrs["complete"]) == 1


# ---- issue 25: nothing lost ---------------------------------------------------

def _bytes(path):
    with open(path, "rb") as f:
        return f.read()


def _refused(r, message):
    text = r.stdout + r.stderr
    assert r.returncode == 2, f"exit {r.returncode}\n{text}"
    assert "Traceback" not in text, text
    assert re.search(message, text), f"the message does not say {message!r}:\n{text}"


@pytest.mark.parametrize("target, extra, message", [
    ("result", [], r"mesh file '.*out\.h5' exists: name another file, or give --overwrite"),
    ("result", ["--overwrite"], r"mesh file '.*out\.h5' has format 'icerubble-run'.*--overwrite replaces only"),
    ("text", ["--overwrite"], r"mesh file '.*out\.h5' is not an HDF5 file.*--overwrite replaces only"),
    ("pile", ["--overwrite"], r"mesh file '.*pile\.h5' is the input pile"),
])
def test_mesh_never_replaces_a_file_that_is_not_its_own_mesh(good, tmp_path, target, extra, message):
    """Before: `icerubble mesh PILE MESH` replaced any MESH, its own pile included."""
    pile = tmp_path / "pile.h5"
    pile.write_bytes(_bytes(good["bricks"]))
    out = {"result": tmp_path / "out.h5", "text": tmp_path / "out.h5", "pile": pile}[target]
    if target == "result":
        out.write_bytes(_bytes(good["result"]))
    elif target == "text":
        out.write_text("a file of another program\n")
    before = _bytes(out)
    r = icerubble("mesh", pile, out, "--element-size", "0.3", *extra, cwd=tmp_path)
    _refused(r, message)
    assert _bytes(out) == before
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted({"pile.h5", out.name})


def test_mesh_overwrite_replaces_an_icerubble_mesh(good, tmp_path):
    out = tmp_path / "mesh.h5"
    out.write_bytes(_bytes(good["mesh"]))
    r = icerubble("mesh", good["bricks"], out, "--element-size", "0.4", "--overwrite", cwd=tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    with open_complete(out, "icerubble-mesh") as f:
        assert f.attrs["element_size"] == 0.4


FAKE_YADE_BATCH = r'''#!/usr/bin/python3
"""yade-batch standing in for the real one: each line of the table 'runs' for
a few seconds, writes a complete result and a log that names it."""
import os, sys, time
import h5py
from icerubble.study import outcome as SO
from icerubble.study.table_check import read_table
table = sys.argv[-2]
time.sleep(float(os.environ["FAKE_LINE_SECONDS"]))
for n, row, _ in read_table(table)[1]:
    out = os.path.join(os.environ["ICERUBBLE_OUT_DIR"], row["description"] + ".h5")
    with h5py.File(out, "w") as f:
        f.attrs["format"] = SO.RESULT_FORMAT
        f.attrs["complete"] = 1
    with open(SO.log_path(".", n), "w") as f:
        f.write(f"{SO.RESULT_MARK}{out}\n{SO.BATCH_SUMMARY}\nstatus : 0 (OK)\n")
'''


def test_a_second_study_run_of_one_table_into_one_folder_is_refused_at_once(tmp_path):
    """Before: the second run deleted the first one's line logs and the first
    reported its complete line as failed. Now the second is refused, naming
    the first (its pid); the first ends with its line done and its log kept."""
    import shutil
    import time
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    fake = bin_dir / "yade-batch"
    fake.write_text(FAKE_YADE_BATCH)
    fake.chmod(0o755)
    path = f"{bin_dir}{os.pathsep}{os.environ['PATH']}"
    table = shutil.copy(os.path.join(ROOT, "data", "study_tiny.table"), tmp_path / "tiny.table")
    args = [*ICERUBBLE, "study", "run", str(table), "--out", str(tmp_path / "out")]
    first = subprocess.Popen(args, cwd=tmp_path, env=command_env(PATH=path, FAKE_LINE_SECONDS="4"),
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    lock = tmp_path / "out" / "logs" / "tiny" / "run.lock"
    for _ in range(300):   # until the first holds the lock
        if lock.exists() and "process" in lock.read_text():
            break
        time.sleep(0.05)
    second = icerubble("study", "run", table, "--out", tmp_path / "out", cwd=tmp_path, PATH=path,
                       FAKE_LINE_SECONDS="0")
    assert first.poll() is None, "the first run ended before the second started: make its line longer"
    _refused(second, rf"already being run into .*out by process {first.pid} on ")
    text = first.communicate(timeout=120)[0]
    assert first.returncode == 0, text
    assert re.search(r"\n +done (\d+) of \1 lines\n", text) and "failed" not in text, text
    logs = tmp_path / "out" / "logs" / "tiny"
    assert sorted(p.name for p in logs.glob("line*.log")) == ["line5.log", "line6.log", "line7.log"]
    # the lock went with its process: the next run goes ahead
    third = icerubble("study", "run", table, "--out", tmp_path / "out", cwd=tmp_path, PATH=path,
                      FAKE_LINE_SECONDS="0")
    assert third.returncode == 0, third.stdout + third.stderr


# ---- issue 25: operating-system errors met while working ------------------------

def _main(args, capsys):
    from icerubble import cli
    status = cli.main(args)
    return status, capsys.readouterr().err


def test_a_full_disk_leaves_no_file_that_looks_whole(good, tmp_path, capsys, monkeypatch):
    """ENOSPC in the middle of writing the summary: exit 1, one line naming
    the file, and neither the file nor its part left behind."""
    import csv
    import errno
    runs = tmp_path / "runs"
    runs.mkdir()
    os.link(good["result"], runs / "result.h5")

    def full(self, row):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    monkeypatch.setattr(csv.DictWriter, "writerow", full)
    out = tmp_path / "summary.csv"
    status, err = _main(["summary", str(runs), "-o", str(out)], capsys)
    assert status == 1
    assert re.fullmatch(rf"icerubble summary: error: No space left on device: {re.escape(str(out))}\n", err), err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["runs"]


def test_a_folder_that_cannot_be_written_is_refused_before_any_work(good, tmp_path, capsys, monkeypatch):
    """EACCES (as root chmod does not stop a write: os.access stands in)."""
    from icerubble.files import output_path
    monkeypatch.setattr(output_path.os, "access", lambda path, mode: False)
    status, err = _main(["run-figures", good["result"], "-o", str(tmp_path / "fig")], capsys)
    assert status == 2
    assert re.fullmatch(rf"icerubble run-figures: error: --out-dir '.*fig': folder '{re.escape(str(tmp_path))}' "
                        r"cannot be written \(permission denied\)\n", err), err
    assert list(tmp_path.iterdir()) == []


# ---- issue 25: command-line conventions -----------------------------------------

def test_version_names_the_package_and_the_code():
    import tomllib
    with open(os.path.join(ROOT, "pyproject.toml"), "rb") as f:
        version = tomllib.load(f)["project"]["version"]
    r = icerubble("--version")
    assert r.returncode == 0 and r.stdout.startswith(f"icerubble {version}"), r.stdout + r.stderr


def test_help_lists_every_command_and_every_study_action():
    from icerubble.cli import COMMANDS
    from icerubble.study.command import ACTIONS
    r = icerubble("--help")
    assert r.returncode == 0
    listed = [ln.split()[0] for ln in r.stdout.splitlines() if ln.startswith("  ") and ln.strip()]
    assert [c for c in listed if c in COMMANDS] == list(COMMANDS)
    assert [a for a in listed if a in ACTIONS] == list(ACTIONS)
    assert re.search(r"exit status.*\n.*0 success; 2 bad input.*1 a run.*75 interrupted", r.stdout, re.S)
    # the study's own parser offers exactly these actions
    study = icerubble("study", "--help")
    assert "{" + ",".join(ACTIONS) + "}" in study.stdout
    bare = icerubble()
    assert bare.returncode == 2 and bare.stderr == r.stdout


@pytest.mark.parametrize("args", [["figures"], ["run-figures"], ["summary"], ["compare"], ["measured"], ["mesh"],
                                  ["study"], ["study", "run"], ["study", "check"], ["demo"]])
def test_every_usage_line_names_icerubble_and_the_command(args):
    r = icerubble(*args, "--help")
    assert r.returncode == 0 and r.stdout.startswith(f"usage: icerubble {' '.join(args)} "), r.stdout[:200]


@pytest.mark.parametrize("args", [
    ["study", "check", "TABLE"],                       # a table with a typo
    ["run-figures", "missing.h5"],                     # an input that does not exist
    ["compare", "missing"],
    ["figures", "missing"],
    ["summary", "missing"],
    ["demo", "--ridge", "-1", "--out-dir", "x"],       # a value out of range
    ["measured", "x.csv", "--keel-depth", "4", "--indenter-width", "4", "--porosity", "2"],
    ["mesh", "missing.h5", "mesh.h5"],
    ["study", "flee"],                                 # argparse's own refusals
    ["punch"],
])
def test_bad_input_exits_2_in_every_command(tmp_path, args):
    """Before: the same kind of mistake exited 1 in study check, run-figures,
    compare and demo, 2 elsewhere."""
    (tmp_path / "TABLE").write_text("description mu_typo\na 0.3\n")
    r = icerubble(*args, cwd=tmp_path)
    assert r.returncode == 2, f"{args}: exit {r.returncode}\n{r.stdout}{r.stderr}"
    assert "Traceback" not in r.stdout + r.stderr
    assert not (tmp_path / "x").exists() and not (tmp_path / "mesh.h5").exists()


def test_the_modules_entry_points_follow_the_same_convention(tmp_path):
    """`python3 -m postproc.run_figures` (as the docs once said) answers as `icerubble run-figures`."""
    r = subprocess.run([sys.executable, "-m", "postproc.run_figures", "missing.h5"], cwd=tmp_path,
                       env=command_env(), capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert r.stderr.startswith("icerubble run-figures: error: result file 'missing.h5' does not exist")
