"""Every file, module and test the docs and the code's comments name exists.

A renamed or deleted file leaves its old name behind in prose that no test
reads (issue 27, item 5); this reads it. It looks in the docs (README.md,
docs/*.md, bench/README.md and the other tracked Markdown) and in the comments
and docstrings of the source (Python, C++, shell, the Makefile): string
literals in code are left out, since there a name like a path is often an
HDF5 group of a checkpoint, not a file. Names looked for:
- paths under one of the repository's top folders (`docs/model.md`,
  `tests/run/test_study.py::test_x`, `engine/src/contact/`; a pattern such as
  `tests/engine/test_freeze_bonds_*.py` or `bench/results/<name>.json` must
  match at least one file), and in the C++ the include-style paths
  (`contact/contact.hpp`, `cohesive_law/softening.hpp`);
- dotted modules of the two packages (`icerubble.run.presets`,
  `postproc.make_figures`, with an optional `.name` defined in the module);
- a section of a page named by its words (`docs/model.md` §3 "A larger step
  while settling"): the words must be on that page.
Outputs a user or a run creates are not in the repository; the names below
are exempt, each with why. Runs in about a second.
"""
import ast
import glob
import io
import os
import re
import subprocess
import tokenize

import pytest

from tests.paths import ROOT

TOP = ("bench", "cohesive_law", "data", "docs", "engine", "icerubble", "postproc",
       "tests", "tools", "yade_scripts")

# Named but made by a user or a run, not shipped: (pattern, why).
NOT_SHIPPED = [
    (r"^yade_scripts/punch_through\.py\.", "the log yade-batch writes beside the script"),
    (r"^icerubble/_[a-z_*]+\.so$", "a compiled extension `make build` makes"),
    (r"^docs/figures/study_paper_depth", "the figures the commands of docs/study_paper_depth.md write"),
    (r"^bench/results/deep_vs_paper\.json$", "bench/deep_vs_paper.py writes it; not yet run"),
    (r"^bench/results/stamps\.json$", "the first stamp writes it (make bench, bench/stamps.py)"),
    (r"^bench/results/paper_peak_cuda\.json$", "bench/paper_peak.py --device cuda writes it on a GPU machine"),
]

DOCS = re.compile(r"\.md$")
CODE = re.compile(r"\.(py|hpp|cpp|h|sh)$|^Makefile$|^CMakeLists\.txt$")
PATH = re.compile(r"(?<![\w./-])((?:%s)/[\w./<>{}*-]*[\w/>}*])" % "|".join(TOP))
MODULE = re.compile(r"(?<![\w./-])((?:icerubble|postproc)(?:\.[A-Za-z_]\w*)+)")
INCLUDE_STYLE = re.compile(r"(?<![\w./-])((?:[a-z_]+/)+[a-z_0-9]+\.(?:hpp|cpp|h))\b")
# where the C++ include-style paths are relative to
INCLUDE_ROOTS = ("engine/src", "cohesive_law/include", "cohesive_law/src", "cohesive_law")
TEMPLATE = re.compile(r"<[^>]*>|\{[^}]*\}")


def tracked(pattern):
    out = subprocess.run(["git", "-C", ROOT, "ls-files"], capture_output=True, text=True,
                         check=True).stdout.split()
    return [p for p in out if pattern.search(os.path.basename(p)) and not p.startswith("tests/data/")
            and os.path.isfile(os.path.join(ROOT, p))]


def python_prose(text):
    """The comments and docstrings of a Python file."""
    parts = [tok.string for tok in tokenize.generate_tokens(io.StringIO(text).readline)
             if tok.type == tokenize.COMMENT]
    for node in ast.walk(ast.parse(text)):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            parts.append(ast.get_docstring(node, clean=False) or "")
    return "\n".join(parts)


def cpp_prose(text):
    """The comments of a C++ file, and what it includes."""
    return "\n".join(re.findall(r"//[^\n]*|/\*.*?\*/|#include\s+\"[^\"]+\"", text, re.S))


def hash_prose(text):
    """The comments of a shell script, Makefile or CMake file."""
    return "\n".join(re.findall(r"#[^\n]*", text))


