"""Punch-through run on one ridge (phase 2, paper section 2.4).

    yade -j2 -n -x yade_scripts/punch_through.py                # demo scene, ridge 1
    yade-batch --job-threads=2 -j 1 --disable-pynotify data/study_small.table yade_scripts/punch_through.py
    YADE_BATCH=data/study_paper.table:4 yade -j2 -n -x yade_scripts/punch_through.py   # one line

Every column of a table is a parameter below: ``ridge`` (the pile's seed),
``model`` (fem-dem, the default, or rigid-dem: the discrete-only comparison model
of rigid YADE blocks, docs/model.md §6),
``scene`` (demo | small | wide | paper | tiny: pile size, mesh, penalty, travel; see
icerubble/run/presets.py), ``numerics`` (paper | balanced | fast: the scene's
numerical preset, default paper: time step, mass scaling, contact reach,
sleeping far field), ``device`` (cpu | cuda: where the steps run, default
$ICERUBBLE_DEVICE, set by `icerubble study run --device`, else cpu;
docs/gpu.md) and any Table 1 parameter (icerubble/parameters.py),
e.g. mu, tau_cr, sigma_cr, G, force_direction, target_travel. The settle's
limit is $ICERUBBLE_SETTLE_MAX_TIME [s], set by `icerubble study run
--settle-max-time`, else the registry's.
OUT_DIR is the out_dir column, else $ICERUBBLE_OUT_DIR (set by `icerubble
study run --out`), else runs/ in this checkout.
Piles and meshes are made on first use and cached in OUT_DIR/scenes; the
result is OUT_DIR/<description>.h5 (docs/results_format.md) with ParaView
fields in OUT_DIR/<description>_fields/. An interrupted run resumes from its
checkpoint when started again.
"""
import os
import sys

from yade import utils

# This checkout's package, not whichever one is installed (an editable install
# points at one checkout; a worktree is another): YADE puts neither the
# script's folder nor the working folder on sys.path.
_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(sys.argv[0] if sys.argv[0].endswith(".py")
                                                        else __file__)))
sys.path.insert(0, _ROOT)

from icerubble import exit_status, parameters as P
from icerubble.study.table_check import check_table

# The whole table is checked before this line runs (YADE would otherwise stop
# at the first bad value with a NameError naming no column).
if os.environ.get("YADE_BATCH"):
    _table = os.environ["YADE_BATCH"].split(":")[0]
    _problems = check_table(_table)
    if _problems:   # bad input, before any work: exit 2 (icerubble/exit_status.py)
        print(f"punch_through: the table {_table} has problems, no line runs:\n  " + "\n  ".join(_problems),
              file=sys.stderr)
        sys.exit(exit_status.USAGE)


# results go beside the scripts' checkout (runs/), whatever the working folder;
# Table 1 parameters default to None: "the scene's value, else Table 1".
_OUT = os.environ.get("ICERUBBLE_OUT_DIR") or os.path.join(_ROOT, "runs")
utils.readParamsFromTable(ridge=1, scene="demo", numerics="", model="fem-dem", device="", out_dir=_OUT, resume=True,
                          noTableOk=True, **{k: None for k in P.TABLE_1})
from yade.params import table
from yade.wrapper import O

from icerubble.cli import os_error_text
from icerubble.run.driver import RunInterrupted
from icerubble.study.line import run_one
from icerubble.study.outcome import EXIT_INTERRUPTED, INTERRUPTED_MARK, RESULT_MARK

overrides = {k: getattr(table, k) for k in P.TABLE_1 if getattr(table, k) is not None}
description = O.tags["description"] if "description" in O.tags.keys() else ""
# a relative out_dir is relative to where the study was started (yade-batch
# runs each line in the study's log folder)
out_dir = os.path.join(os.environ.get("ICERUBBLE_WORKDIR", ""), table.out_dir)
try:
    out = run_one(scene_name=table.scene, ridge=table.ridge, overrides=overrides, out_dir=out_dir,
                  description=description, resume=bool(table.resume), numerics_name=table.numerics or None,
                  model=table.model, device=table.device or os.environ.get("ICERUBBLE_DEVICE") or "cpu",
                  settle_max_time=float(os.environ["ICERUBBLE_SETTLE_MAX_TIME"])
                  if os.environ.get("ICERUBBLE_SETTLE_MAX_TIME") else None)
except RunInterrupted as e:   # a scheduler's signal or Ctrl-C: the checkpoint is written, a rerun resumes
    print(INTERRUPTED_MARK + str(e), file=sys.stderr, flush=True)
    sys.exit(EXIT_INTERRUPTED)
except ValueError as e:   # bad input, refused before the run: exit 2 (icerubble/exit_status.py)
    print(f"punch_through: error: {e}", file=sys.stderr)
    sys.exit(exit_status.USAGE)
except RuntimeError as e:   # a run in progress elsewhere, an instability: failed while working
    print(f"punch_through: error: {e}", file=sys.stderr)
    sys.exit(exit_status.FAILED)
except OSError as e:   # a full disk, a folder that cannot be written: one line in the line's log
    print(f"punch_through: error: {os_error_text(e)}", file=sys.stderr)
    sys.exit(exit_status.FAILED)
print(RESULT_MARK + os.path.abspath(out), flush=True)   # what `icerubble study` reads as done
utils.waitIfBatch()
