"""Read one punch-through run result (docs/results_format.md) into a light object.

The writer is beside it (recorder.py); postproc.results re-exports this module
for scripts that import it from there.

The force record, mesh summary and bond-point table are read eagerly (they are
small); the snapshots (u_y fields) are read on demand, one at a time, because a
folder of runs would not fit in memory otherwise.
"""
import enum
import os
from dataclasses import dataclass, field

import h5py
import numpy as np

from .h5io import open_complete, read_checked
from .mesh_file import KIND_BLOCK, KIND_INDENTER, KIND_LAYER
from .recorder import RESULT_FORMAT

FORMAT_NAME = RESULT_FORMAT   # written by recorder.py
FORMAT_VERSION = 1
OPTIONAL_GROUPS = ("snapshots", "energy", "fields")
OPTIONAL_BOND_FIELDS = ("split_tn", "split_tt")   # older files lack them
REQUIRED_GROUPS = ("parameters", "pile", "mesh", "force", "bonds")

# Body kinds (docs/conventions.md), the mesh file's codes
BLOCK, LAYER, INDENTER = KIND_BLOCK, KIND_LAYER, KIND_INDENTER


class FailureMode(enum.IntEnum):
    """How a bond point failed, as /bonds/mode stores it (docs/results_format.md;
    the engine's _engine.FailureMode, kept equal by a test)."""
    none = 0
    tensile = 1
    shear = 2


class ResultFileError(ValueError):
    """A file that is not a complete, readable run result."""


def _text(value):
    if isinstance(value, bytes):
        return value.decode()
    if isinstance(value, np.ndarray) and value.shape == ():
        return _text(value[()])
    return value


def _attrs(obj):
    out = {}
    for key, value in obj.attrs.items():
        value = _text(value)
        if isinstance(value, np.generic):
            value = value.item()
        out[key] = value
    return out


@dataclass
class Snapshot:
    name: str
    t: float
    y_I: float  # m


@dataclass
class RunResult:
    """One run: root attributes, parameters, pile, force record, bonds, mesh summary.

    ``missing`` lists optional groups that are absent, and the bond tractions at
    the split when absent or NaN (OPTIONAL_BOND_FIELDS), with a sentence each.
    Snapshots are listed in ``snapshots`` and read with :meth:`u_elem`.
    """
    path: str
    attrs: dict
    parameters: dict
    pile: dict
    force_y: np.ndarray          # m, indenter travel (down positive)
    force_F: np.ndarray          # N/m
    bonds: dict                  # name -> array (docs/results_format.md /bonds)
    elem_area: np.ndarray        # m^2, initial triangle areas
    elem_centroid: np.ndarray    # m, initial centroids (M, 2)
    elem_kind: np.ndarray        # body kind per triangle
    snapshots: list = field(default_factory=list)
    missing: dict = field(default_factory=dict)

    # -- identity ---------------------------------------------------------
    @property
    def name(self):
        return os.path.basename(self.path)

    @property
    def ridge(self):
        return str(self.attrs.get("ridge", "?"))

    @property
    def model(self):
        return str(self.attrs.get("model", "?"))

    @property
    def force_direction(self):
        """Eq 11's form the run took: its parameter, else 'paper' (eq 11 as
        printed), which every run made before the parameter existed took."""
        return str(self.parameters.get("force_direction", "paper"))

    @property
    def scene(self):
        """The scene the run was made on: its attribute, else the ridge's prefix
        ('deep-1': deep), else '?'."""
        if "scene" in self.attrs:
            return str(self.attrs["scene"])
        return self.ridge.split("-")[0] if "-" in self.ridge else "?"

    @property
    def mu(self):
        return float(self.parameters["mu"])

    @property
    def tau_cr(self):
        return float(self.parameters["tau_cr"])

    @property
    def porosity(self):
        return float(self.pile["porosity"])

    @property
    def keel_depth(self):
        """h [m]: the parameter keel_depth, else keel_top_y - keel_bottom_y of /pile."""
        if "keel_depth" in self.parameters:
            return float(self.parameters["keel_depth"])
        return float(self.pile["keel_top_y"] - self.pile["keel_bottom_y"])

    @property
    def indenter_width(self):
        return float(self.parameters["indenter_width"])

    def param(self, key, default):
        return float(self.parameters.get(key, default))

    # -- snapshots --------------------------------------------------------
    def nearest_snapshot(self, y_I, tol=None):
        """The snapshot whose y_I is nearest to ``y_I`` [m]; None if none lies within
        ``tol`` (default: 0.5 mm or 5 % of y_I, whichever is larger)."""
        if not self.snapshots:
            return None
        if tol is None:
            tol = max(0.5e-3, 0.05 * y_I)
        ys = np.array([s.y_I for s in self.snapshots])
        i = int(np.argmin(np.abs(ys - y_I)))
        return self.snapshots[i] if abs(ys[i] - y_I) <= tol else None

    def mesh_polygons(self):
        """(M, 3, 2) initial corner positions of every triangle [m], for field plots."""
        with h5py.File(self.path, "r") as f:
            nodes = np.asarray(f["mesh/nodes"][...], dtype=float)
            tris = np.asarray(f["mesh/triangles"][...])
        return nodes[tris]

    def u_elem(self, snapshot):
        """(M, 2) displacement of each triangle centroid [m] in ``snapshot``."""
        with h5py.File(self.path, "r") as f:
            return np.asarray(f["snapshots"][snapshot.name]["u_elem"][...], dtype=float)


