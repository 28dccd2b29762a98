"""The pile file: phase 1's settled blocks (layout: docs/pile_and_mesh.md).

Written from inside YADE (yade_scripts/make_pile.py) and read by the mesher.
The reader checks every dataset before any work: a pile in millimetres or
without its corners is refused with the file and dataset named, never read
as metres.
"""
import numpy as np

from ..polygon import ccw
from .h5io import AtomicH5, open_complete, read_checked, write_dataset

PILE_FORMAT = "icerubble-pile"
PILE_FORMAT_VERSION = 1


def write_pile(path, corners, thickness, length, params, meta):
    """Write a settled pile to `path` (atomically: docs/results_format.md)."""
    corners = np.array([ccw(c) for c in corners], dtype=float)
    with AtomicH5(path, PILE_FORMAT, PILE_FORMAT_VERSION) as f:
        for k, v in meta.items():
            f.attrs[k] = v
        pg = f.create_group("parameters")
        for k, v in params.items():
            pg.attrs[k] = v
        b = f.create_group("blocks")
        write_dataset(b, "corners", corners, "m")
        write_dataset(b, "thickness", np.asarray(thickness, float), "m")
        write_dataset(b, "length", np.asarray(length, float), "m")


def read_pile(path):
    """Read a pile file; ValueError naming the file and dataset if it is not
    a complete icerubble pile of finite (n, 4, 2) corners in metres."""
    with open_complete(path, PILE_FORMAT, what="pile file") as f:
        def get(name, shape):
            return read_checked(f, name, shape=shape, units="m", what="pile file")
        corners = get("blocks/corners", (None, 4, 2))
        n = len(corners)
        if n == 0:
            raise ValueError(f"pile file {path!r}, dataset 'blocks/corners': no blocks")
        if "parameters" not in f:
            raise ValueError(f"pile file {path!r}: group 'parameters' missing")
        return dict(corners=corners,
                    thickness=get("blocks/thickness", (n,)),
                    length=get("blocks/length", (n,)),
                    params=dict(f["parameters"].attrs),
                    meta=dict(f.attrs))