def prose(rel):
    with open(os.path.join(ROOT, rel), errors="replace") as f:
        text = f.read()
    if rel.endswith(".md"):
        return text
    if rel.endswith(".py"):
        return python_prose(text)
    if rel.endswith((".hpp", ".cpp", ".h")):
        return cpp_prose(text)
    return hash_prose(text)


def exempt(path):
    return any(re.search(pattern, path) for pattern, _ in NOT_SHIPPED)


def path_exists(path, roots=("",)):
    path = path.split("::")[0].rstrip("/.")
    if exempt(path):
        return True
    # a pattern (`*`, `<name>`, `{name}`, `.hpp/.cpp`) must match at least one file
    pattern = TEMPLATE.sub("*", path.replace(".hpp/.cpp", ".*"))
    return any(glob.glob(os.path.join(ROOT, root, pattern)) for root in roots)


def module_file(dotted):
    """The source of module `dotted` if it is one (package, .py or compiled)."""
    base = os.path.join(ROOT, *dotted.split("."))
    for candidate in (os.path.join(base, "__init__.py"), base + ".py"):
        if os.path.isfile(candidate):
            return candidate
    if glob.glob(base + ".*.so") or glob.glob(base + ".so"):
        return base + ".so"
    return None


def defines(source, name):
    if source.endswith(".so") or name.startswith("__"):
        return True  # a compiled module's names: the bindings' tests check them
    with open(source) as f:
        text = f.read()
    return re.search(r"(^|\n)\s*(def|class)\s+%s\b|(^|\n)%s\s*[:=]|import[^\n]*\b%s\b"
                     % (name, name, name), text) is not None


def module_exists(dotted):
    parts = dotted.split(".")
    for n in range(len(parts), 0, -1):
        source = module_file(".".join(parts[:n]))
        if source:
            return n == len(parts) or defines(source, parts[n])
    return False


def stale_names():
    stale = []
    for rel in tracked(DOCS) + tracked(CODE):
        text = prose(rel)
        for m in PATH.finditer(text):
            if not path_exists(m.group(1), ("", "cohesive_law/include")):
                stale.append((rel, m.group(1)))
        for m in MODULE.finditer(text):
            name = m.group(1)
            if re.search(r"\.(py|md|h5|hpp|cpp|table|so)$", name):
                continue  # a file's name (icerubble.h5), not a module
            if not module_exists(name):
                stale.append((rel, name))
        if rel.endswith((".hpp", ".cpp", ".h")):
            for m in INCLUDE_STYLE.finditer(text):
                name = m.group(1)
                if not path_exists(name, (os.path.dirname(rel),) + INCLUDE_ROOTS + ("",)):
                    stale.append((rel, name))
    return sorted(set(stale))


SECTION = re.compile(r'((?:docs/[\w.-]+\.md|bench/README\.md|README(?:\.md)?))`?\)?(?:\s*§[\d.]+)?,?\s+'
                     r'["\u201c]([^"\u201d\n]{4,80})["\u201d]')


def words(text):
    return " ".join(text.lower().split())


def stale_sections():
    stale = []
    for rel in tracked(DOCS) + tracked(CODE):
        for m in SECTION.finditer(prose(rel)):
            page = "README.md" if m.group(1).startswith("README") else m.group(1)
            path = os.path.join(ROOT, page)
            if os.path.exists(path):
                with open(path) as f:
                    if words(m.group(2)) not in words(f.read()):
                        stale.append((rel, f'{page} "{m.group(2)}"'))
    return stale


def test_every_named_section_is_on_its_page():
    stale = stale_sections()
    assert not stale, "sections named but not on their page:\n" + "\n".join(f"  {f}: {n}" for f, n in stale)


def test_every_named_file_module_and_test_exists():
    stale = stale_names()
    assert not stale, "named but missing:\n" + "\n".join(f"  {f}: {n}" for f, n in stale)


@pytest.mark.parametrize("pattern,why", NOT_SHIPPED)
def test_each_exemption_says_why(pattern, why):
    assert why and re.compile(pattern)
