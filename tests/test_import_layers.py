"""Imports run one way: each part of the code imports only the parts below it.

    base modules (parameters, code_identity, polygon, cohesive_law, ...)
      <- engine <- files <- geometry <- run <- rigid_dem <- study <- cli <- postproc

A part is a subpackage of icerubble (engine, files, geometry, run, rigid_dem,
study), one of its top-level modules (cli, parameters, ...) or postproc as a
whole. Every import statement counts, those inside functions too (an import
on use is still a dependency). The `icerubble` command names postproc's
commands by string (cli.COMMANDS) and imports them on use: that is no import
statement, and the reason postproc may sit above cli.

Reads the source only (ast); nothing is imported.
"""
import ast
import os

from tests.paths import ROOT

BASE = ("icerubble", "icerubble._engine", "icerubble._cohesive_law", "icerubble.parameters",
        "icerubble.exit_status", "icerubble.openmp_threads", "icerubble.code_identity",
        "icerubble.machine", "icerubble.polygon", "icerubble.plain_products", "icerubble.cohesive_law")
# bottom to top; a part imports parts of lower layers (base modules: each other, without cycles)
LAYERS = [BASE, ("icerubble.engine",), ("icerubble.files",), ("icerubble.geometry",), ("icerubble.run",),
          ("icerubble.rigid_dem",), ("icerubble.study",), ("icerubble.cli",), ("postproc",)]
LAYER = {part: i for i, parts in enumerate(LAYERS) for part in parts}
PACKAGES = ("icerubble", "postproc")


def part_of(module):
    """The part a dotted module name belongs to, None outside the project."""
    names = module.split(".")
    if names[0] == "postproc":
        return "postproc"
    if names[0] != "icerubble":
        return None
    if len(names) == 1:
        return "icerubble"
    part = "icerubble." + names[1]
    here = os.path.join(ROOT, "icerubble", names[1])
    # `from icerubble import __version__`: a name of the package's __init__
    return part if part in LAYER or os.path.isdir(here) or os.path.exists(here + ".py") else "icerubble"


def modules():
    """(dotted name, path, is a package's __init__) of every module of the packages."""
    for package in PACKAGES:
        for folder, dirs, files in os.walk(os.path.join(ROOT, package)):
            dirs[:] = sorted(d for d in dirs if d != "__pycache__")
            for name in sorted(files):
                if name.endswith(".py"):
                    path = os.path.join(folder, name)
                    dotted = os.path.relpath(path, ROOT)[:-3].replace(os.sep, ".")
                    init = name == "__init__.py"
                    yield (dotted[: -len(".__init__")] if init else dotted), path, init


def imported(module, tree, init):
    """(line, dotted name) of everything `module` imports; `from P import n` gives
    P.n (a submodule, or a name of P: part_of tells the part either way)."""
    package = module if init else module.rpartition(".")[0]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield node.lineno, alias.name
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                base = ".".join(up + ([node.module] if node.module else []))
            for alias in node.names:
                yield node.lineno, f"{base}.{alias.name}"


def part_imports():
    """{(importer part, imported part): ['path:line imports name', ...]} over the packages."""
    edges = {}
    for module, path, init in modules():
        with open(path, encoding="utf-8") as f:
            tree = ast.parse(f.read(), path)
        for line, name in imported(module, tree, init):
            src, dst = part_of(module), part_of(name)
            if dst is not None and dst != src:
                edges.setdefault((src, dst), []).append(f"{os.path.relpath(path, ROOT)}:{line} imports {name}")
    return edges


def test_every_part_has_a_layer():
    parts = {part_of(module) for module, _, _ in modules()}
    missing = sorted(parts - set(LAYER))
    assert not missing, f"{missing}: give each a layer in LAYERS (tests/test_import_layers.py)"


def test_imports_run_down_the_layers():
    upward = [f"{where} ({dst} is not below {src})"
              for (src, dst), wheres in sorted(part_imports().items())
              for where in wheres
              if LAYER[dst] > LAYER[src] or (LAYER[dst] == LAYER[src] and src not in BASE)]
    assert not upward, "imports against the layer order:\n" + "\n".join(upward)


def test_no_cycle_between_parts():
    edges = part_imports()
    graph = {}
    for src, dst in edges:
        graph.setdefault(src, set()).add(dst)
    state, stack = {}, []

    def visit(part):   # depth first; a part met again while on the stack closes a cycle
        state[part] = "open"
        stack.append(part)
        for nxt in sorted(graph.get(part, ())):
            if state.get(nxt) == "open":
                cycle = stack[stack.index(nxt):] + [nxt]
                hops = [f"{a} -> {b}: {edges[(a, b)][0]}" for a, b in zip(cycle, cycle[1:])]
                raise AssertionError("import cycle " + " -> ".join(cycle) + ":\n" + "\n".join(hops))
            if nxt not in state:
                visit(nxt)
        stack.pop()
        state[part] = "done"

    for part in sorted(graph):
        if part not in state:
            visit(part)
