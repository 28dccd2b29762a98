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
