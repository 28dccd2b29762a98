"""A benchmark's result file: its JSON written whole (a folder made where
needed), and the path printed (bench/README.md is made from these files)."""
import json
import os


def write(path, data):
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    with open(path, "w") as f:
        json.dump(data, f, indent=1)
    print(f"wrote {path}")
