"""The result file's reader, icerubble/files/results.py (beside its writer,
icerubble/files/recorder.py), under its former name for scripts that import
postproc.results."""
from icerubble.files.results import (BLOCK, FORMAT_NAME, FORMAT_VERSION, INDENTER, LAYER,  # noqa: F401
                                     OPTIONAL_BOND_FIELDS, OPTIONAL_GROUPS, REQUIRED_GROUPS, FailureMode,
                                     ResultFileError, RunResult, Snapshot, find_results, load, load_folder)
