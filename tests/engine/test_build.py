"""The compiled modules import from the interpreter YADE uses."""
import sys


def test_interpreter_is_debian_python():
    assert sys.executable.startswith("/usr/bin/python3")


def test_extensions_import():
    from icerubble import _engine, _cohesive_law
    assert _engine.version() and _cohesive_law.version()


def test_the_entry_points_of_a_build_without_cuda_match_the_backend():
    # A build with neither a CUDA toolkit nor the emulation compiles
    # engine/src/cuda/without_cuda.cpp instead of the backend: its entry points
    # must keep the headers' signatures (a constructor's new argument once left
    # it uncompilable unnoticed, since the suite's build is the emulation's).
    import os
    import shutil
    import subprocess

    import pytest
    compiler = shutil.which(os.environ.get("CXX", "g++")) or shutil.which("c++")
    if compiler is None:
        pytest.skip("no C++ compiler on PATH")
    import pybind11
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    run = subprocess.run([compiler, "-std=c++17", "-fsyntax-only", "-I", os.path.join(root, "engine", "src"),
                          "-I", os.path.join(root, "cohesive_law", "include"), "-I", pybind11.get_include(),
                          "-I", __import__("sysconfig").get_paths()["include"],
                          os.path.join(root, "engine", "src", "cuda", "without_cuda.cpp")],
                         capture_output=True, text=True)
    assert run.returncode == 0, run.stderr[-3000:]
