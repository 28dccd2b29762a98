"""Which code and which machine measured each bench/results/*.json.

A measured figure means little without the code that computed it and the
processor it ran on, and a result's own fields rarely say both. `make bench`
(bench/run_all.py) stamps every result a benchmark rewrote; a benchmark run
alone is stamped by hand right after it:

    /usr/bin/python3 bench/stamps.py paper_peak.json [...]

The stamps live beside the results, in bench/results/stamps.json;
bench/make_readme.py prints them in bench/README.md.
"""
import datetime
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
RESULTS = os.path.join(HERE, "results")
STAMPS = os.path.join(RESULTS, "stamps.json")


def read():
    if not os.path.exists(STAMPS):
        return {}
    with open(STAMPS) as f:
        return json.load(f)


def stamp(names):
    """Record this checkout's code version and this machine for results `names`."""
    from icerubble.files.h5io import code_version
    from icerubble.machine import processor
    stamps = read()
    today = datetime.date.today().isoformat()
    for name in names:
        if not os.path.exists(os.path.join(RESULTS, name)):
            raise SystemExit(f"bench/results/{name} does not exist: nothing to stamp")
        stamps[name] = dict(code_version=code_version(), processor=processor(), measured=today)
    with open(STAMPS, "w") as f:
        json.dump(stamps, f, indent=1, sort_keys=True)


if __name__ == "__main__":
    stamp(sys.argv[1:])