def load(path):
    """Load one run result.

    Refuses (ResultFileError) a file still named ``*.part``, a file whose root
    attribute ``complete`` is not 1, a wrong format, and a file lacking a required
    group. Missing optional groups (/snapshots, /energy, /fields) and bond
    tractions at the split are listed in ``RunResult.missing``.
    """
    path = os.fspath(path)
    try:
        f = open_complete(path, FORMAT_NAME, what="result file")
    except ValueError as exc:
        raise ResultFileError(str(exc)) from None
    with f:
        root = _attrs(f)
        if int(root.get("format_version", -1)) != FORMAT_VERSION:
            raise ResultFileError(f"{path}: format_version={root.get('format_version')!r}, "
                                  f"this reader knows version {FORMAT_VERSION}")
        absent = [g for g in REQUIRED_GROUPS if g not in f]
        if absent:
            raise ResultFileError(f"{path}: required group(s) missing: {', '.join('/' + g for g in absent)}")

        parameters = _attrs(f["parameters"])
        for key in ("mu", "tau_cr", "indenter_width"):
            if key not in parameters:
                raise ResultFileError(f"{path}: /parameters lacks attr {key!r}")
        pile = _attrs(f["pile"])
        if "porosity" not in pile:
            raise ResultFileError(f"{path}: /pile lacks attr 'porosity'")

        # each dataset checked before use: present, shaped, finite, in SI units
        # (a damaged file is named with its dataset, never a KeyError traceback)
        def read(name, shape, kind="f", units=None):
            try:
                return read_checked(f, name, shape=shape, kind=kind, units=units, what="result file")
            except ValueError as exc:
                raise ResultFileError(str(exc)) from None

        y = read("force/y_I", (None,), units="m")
        F = read("force/F", (len(y),), units="N/m")
        if y.size < 2:
            raise ResultFileError(f"{path}: /force/y_I and /force/F must hold >= 2 samples (found {y.size})")

        for key in ("position", "y_I_fail", "y_I_split", "mode"):
            if key not in f["bonds"] or not isinstance(f["bonds"][key], h5py.Dataset):
                raise ResultFileError(f"{path}: /bonds lacks dataset {key!r}")
        bonds = {k: np.asarray(v[...]) for k, v in f["bonds"].items() if isinstance(v, h5py.Dataset)}

        body_kind = read("mesh/body_kind", (None,), kind="i")
        body = read("mesh/body", (None,), kind="i")
        if body.size and (body.min() < 0 or body.max() >= len(body_kind)):
            raise ResultFileError(f"{path}: /mesh/body ids must lie in [0, {len(body_kind)})")
        area = read("mesh/area", (len(body),), units="m^2")
        centroid = read("mesh/centroid", (len(body), 2), units="m")
        if "snapshots" in f:   # their u_y figures draw the triangles: checked before any figure is made
            nodes = read("mesh/nodes", (None, 2), units="m")
            tris = read("mesh/triangles", (len(body), 3), kind="i")
            if tris.size and (tris.min() < 0 or tris.max() >= len(nodes)):
                raise ResultFileError(f"{path}: /mesh/triangles node ids must lie in [0, {len(nodes)})")

        missing = {}
        snapshots = []
        if "snapshots" in f:
            for name, g in sorted(f["snapshots"].items()):
                if "t" not in g.attrs or "y_I" not in g.attrs:
                    raise ResultFileError(f"{path}: /snapshots/{name} lacks its attribute t or y_I")
                snapshots.append(Snapshot(name, float(g.attrs["t"]), float(g.attrs["y_I"])))
            if not snapshots:
                missing["snapshots"] = "/snapshots is empty: no u_y fields (Figs. 16-20 need them)"
        else:
            missing["snapshots"] = "/snapshots absent: no u_y fields (Figs. 16-20 need them)"
        if any(k not in bonds for k in OPTIONAL_BOND_FIELDS):
            missing["split_traction"] = ("/bonds/split_tn, split_tt absent (written before they were recorded): "
                                         "no initiation-side count n_t_init/n_s_init")
        elif not np.isfinite(np.asarray(bonds["split_tn"], dtype=float)[
                np.isfinite(np.asarray(bonds["y_I_split"], dtype=float))]).all():
            missing["split_traction"] = ("/bonds/split_tn is NaN at split bond points (a rigid-DEM run keeps no "
                                         "traction at the split): no initiation-side count n_t_init/n_s_init")
        if "energy" not in f:
            missing["energy"] = "/energy absent: energy balance cannot be checked"
        if "fields" not in f:
            missing["fields"] = "/fields absent: no XDMF/VTU beside the file (ParaView only; not needed here)"

    snapshots.sort(key=lambda s: s.y_I)
    return RunResult(path=path, attrs=root, parameters=parameters, pile=pile,
                     force_y=y, force_F=F, bonds=bonds, elem_area=area,
                     elem_centroid=centroid, elem_kind=body_kind[body],
                     snapshots=snapshots, missing=missing)


def load_folder(folder):
    """(runs, skipped): every complete result under `folder` loaded, and one
    line per file not read and why (still being written, not a result, damaged)."""
    files, partial = find_results(folder)
    skipped = [f"{p}: still being written (*.part)" for p in partial]
    runs = []
    for path in files:
        try:
            runs.append(load(path))
        except ResultFileError as exc:
            skipped.append(str(exc))
    return runs, skipped


def find_results(folder):
    """Every ``*.h5`` under ``folder`` (recursively, as yade-batch nests them),
    sorted, and every ``*.h5.part`` (reported, never read)."""
    done, partial = [], []
    for dirpath, _, names in os.walk(folder):
        for n in names:
            if n.endswith(".h5"):
                done.append(os.path.join(dirpath, n))
            elif n.endswith(".h5.part"):
                partial.append(os.path.join(dirpath, n))
    return sorted(done), sorted(partial)
