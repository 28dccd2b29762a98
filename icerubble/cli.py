"""`icerubble COMMAND ...`: the project's commands in one place.

`icerubble --help` lists the commands (from COMMANDS below, so the list cannot
drift from what runs) and the actions of `icerubble study`; each command's
--help tells its options. The runs themselves are YADE scripts
(yade_scripts/, yade-batch tables).

Exit status, the same for every command (icerubble/exit_status.py):
0 success; 2 bad input or usage, refused before any work (as argparse);
1 a run or a line that failed while working; 75 interrupted after writing
a checkpoint (started again, it resumes).

A command refuses bad input by raising ValueError; an operating-system error
(a folder that cannot be written, a full disk) is reported here too: one
line naming the file, never a traceback.
"""
import importlib
import sys

from . import exit_status

# command -> (module whose main(argv) it runs, what it does); modules are
# imported on use, so a command does not pay for (or need) another's dependencies;
# postproc's commands are named here, never imported by icerubble's modules
# (tests/test_import_layers.py)
COMMANDS = {
    "demo": ("postproc.demo", "pile -> mesh -> punch-through -> figures on a small scene (make demo)"),
    "mesh": ("icerubble.geometry.mesh_command", "mesh a settled pile with gmsh"),
    "study": ("icerubble.study.command", "a yade-batch table of runs:"),
    "figures": ("postproc.make_figures", "every figure and table of the paper from a folder of runs"),
    "run-figures": ("postproc.run_figures", "F-y_I record and u_y field of one run"),
    "summary": ("postproc.summary", "one line per run: peaks, alpha, n_t/n_s"),
    "compare": ("postproc.paper_comparison", "the study beside the paper's numbers"),
    "measured": ("postproc.measured", "peaks and strengths of a measured test record"),
}


def usage():
    """The text of `icerubble --help`."""
    from .study.command import ACTIONS   # light: argparse and the study's files
    width = max(map(len, COMMANDS)) + 2
    lines = ["usage: icerubble COMMAND [ARGS ...]   (icerubble COMMAND --help: its options)",
             "       icerubble --version", "", "commands:"]
    for name, (_, what) in COMMANDS.items():
        lines.append(f"  {name:<{width}}{what}")
        if name == "study":
            lines += [f"    {action:<{width - 2}}{what}" for action, what in ACTIONS.items()]
    doc = __doc__.split("Exit status", 1)[1].split("\n\n")[0]
    return "\n".join(lines) + "\n\nexit status" + doc + "\n"


def version():
    from .code_identity import code_version
    return f"icerubble {code_version()}"


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    if not argv or argv[0] in ("-h", "--help"):
        print(usage(), end="", file=sys.stdout if argv else sys.stderr)
        return exit_status.OK if argv else exit_status.USAGE
    if argv[0] == "--version":
        print(version())
        return exit_status.OK
    name, rest = argv[0], argv[1:]
    if name not in COMMANDS:
        print(f"icerubble: unknown command {name!r}; commands: {', '.join(COMMANDS)} "
              "(icerubble --help)", file=sys.stderr)
        return exit_status.USAGE
    return run(name, rest)


def run(name, argv):
    """Command `name` with its arguments, its errors reported in one line:
    the exit status. The commands' `python3 -m MODULE` entry points come here too."""
    module = importlib.import_module(COMMANDS[name][0])
    try:
        status = module.main(argv)
    except ValueError as e:   # bad input, refused before any work
        print(f"icerubble {name}: error: {e}", file=sys.stderr)
        return exit_status.USAGE
    except OSError as e:   # met while working: a full disk, a folder that went away
        print(f"icerubble {name}: error: {os_error_text(e)}", file=sys.stderr)
        return exit_status.FAILED
    # a command that reports its own error returns its exit status (an int);
    # anything else it returns (run-figures: the figures it made) means success
    return status if isinstance(status, int) and not isinstance(status, bool) else exit_status.OK


def os_error_text(e):
    """'<what>: <path>' of an OSError (h5py's carry no strerror: their text)."""
    what = e.strerror or str(e)
    paths = [p for p in (e.filename, getattr(e, "filename2", None)) if p is not None]
    return what + "".join(f": {p}" for p in paths)


if __name__ == "__main__":
    sys.exit(main())
