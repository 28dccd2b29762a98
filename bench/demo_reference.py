"""The demo's numbers, the ones the README quotes: `icerubble demo` run as a
user runs it (shipped ridge 1, 2 threads, 30 mm), its printed peak line and
record kept in bench/results/demo_reference.json. On every machine the demo
prints this line (tests/run/test_demo_everywhere.py; docs/reproducibility.md).

    /usr/bin/python3 bench/demo_reference.py        (~2-3 min)
"""
import datetime
import hashlib
import json
import os
import re
import subprocess
import sys
import tempfile

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
OUT = os.path.join(HERE, "results", "demo_reference.json")
PEAK_LINE = re.compile(r"F\^m = ([0-9.]+) kN/m at y_I = ([0-9.]+) mm")


def run_demo(out_dir):
    """(printed peak line, result path) of `icerubble demo --out-dir out_dir`."""
    r = subprocess.run([sys.executable, "-m", "icerubble.cli", "demo", "--out-dir", out_dir],
                       cwd=ROOT, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"icerubble demo failed (exit {r.returncode}):\n{r.stdout[-3000:]}{r.stderr[-3000:]}")
    line = PEAK_LINE.search(r.stdout)
    result = re.search(r"result \(HDF5.*?\): (\S+)", r.stdout)
    if line is None or result is None:
        raise RuntimeError(f"icerubble demo printed no peak line:\n{r.stdout[-3000:]}")
    return line.group(0), os.path.join(ROOT, result.group(1)) if not os.path.isabs(result.group(1)) \
        else result.group(1)


def main():
    with tempfile.TemporaryDirectory() as tmp:
        line, result = run_demo(os.path.join(tmp, "demo"))
        with h5py.File(result) as f:
            F = f["force/F"][:]
            ref = dict(peak_line=line, F_m_kN=float(PEAK_LINE.search(line).group(1)),
                       y_I_at_F_m_mm=float(PEAK_LINE.search(line).group(2)),
                       samples=int(len(F)), force_sha256=hashlib.sha256(np.ascontiguousarray(F).tobytes()).hexdigest(),
                       engine_build=str(f.attrs["engine_build"]), processor=str(f.attrs["processor"]),
                       pile=str(f["pile"].attrs["shipped"]), measured=datetime.date.today().isoformat())
    with open(OUT + ".part", "w") as f:
        json.dump(ref, f, indent=1)
        f.write("\n")
    os.replace(OUT + ".part", OUT)
    print(f"demo: {line} ({ref['samples']} samples, force record sha256 {ref['force_sha256'][:16]}...)")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
