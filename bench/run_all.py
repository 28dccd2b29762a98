"""`make bench`: run every benchmark bench/*.py (each prints its figures and
writes bench/results/<name>.json). Extra arguments (e.g. --quick) are passed on."""
import glob
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
# Benchmarks of many hours, run alone (each says how in its docstring).
LONG = {"paper_peak.py": "the paper scene's cohesive peak under each preset: ~0.7-1 h for `fast` "
                         "and `balanced`, ~5 h for `paper`, after a ~0.5 h settle"}


def main():
    scripts = sorted(p for p in glob.glob(os.path.join(HERE, "*.py"))
                     if os.path.basename(p) not in LONG and os.path.basename(p) != os.path.basename(__file__))
    for name, what in LONG.items():
        print(f"=== {name}: not run by make bench ({what}); /usr/bin/python3 bench/{name}", flush=True)
    failed = []
    for path in scripts:
        name = os.path.basename(path)
        print(f"=== {name}", flush=True)
        start = time.time()
        rc = subprocess.call([sys.executable, path] + sys.argv[1:])
        print(f"=== {name}: {'ok' if rc == 0 else f'FAILED (exit {rc})'} in {time.time() - start:.0f} s\n",
              flush=True)
        if rc:
            failed.append(name)
    if failed:
        sys.exit(f"benchmarks failed: {', '.join(failed)}")


if __name__ == "__main__":
    main()
