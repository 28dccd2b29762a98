"""Phase 1 (paper section 2.4): rigid blocks float up under the consolidated layer into a pile.

Run:   yade -n -x yade_scripts/make_pile.py            (defaults below: the demo pile)
       yade-batch --job-threads=1 -j 1 --disable-pynotify data/pile_small.table yade_scripts/make_pile.py
Output: an icerubble-pile HDF5 file (layout: docs/pile_and_mesh.md).

The model: icerubble/rigid_dem/phase1.py. This script reads one table line
(columns and defaults: the registry's PILE, icerubble/parameters.py) and runs it.
"""
import os
import sys

import yade
from yade import utils
from yade.wrapper import O

# This checkout's package, not whichever one is installed (an editable install
# points at one checkout; a worktree is another): YADE puts neither the
# script's folder nor the working folder on sys.path.
_ROOT = os.path.dirname(os.path.dirname(os.path.abspath(sys.argv[0] if sys.argv[0].endswith(".py")
                                                        else __file__)))
sys.path.insert(0, _ROOT)

from icerubble import exit_status
from icerubble.parameters import PILE, PILE_SHARED, REGISTRY
from icerubble.rigid_dem.phase1 import make_pile
from icerubble.study.table_check import reader_problems

# every touching pair prints a warning each step otherwise (docs/yade_notes.md)
yade.log.setLevel('Polyhedra_support.cpp', yade.log.ERROR)

# what YADE's reader would read otherwise than the table says (a last line
# without its newline, a column named twice), before it reads it
if os.environ.get("YADE_BATCH"):
    _table = os.environ["YADE_BATCH"].split(":")[0]
    _problems = reader_problems(_table)
    if _problems:
        print(f"make_pile: the table {_table} has problems, no line runs:\n  " + "\n  ".join(_problems),
              file=sys.stderr)
        sys.exit(exit_status.USAGE)   # bad input, before any work (icerubble/exit_status.py)

# the columns a pile table may have and their defaults (the demo pile's):
# the registry's, icerubble/parameters.py (PILE, and the run's PILE_SHARED)
utils.readParamsFromTable(noTableOk=True, **{k: p.default for k, p in PILE.items()},
                          **{k: REGISTRY[k].default for k in PILE_SHARED})
from yade.params import table as P  # noqa: E402

try:
    make_pile(P, O.tags["description"] if "description" in O.tags.keys() else "")
except ValueError as e:   # a bad parameter: one line naming it, not a traceback; exit 2
    print(f"make_pile: error: {e}", file=sys.stderr)
    sys.exit(exit_status.USAGE)
utils.waitIfBatch()
