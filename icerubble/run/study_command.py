"""`icerubble study`: a study is a yade-batch table of punch-through runs.

    icerubble study check TABLE     every line checked before any runs: exit 1 and
                                    'line N, column C: ...' for each problem
"""
import argparse
import sys

from .table_check import check_table


def main(argv=None):
    ap = argparse.ArgumentParser(prog="icerubble study", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="action", required=True)
    c = sub.add_parser("check", help="check a table as a whole")
    c.add_argument("table")
    a = ap.parse_args(argv)
    if a.action == "check":
        problems = check_table(a.table)
        for p in problems:
            print(f"{a.table}: {p}")
        if problems:
            sys.exit(1)
        print(f"{a.table}: every line can run")
