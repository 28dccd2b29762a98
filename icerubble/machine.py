"""What a result records of the machine that made it, where the machine can
change the numbers (docs/reproducibility.md).

Two things differ between processors:
- YADE's phase 1 (a pile made here): its settle is chaotic and its floating
  point follows the processor (measured: demo ridge 1 made with AVX-512, or
  AVX2 and FMA, masked from glibc and numpy is another pile). Every pile
  records `made_on`; the study's ridges are shipped piles (run/shipped_ridges.py).
- the engine's build: the portable build (the default) computes the same bits
  on every x86-64 processor; NATIVE=ON does not. Every result records `build`.
"""
import platform


def processor():
    """The processor in words, with the features that change floating point
    in the libraries (glibc's libm and numpy pick code paths by them)."""
    name, flags = platform.machine(), set()
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                key, _, value = line.partition(":")
                if key.strip() == "model name" and name == platform.machine():
                    name = value.strip()
                elif key.strip() == "flags":
                    flags = set(value.split())
                    break
    except OSError:   # not Linux: the architecture is all we know
        pass
    shown = [f for f in ("fma", "avx2", "avx512f") if f in flags]
    return f"{name} ({platform.machine()}{', ' + ' '.join(shown) if shown else ''})"


def engine_build():
    """How the engine was compiled ("portable: GNU 12.2.0 -O3 ..."), or
    "unknown" for an extension built before builds were recorded."""
    from . import _engine
    return getattr(_engine, "build", "unknown")


def cpu_topology():
    """Logical processors, physical cores and sockets as Linux lists them in
    /proc/cpuinfo, with the OpenMP placement asked for: a thread count's
    speed-up reads differently where two threads share a core (a machine of
    16 logical processors on 8 cores doubles its threads on the same cores).
    None where /proc/cpuinfo says nothing of cores."""
    import os
    logical, cores, sockets, phys = 0, set(), set(), None
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                key, _, value = line.partition(":")
                key = key.strip()
                if key == "processor":
                    logical += 1
                elif key == "physical id":
                    phys = value.strip()
                    sockets.add(phys)
                elif key == "core id":
                    cores.add((phys, value.strip()))
    except OSError:
        return None
    if not cores:
        return None
    return dict(logical=logical, cores=len(cores), sockets=len(sockets), threads_per_core=logical / len(cores),
                omp_places=os.environ.get("OMP_PLACES", ""), omp_proc_bind=os.environ.get("OMP_PROC_BIND", ""))
