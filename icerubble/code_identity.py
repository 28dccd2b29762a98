"""Which code computes: the rule for continuing a checkpoint.

A run continued from a checkpoint is one run only if the code that wrote the
checkpoint and the code that continues it compute alike. The git commit
(code_version below: "0.1.0+g1a2b3c4[.dirty]", recorded in every file
for people to read) cannot tell: ".dirty" hides which edits, a commit that
only touched the README changes it, and the compiled engine is a build
output git does not see (a worktree may hold one built from other sources).
So files record source_hash() beside it, a digest of what computes:

- the compiled modules this interpreter loads (icerubble._engine,
  icerubble._cohesive_law), byte for byte;
- every Python module of the package but those that only talk to people
  or schedulers (CONSOLE_ONLY), as its syntax tree without docstrings, so
  comments, docstrings and layout do not count but any statement does.

The rule (run/checkpoint.py, rigid_dem/checkpoint.py): a checkpoint is
continued only by code of the same source_hash; any other, or one that
records none, is refused before anything is loaded. A rest state that a new
run loads from (restore(..., from_rest=True)) is that run's starting state,
not a run it continues: it loads whatever code settled it, and the run names
that code (rest_state_code_version, rest_state_source_hash). Equal digests prove the
same computation (same machine code, same Python statements); a refusal may
be needless (a rebuild that differs in bytes alone), never the reverse.
"""
import ast
import functools
import hashlib
import importlib.util
import os
import subprocess

from . import __version__

PACKAGE = os.path.dirname(os.path.abspath(__file__))
EXTENSIONS = ("icerubble._engine", "icerubble._cohesive_law")
# Modules that print, parse command lines or talk to schedulers, and compute
# nothing a run records: a change to them keeps checkpoints valid.
CONSOLE_ONLY = ("cli.py", "run/progress.py", "study/command.py", "study/folder.py",
                "study/outcome.py", "study/progress.py", "study/slurm.py", "study/table_check.py",
                "geometry/mesh_command.py")


def python_digest(text):
    """sha256 of a module's syntax tree without docstrings (comments and
    layout are not in the tree)."""
    tree = ast.parse(text)
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if (isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef))
                and body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant)
                and isinstance(body[0].value.value, str)):
            node.body = body[1:] or [ast.Pass()]
    return hashlib.sha256(ast.dump(tree).encode()).hexdigest()


@functools.lru_cache(maxsize=None)
def source_hash():
    """The digest of the code that computes (see above), once per process."""
    h = hashlib.sha256()
    for name in EXTENSIONS:
        spec = importlib.util.find_spec(name)
        with open(spec.origin, "rb") as f:
            h.update(name.encode() + b"\0" + hashlib.sha256(f.read()).hexdigest().encode())
    for folder, dirs, files in sorted(os.walk(PACKAGE)):
        dirs.sort()
        for name in sorted(files):
            rel = os.path.relpath(os.path.join(folder, name), PACKAGE).replace(os.sep, "/")
            if name.endswith(".py") and rel not in CONSOLE_ONLY:
                with open(os.path.join(folder, name), encoding="utf-8") as f:
                    h.update(rel.encode() + b"\0" + python_digest(f.read()).encode())
    return h.hexdigest()[:16]


@functools.lru_cache(maxsize=None)
def code_version():
    """Package version plus the git commit of the checkout, if there is one,
    once per process (as source_hash; both taken as the engine is loaded):
    for people to read; whether two codes compute alike is source_hash's
    (above)."""
    here = os.path.dirname(os.path.abspath(__file__))
    try:
        rev = subprocess.run(["git", "-C", here, "rev-parse", "--short", "HEAD"],
                             capture_output=True, text=True, timeout=5).stdout.strip()
        dirty = subprocess.run(["git", "-C", here, "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, timeout=5).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        rev, dirty = "", ""
    if rev:
        return f"{__version__}+g{rev}" + (".dirty" if dirty else "")
    return __version__


def refuse_other_code(attrs, path, what="checkpoint"):
    """ValueError unless the file with root attributes `attrs` was written by
    code of this source_hash (the rule above), saying which code wrote it,
    which is running and what to do."""
    theirs = attrs.get("source_hash")
    theirs = theirs.decode() if isinstance(theirs, bytes) else theirs
    if theirs == source_hash():
        return
    made_by = attrs.get("code_version", "?")
    made_by = made_by.decode() if isinstance(made_by, bytes) else str(made_by)
    which = (f"code {made_by} (source {theirs})" if theirs else
             f"code {made_by}, before checkpoints recorded the source they were computed by")
    raise ValueError(f"{what} {path} was written by {which}; this is code {code_version()} (source "
                     f"{source_hash()}): a run continued by other code is not one run. Delete the checkpoint "
                     f"to start the run again, or resume it with the code that wrote it (the same commit and "
                     f"build: its source hash must match)")
