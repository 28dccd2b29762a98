"""A yade-batch table checked as a whole before any line runs.

YADE reads a table line by line when each line starts: an unknown column is a
``NameError`` naming no valid name, an unquoted word a ``NameError`` naming no
column, and a bad value fails only after that line's pile was made. Here every
line is read as yade.utils.TableParamReader reads it (first non-empty line the
column names; ``#`` starts a comment; ``=`` repeats the value above; a
trailing ``!`` marks description columns; lines numbered as in an editor),
each value is parsed as the Python literal YADE will evaluate, and each line is
validated as the run will validate it. Every problem is reported as
``line N, column C: ...``.

Where YADE's reader would silently run something else than the text says,
the table is refused (reader_problems): a last line without its newline
(YADE cuts every line's last character, the newline it expects: ``mu 0.35``
runs at 0.3), a column named twice (the last value wins), a table of column
names only (nothing runs, and the study would report success).

    icerubble study check TABLE
"""
import ast
import difflib
import glob
import os
import re

from .. import parameters as P
from ..run import shipped_ridges as SR
from ..run.presets import NUMERICS, SCENES
from ..engine.model import DEVICES
from .line import MODELS, result_name_problem

# Columns of the punch-through driver (yade_scripts/punch_through.py) beside the
# run parameters (the registry's table columns, icerubble/parameters.py).
DRIVER_COLUMNS = {"ridge", "scene", "numerics", "out_dir", "resume", "description", "model", "device"}


def read_table(path):
    """(columns, rows): rows as (line number, {column: text}) with '=' resolved."""
    try:
        with open(path) as f:
            raw = f.read().split("\n")
    except OSError as e:
        raise ValueError(f"table {path!r} cannot be read: {e.strerror}") from None
    except UnicodeDecodeError:
        raise ValueError(f"table {path!r} is not a text file") from None
    lines = [(i + 1, re.sub(r"\s*#.*", "", text)) for i, text in enumerate(raw)]
    lines = [(n, text) for n, text in lines if text.strip()]
    if not lines:
        raise ValueError(f"table {path!r} has no column names (it is empty)")
    (_, head), body = lines[0], lines[1:]
    columns = head.split()
    if "description" not in columns:   # YADE keeps a '!' in the names of a table with a description
        columns = [c[:-1] if c.endswith("!") else c for c in columns]
    rows, previous = [], {}
    for n, text in body:
        cells = text.split()
        if len(cells) != len(columns):
            rows.append((n, None, f"line {n}: {len(cells)} values for {len(columns)} columns "
                                  f"({' '.join(columns)})"))
            continue
        row = {}
        for c, v in zip(columns, cells):
            if v == "=":
                if c not in previous:
                    rows.append((n, None, f"line {n}, column {c}: '=' but no line above gives a value"))
                    row = None
                    break
                v = previous[c]
            row[c] = v
        if row is not None:
            previous = row
            rows.append((n, row, None))
    return columns, rows


def devices(path, default=None):
    """The devices the lines of table `path` ask for: a line's device column,
    else `default` (a study's --device), else 'cpu' (as
    yade_scripts/punch_through.py reads them)."""
    _, rows = read_table(path)
    return sorted({(_literal(row["device"]) if "device" in row else None) or default or "cpu"
                   for _, row, _ in rows if row})


def _literal(text):
    try:
        return ast.literal_eval(text)
    except (ValueError, SyntaxError):
        raise ValueError(f"{text} does not parse as a value (numbers as 0.3 or 5e3, words quoted: "
                         f"'{text}')") from None


def check_table(path):
    """All problems of the table at `path`, as 'line N, column C: ...' strings
    (an empty list: every line can run)."""
    columns, rows = read_table(path)
    known = DRIVER_COLUMNS | set(P.TABLE_1)
    problems = reader_problems(path)
    for c in columns:
        if c.startswith("!"):   # an environment variable for the line (YADE: !OMP_NUM_THREADS)
            continue
        if c in P.MESH:   # the scene's geometry, never a column
            problems.append(f"line {_head_line(path)}, column {c}: {P.geometry_refused([c], SCENES)}")
        elif c not in known:
            near = difflib.get_close_matches(c, sorted(known), n=1, cutoff=0.4)
            hint = f"; did you mean {near[0]!r}?" if near else ""
            if c.endswith("!") and "description" in columns:
                hint += " (YADE keeps the '!' in a column's name when the table has a description column)"
            problems.append(f"line {_head_line(path)}, column {c}: not a parameter{hint} "
                            f"(valid: {', '.join(sorted(known))})")
    descriptions = {}
    for n, row, error in rows:
        if error:
            problems.append(error)
            continue
        problems += _check_line(n, row, known)
        d = row.get("description")
        if d is None:   # YADE makes one of the values (yade.utils.TableParamReader)
            d = _yade_description(path, row)
            why = result_name_problem(d)
            if why:
                problems.append(f"line {n}: the result's name YADE makes of the values, {d!r}, {why}; "
                                "add a description column")
            continue
        why = result_name_problem(d)
        if why:
            problems.append(f"line {n}, column description: {d!r} {why}")
        else:
            if d in descriptions:
                problems.append(f"line {n}, column description: {d!r} also on line {descriptions[d]} "
                                "(both runs would write the same result file)")
            descriptions.setdefault(d, n)
    return problems


