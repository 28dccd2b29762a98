"""A benchmark's result file: its JSON written whole (a folder made where
needed; into a temporary file renamed over it, so a run stopped while
writing leaves the file before), and the path printed (bench/README.md is
made from these files)."""
import json
import os


def write(path, data):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    part = path + ".part"
    with open(part, "w") as f:
        json.dump(data, f, indent=1)
    os.replace(part, path)
    print(f"wrote {path}")
