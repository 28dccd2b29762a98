"""`icerubble COMMAND ...`: the project's commands in one place.

    icerubble demo [--ridge N]          pile -> mesh -> punch-through -> figures (make demo)
    icerubble mesh PILE MESH [...]      mesh a settled pile with gmsh
    icerubble study check TABLE         a yade-batch table checked line by line before it runs
    icerubble study run TABLE           the table run here (yade-batch), then each line's outcome
    icerubble figures RESULTS [-o DIR]  every figure and table of the paper from a folder of runs
    icerubble run-figures RESULT        F-y_I record and u_y field of one run
    icerubble summary RESULTS           one line per run: peaks, alpha, n_t/n_s
    icerubble compare RESULTS           the study beside the paper's numbers
    icerubble measured RECORD           peaks and strengths of a measured test record

The runs themselves are YADE scripts (yade_scripts/, yade-batch tables). Each
command's --help tells its options.
"""
import importlib
import sys

# command -> module whose main(argv) it runs; imported on use, so a command
# does not pay for (or need) another's dependencies
COMMANDS = {
    "demo": "icerubble.run.demo",
    "mesh": "icerubble.geometry.mesh_command",
    "study": "icerubble.run.study_command",
    "figures": "postproc.make_figures",
    "run-figures": "postproc.run_figures",
    "summary": "postproc.summary",
    "compare": "postproc.paper_comparison",
    "measured": "postproc.measured",
}


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    if not argv or argv[0] in ("-h", "--help"):
        print(__doc__)
        return 0 if argv else 2
    name, rest = argv[0], argv[1:]
    if name not in COMMANDS:
        print(f"icerubble: unknown command {name!r}; commands: {', '.join(COMMANDS)}", file=sys.stderr)
        return 2
    module = importlib.import_module(COMMANDS[name])
    try:
        status = module.main(rest)
    except ValueError as e:   # bad input: one line naming it, not a traceback
        print(f"icerubble {name}: error: {e}", file=sys.stderr)
        return 2
    # a command that reports its own error returns its exit status (an int);
    # anything else it returns (run-figures: the figures it made) means success
    return status if isinstance(status, int) and not isinstance(status, bool) else 0


if __name__ == "__main__":
    sys.exit(main())
