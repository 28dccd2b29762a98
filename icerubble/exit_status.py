"""The exit status of every icerubble command, one convention (cli.py's
`icerubble --help` and the README tell it):

    0   success
    1   a run, or a line of a study, failed while working (an instability, an
        operating-system error such as a full disk met after work began)
    2   bad input or usage, refused before any work (argparse's own status)
    75  interrupted after writing a checkpoint: started again it resumes
        (EX_TEMPFAIL of sysexits.h: the SIGTERM of a scheduler's time limit)
"""
OK = 0
FAILED = 1
USAGE = 2
INTERRUPTED = 75
