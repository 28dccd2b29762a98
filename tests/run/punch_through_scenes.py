"""A tiny constructed punch-through scene (no YADE): two rows of touching
rectangular blocks under the consolidated layer, meshed by icerubble.geometry.meshing."""
import numpy as np

from icerubble.files import pile_file
from icerubble.geometry import meshing, pile

WIDTH = 8.0          # m, domain
BLOCK = (1.0, 0.3)   # m, length x thickness
ROWS = 2


def brick_pile(path, width=WIDTH, rows=ROWS):
    """Rows of blocks in a running bond pattern, touching exactly: every
    interface is a freeze bond."""
    yb = pile.layer_bottom_y()
    L, t = BLOCK
    corners, ts, ls = [], [], []
    for r in range(rows):
        y1 = yb - t * r
        off = 0.5 * L * (r % 2)
        for x in np.arange(-width / 2 - off, width / 2, L):
            a, b = max(x, -width / 2), min(x + L, width / 2)
            if b - a < 0.2:
                continue
            corners.append([(a, y1 - t), (b, y1 - t), (b, y1), (a, y1)])
            ts.append(t)
            ls.append(b - a)
    meta = dict(domain_width=width, layer_thickness=1.0, layer_bottom_y=yb, seed=0,
                n_blocks=len(corners), porosity=0.0, settled=1, yade_version="none")
    pile_file.write_pile(str(path), corners, ts, ls, {}, meta)
    return len(corners)


def brick_mesh(tmp_dir, element_size=0.2):
    pile_path, mesh_path = tmp_dir / "brick_pile.h5", tmp_dir / "brick_mesh.h5"
    brick_pile(pile_path)
    meshing.mesh_pile_file(str(pile_path), str(mesh_path), element_size=element_size)
    return mesh_path
