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
    return run.scene, run.model, str(run.parameters.get("force_direction", "paper"))


def row_variant(row):
    """The same of a summary row (postproc.summary.summarize)."""
    return row["scene"], row["model"], row["force_direction"]


def label(key, keys):
    """The variant's name among `keys`, all the variants of a folder: the scene
    is named only where the folder holds more than one."""
    scene, model, direction = key
    one_scene = len({k[0] for k in keys}) == 1
    return (f"{model}, force_direction = {direction}" if one_scene
            else f"{scene}, {model}, force_direction = {direction}")


def folder(key, keys):
    """The variant's sub-folder name among `keys`, the scene first where the
    folder holds more than one (fem-dem_paper, deep_fem-dem_work_conjugate)."""
    scene, model, direction = key
    one_scene = len({k[0] for k in keys}) == 1
    return f"{model}_{direction}" if one_scene else f"{scene}_{model}_{direction}"
