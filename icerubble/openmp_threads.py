"""The thread count a run asks for, kept whatever else runs in the process.

OpenMP's "how many threads" (omp_get_max_threads) is one setting of the whole
process that any library may change, and gmsh does: gmsh.initialize() sets it
to 1 (its General.NumThreads) and finalize() does not put it back. A run that
meshed its scene first (run/scene_cache.py) then computed on one thread, and
its shared rest state was keyed "1 thread", so the next line of the table
settled again instead of loading it. Two guards:

- default_threads(): what "0 = OpenMP's default" means, read from where
  OpenMP reads it at start (OMP_NUM_THREADS, which `yade -jN` sets, else the
  CPUs this process may run on), never from the live setting; the engine
  sets this count explicitly on each model (icerubble/engine/model.py);
- openmp_threads_kept(): around gmsh, the live setting is put back, for the
  OpenMP code that does read it (YADE's own loops in a rigid-dem run).
"""
import contextlib
import ctypes
import ctypes.util
import os


def default_threads():
    """The threads OpenMP gives a program at start: OMP_NUM_THREADS (its first
    level, as libgomp reads "4,2"), else the CPUs this process may run on."""
    text = os.environ.get("OMP_NUM_THREADS", "").split(",")[0].strip()
    if text.isdigit() and int(text) > 0:
        return int(text)
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:   # no affinity masks (not Linux)
        return os.cpu_count() or 1


def _libgomp():
    """The process's OpenMP runtime (the one the engine and gmsh link), or None."""
    name = ctypes.util.find_library("gomp") or "libgomp.so.1"
    try:
        return ctypes.CDLL(name)
    except OSError:
        return None


def openmp_max_threads():
    """OpenMP's live setting (omp_get_max_threads) of this thread, or None without OpenMP."""
    lib = _libgomp()
    return None if lib is None else int(lib.omp_get_max_threads())


@contextlib.contextmanager
def openmp_threads_kept():
    """Inside: anything may change OpenMP's thread count (gmsh sets it to 1);
    after: it is what it was before."""
    lib = _libgomp()
    before = None if lib is None else int(lib.omp_get_max_threads())
    try:
        yield
    finally:
        if before is not None:
            lib.omp_set_num_threads(before)
