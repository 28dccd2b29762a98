"""Where a command will write, checked before it does any work: a mistake in
an output path (a file where a folder is wanted, a folder where a file is, a
folder that cannot be written) is named at once as bad input, not found as an
operating-system error after an hour of work or after half the outputs.

A missing folder is not a mistake: the writers make it (os.makedirs).
A text output is written whole or not at all (whole_file), as the HDF5
files are (h5io.AtomicH5): a full disk leaves no file that looks complete.
"""
import contextlib
import os


def check_output_file(path, what="output file"):
    """Refuse (ValueError) a `path` a file cannot be written to."""
    path = os.fspath(path)
    if os.path.isdir(path):
        raise ValueError(f"{what} {path!r} is a folder, not a file: name a file in it")
    _check_parents(os.path.dirname(os.path.abspath(path)), what, path)
    return path


def check_output_folder(path, what="output folder"):
    """Refuse (ValueError) a `path` that is not, and cannot become, a writable folder."""
    path = os.fspath(path)
    if os.path.exists(path) and not os.path.isdir(path):
        raise ValueError(f"{what} {path!r} is a file, not a folder: name a folder")
    _check_parents(os.path.abspath(path), what, path)
    return path


def _check_parents(folder, what, path):
    """The nearest existing folder on the way to `folder` must be a writable folder."""
    existing = folder
    while not os.path.exists(existing):
        existing = os.path.dirname(existing)
    if not os.path.isdir(existing):
        raise ValueError(f"{what} {path!r}: {existing!r} is a file, not a folder")
    if not os.access(existing, os.W_OK | os.X_OK):
        raise ValueError(f"{what} {path!r}: folder {existing!r} cannot be written (permission denied)")


@contextlib.contextmanager
def whole_file(path, mode="w", **open_kw):
    """open() for writing `path` as PATH.part, renamed to PATH once written
    whole; on any error the part is removed and an OSError names `path`. A
    path that exists and is not a regular file (/dev/stdout, /dev/full) is
    written in place: renaming over it would replace the device."""
    path = os.fspath(path)
    regular = not os.path.exists(path) or os.path.isfile(path)
    target = path + ".part" if regular else path
    if regular:
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    try:
        with open(target, mode, **open_kw) as f:
            yield f
        if regular:
            os.replace(target, path)
    except BaseException as e:
        if regular:
            with contextlib.suppress(OSError):
                os.remove(target)
        if isinstance(e, OSError) and e.filename is None:   # a failed write names no file
            e.filename = path
        raise
