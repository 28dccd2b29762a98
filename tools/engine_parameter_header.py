"""Write the engine's parameter ranges from the registry (issue 27, item 1).

    /usr/bin/python3 tools/engine_parameter_header.py OUT.hpp

The ranges of the parameters the engine reads are declared once, in
icerubble/parameters.py (REGISTRY). The build runs this script (CMake, before
compiling the engine) to write them as a C++ header, so the engine checks what
it is given against the registry's own bounds and prints the registry's own
range text: there is no second list to drift. parameters.py is loaded by its
path, not through the package, whose __init__ would import the engine that is
being built.
"""
import importlib.util
import math
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def registry():
    spec = importlib.util.spec_from_file_location("_registry", os.path.join(ROOT, "icerubble", "parameters.py"))
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module    # dataclasses looks its module up by name
    spec.loader.exec_module(module)
    return module


def c_string(s):
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def c_double(v, missing):
    if v is None:
        return missing
    return repr(float(v)) if math.isfinite(v) else ("INFINITY" if v > 0 else "-INFINITY")


def header(P):
    lines = ["// Generated from icerubble/parameters.py by tools/engine_parameter_header.py",
             "// at build time: do not edit (change the registry, then rebuild).",
             "#pragma once",
             "#include <cmath>",
             "",
             "#include \"common/parameter_range.hpp\"",
             "",
             "namespace engine::registry {",
             ""]
    for name, p in P.ENGINE.items():
        if p.kind in ("number", "whole"):
            lines.append(
                f"inline constexpr ParameterRange {name}{{{c_string(name)}, {c_string(p.unit)}, "
                f"{c_double(p.lo, '-INFINITY')}, {c_double(p.hi, 'INFINITY')}, "
                f"{str(p.lo is not None).lower()}, {str(p.hi is not None).lower()}, "
                f"{str(p.lo_open).lower()}, {str(p.hi_open).lower()}, {str(p.inf_ok).lower()}, "
                f"{str(p.kind == 'whole').lower()}, {c_string(p.range_text())}, {c_string(p.rule_text())}}};")
        elif p.kind == "choice":
            choices = ", ".join(c_string(c) for c in p.choices)
            lines.append(f"inline constexpr const char* {name}_choices[] = {{{choices}}};")
            lines.append(f"inline constexpr const char* {name}_range = {c_string(p.range_text())};")
    lines += ["", "}  // namespace engine::registry", ""]
    return "\n".join(lines)


def main(argv):
    if len(argv) != 1:
        sys.exit("usage: engine_parameter_header.py OUT.hpp")
    text = header(registry())
    out = argv[0]
    os.makedirs(os.path.dirname(os.path.abspath(out)), exist_ok=True)
    tmp = out + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, out)


if __name__ == "__main__":
    main(sys.argv[1:])