def reader_problems(path):
    """What YADE's reader would read otherwise than the table says, or not at
    all: 'line N: ...' strings (any table of a YADE script, whatever its columns)."""
    with open(path, "rb") as f:
        raw = f.read().decode(errors="replace")
    problems = []
    last_n = raw.count("\n") + 1
    last = raw.rsplit("\n", 1)[-1]
    # YADE cuts the last character of every line, which is its newline but for
    # the last line of a file that does not end with one
    kept, cut = _uncommented(last).strip(), _uncommented(last[:-1]).strip()
    if last and kept != cut:
        read_as = next((b for a, b in zip(kept.split(), cut.split() + [""]) if a != b), "")
        problems.append(f"line {last_n}: {kept!r} has no final newline; YADE's reader would drop its last character "
                        f"({kept.split()[-1]!r} read as {read_as!r}): end the file with a newline")
    head_n, head = _head(path)
    first = {}
    for i, c in enumerate(head, 1):
        if c in first:
            problems.append(f"line {head_n}, column {c}: named twice (columns {first[c]} and {i}); YADE "
                            "would keep the last column's values: drop one")
        first.setdefault(c, i)
    if head and not any(_uncommented(t).strip() for t in raw.split("\n")[head_n:]):
        problems.append(f"line {head_n}: column names only, no lines to run: add one line of values per run")
    return problems


def _uncommented(text):
    return re.sub(r"\s*#.*", "", text)


def _yade_description(path, row):
    """The description YADE gives a line of a table without a description
    column: name=value of the columns marked '!' (all without one), quotes removed."""
    _, head = _head(path)
    marked = [c[:-1] for c in head if c.endswith("!")] or head
    text = ",".join(f"{c.replace('!', '')}={row.get(c, '')}" for c in marked)
    return text.replace("'", "").replace('"', "")


def _check_line(n, row, known):
    values, problems = {}, []
    for c, text in row.items():
        # the description is taken as text, not evaluated
        if c.startswith("!") or c not in known or c == "description":
            continue
        try:
            value = _literal(text)
        except ValueError as e:
            problems.append(f"line {n}, column {c}: {e}")
            continue
        if value is not None:   # None: the scene's value, else Table 1's (as the driver reads it)
            values[c] = value
    scene_name = values.pop("scene", "demo")
    if scene_name not in SCENES:
        problems.append(f"line {n}, column scene: {scene_name!r} is not a scene; valid: "
                        f"{', '.join(sorted(SCENES))}")
        return problems
    ridge = values.pop("ridge", 1)
    if isinstance(ridge, bool) or not (isinstance(ridge, int) and ridge >= 0):
        problems.append(f"line {n}, column ridge: {ridge!r} must be a whole number >= 0 (0, 1, 2, ...: "
                        "it seeds the pile)")
    preset = values.pop("numerics", None)
    if preset is not None and preset not in NUMERICS[scene_name]:
        problems.append(f"line {n}, column numerics: {preset!r} is not a preset of scene {scene_name}; "
                        f"valid: {', '.join(sorted(NUMERICS[scene_name]))}")
    model = values.pop("model", "fem-dem")
    if model not in MODELS:
        problems.append(f"line {n}, column model: {model!r} is not a model; valid: {', '.join(MODELS)}")
    device = values.pop("device", "")
    if device not in ("",) + DEVICES:   # '': the study's --device, else the CPU
        problems.append(f"line {n}, column device: {device!r} is not a device; valid: {', '.join(DEVICES)}")
    elif device == "cuda" and model == "rigid-dem":
        problems.append(f"line {n}, column device: the rigid-dem model runs on YADE's engines, on the CPU only")
    resume = values.pop("resume", True)
    if resume not in (True, False):   # the driver takes bool(resume): 'no' would resume
        problems.append(f"line {n}, column resume: {resume!r} must be True or False")
    out_dir = values.pop("out_dir", "")
    if not isinstance(out_dir, str):
        problems.append(f"line {n}, column out_dir: {out_dir!r} must be a folder's name in quotes, e.g. 'runs'")
    for c, v in values.items():
        try:
            P.check_value(c, v)
        except ValueError as e:
            problems.append(f"line {n}, column {c}: {e}")
    if not problems:
        try:   # what only the whole line can tell (a drag constant without its law, ...)
            P.validate(dict(SCENES[scene_name]["params"], **values))
        except ValueError as e:
            problems.append(f"line {n}: {e}")
    return problems


def _head_line(path):
    return _head(path)[0]


def _head(path):
    """(line number, column names as written) of the table's first non-empty line."""
    with open(path, errors="replace") as f:
        for i, text in enumerate(f, 1):
            if _uncommented(text).strip():
                return i, _uncommented(text).split()
    return 1, []


def ridges_to_ship():
    """Every (scene, ridge) a study table in data/ names, and shipped_ridges.ALSO_SHIPPED:
    the ridges that ship as piles (run/shipped_ridges.py, tools/make_ridges.py)."""
    found = set(SR.ALSO_SHIPPED)
    for path in sorted(glob.glob(os.path.join(SR.ROOT, "data", "*.table"))):
        columns, rows = read_table(path)
        if "ridge" not in columns:
            continue   # a pile table (make_pile.py's seeds), not a study
        for _, row, _ in rows:
            # the YADE script's default scene is the demo's
            found.add((row.get("scene", "demo").strip("'\""), int(row["ridge"])))
    return sorted(found)
