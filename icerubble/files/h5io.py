"""Atomic, self-describing HDF5 files (docs/results_format.md).

A file is written as NAME.part and renamed to NAME only once it is complete,
and the root attribute ``complete`` is set to 1 as the last write. So a file
carrying the final name is complete even if the machine died while writing
(rename is atomic on one filesystem), and a reader can refuse anything else.
"""
import datetime
import os
import socket

import h5py
import numpy as np

from ..code_identity import code_version, source_hash


def write_dataset(group, name, data, units, **attrs):
    ds = group.create_dataset(name, data=np.asarray(data))
    ds.attrs["units"] = units
    for k, v in attrs.items():
        ds.attrs[k] = v
    return ds


def set_attrs(obj, mapping):
    for k, v in mapping.items():
        obj.attrs[k] = v if v is not None else "none"


class AtomicH5:
    """Context manager: ``with AtomicH5(path, fmt) as f:`` writes path.part,
    then sets root ``complete = 1`` and renames to path on a clean exit. On an
    exception the .part file stays (for inspection) and path is not touched.
    writer_part: the .part file named by host and process too, for a file
    that several processes may write at once (the last rename wins).
    """

    def __init__(self, path, fmt, format_version=1, writer_part=False):
        self.path = os.fspath(path)
        self.part = self.path + (f".{socket.gethostname()}.{os.getpid()}.part" if writer_part else ".part")
        self.fmt = fmt
        self.format_version = format_version
        self.file = None

    def __enter__(self):
        d = os.path.dirname(os.path.abspath(self.path))
        os.makedirs(d, exist_ok=True)
        self.file = h5py.File(self.part, "w")
        a = self.file.attrs
        a["format"] = self.fmt
        a["format_version"] = self.format_version
        a["code_version"] = code_version()
        a["source_hash"] = source_hash()   # what a checkpoint must match to be continued
        a["created"] = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
        a["complete"] = 0
        return self.file

    def __exit__(self, exc_type, exc, tb):
        if exc_type is None:
            self.file.attrs["complete"] = 1
            self.file.flush()
        self.file.close()
        if exc_type is None:
            os.replace(self.part, self.path)
        return False


def open_complete(path, fmt=None, what="file"):
    """Open an HDF5 file for reading, refusing missing, partial or foreign
    files with a ValueError that starts with `what` (e.g. "mesh file")."""
    path = os.fspath(path)
    if path.endswith(".part"):
        raise ValueError(f"{what} {path!r} is partially written (.part): what wrote it did not finish")
    if os.path.isdir(path):
        raise ValueError(f"{what} {path!r} is a folder, not a file")
    if not os.path.isfile(path):
        raise ValueError(f"{what} {path!r} does not exist")
    try:
        f = h5py.File(path, "r")
    except OSError as e:
        raise ValueError(f"{what} {path!r} is not an HDF5 file ({e})") from None
    if fmt is not None and f.attrs.get("format") != fmt:
        found = f.attrs.get("format")
        f.close()
        raise ValueError(f"{what} {path!r} has format {found!r}, expected {fmt!r}")
    if int(f.attrs.get("complete", 0)) != 1:
        f.close()
        raise ValueError(f"{what} {path!r} is incomplete (root attribute complete != 1)")
    return f


def read_checked(f, name, *, shape, kind="f", units=None, what="file"):
    """Dataset `name` of open file `f` as an array, checked before any work:
    present, of `shape` (None matches any length), of dtype kind `kind` ("f"
    float, "i" integer; integers pass for floats), finite, and in `units`
    when given (a file in other units is refused, never rescaled). Raises
    ValueError naming the file, the dataset and what was expected."""
    where = f"{what} {f.filename!r}, dataset {name!r}"
    if name not in f or not isinstance(f[name], h5py.Dataset):
        raise ValueError(f"{where}: missing (expected {_shape_text(shape)} {_KIND_TEXT[kind]})")
    d = f[name]
    if len(d.shape) != len(shape) or any(n is not None and n != m for n, m in zip(shape, d.shape)):
        raise ValueError(f"{where}: shape {d.shape}, expected {_shape_text(shape)}")
    if d.dtype.kind not in ({"f", "i", "u"} if kind == "f" else {"i", "u"}):
        raise ValueError(f"{where}: dtype {d.dtype}, expected {_KIND_TEXT[kind]}")
    if units is not None:
        got = d.attrs.get("units", None)
        got = got.decode() if isinstance(got, bytes) else got
        if got != units:
            raise ValueError(f"{where}: units {got!r}, expected {units!r}")
    a = d[...]
    if kind == "f" and not np.isfinite(a).all():
        raise ValueError(f"{where}: {int(np.size(a) - np.isfinite(a).sum())} non-finite values")
    return a


_KIND_TEXT = {"f": "numbers", "i": "integers"}


def _shape_text(shape):
    return "(" + ", ".join("n" if n is None else str(n) for n in shape) + ("," if len(shape) == 1 else "") + ")"


def write_tree(group, tree):
    """A nested dict of arrays, numbers and strings into an HDF5 group
    (arrays -> datasets, scalars -> attributes, dicts -> subgroups)."""
    for k, v in tree.items():
        if isinstance(v, dict):
            write_tree(group.create_group(k), v)
        elif isinstance(v, np.ndarray) or isinstance(v, (list, tuple)):
            group.create_dataset(k, data=np.asarray(v))
        else:
            group.attrs[k] = "__none__" if v is None else v


def read_tree(group):
    """Inverse of write_tree."""
    out = {}
    for k, v in group.attrs.items():
        if isinstance(v, bytes):
            v = v.decode()
        if isinstance(v, str) and v == "__none__":
            v = None
        elif isinstance(v, np.generic):
            v = v.item()
        out[k] = v
    for k, v in group.items():
        out[k] = read_tree(v) if isinstance(v, h5py.Group) else v[...]
    return out
