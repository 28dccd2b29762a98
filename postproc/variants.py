"""What must not be mixed in one statistic over ridges: the scene, the model
and eq 11's form.

A folder may hold runs of several scenes (`runs/` with the reduced study and
`runs/deep/` with the paper-depth one: results are found recursively), of both
models (docs/rigid_blocks.md) and of both forms of eq 11 (issue 26, item 4).
A 1.7 m keel's ridges beside a 4 m keel's are not more ridges of one study, so
each (scene, model, force direction) is read on its own: make_figures writes a
folder each, paper_comparison a column each.
"""


def variant(run):
    """(scene, model, force direction) of a run (files.results.Run)."""
    return run.scene, run.model, run.force_direction


def row_variant(row):
    """The same of a summary row (postproc.summary.summarize)."""
    return row["scene"], row["model"], row["force_direction"]


def _named(key, keys):
    """The parts of `key` that name it among `keys`, all the variants of a
    folder: the scene only where the folder holds more than one."""
    return key if len({k[0] for k in keys}) > 1 else key[1:]


def label(key, keys):
    """The variant's name among `keys` (deep, fem-dem, force_direction = paper)."""
    *head, direction = _named(key, keys)
    return ", ".join([*head, f"force_direction = {direction}"])


def folder(key, keys):
    """The variant's sub-folder name among `keys` (fem-dem_paper,
    deep_fem-dem_work_conjugate)."""
    return "_".join(_named(key, keys))
