"""The CPU emulation of the CUDA runtime (engine/src/cuda/emulation/, the
GPU backend's test bench where no GPU is; docs/gpu.md): what it keeps of a
GPU, each shown by a scene whose answer is known, so that a backend that
reads a result before waiting for it, or touches device memory from the
host, fails its tests here as it would on a GPU."""
import subprocess
import sys

import pytest

from icerubble import _engine
from icerubble.engine import gpu
from tests.paths import ROOT

pytestmark = pytest.mark.skipif(not gpu.emulation_built(), reason="this build has no CPU emulation of the CUDA "
                                "runtime (it was built with a CUDA toolkit, or with ICERUBBLE_CUDA_EMULATION off)")


def check(scene):
    return _engine.cuda_emulation_check(scene)


def test_a_stream_runs_its_work_when_the_host_waits():
    assert check("stream_is_asynchronous") == {"before_wait": 0.0, "after_wait": 42.0}


def test_a_copy_on_the_legacy_stream_does_not_wait_for_a_non_blocking_stream():
    assert check("legacy_copy_does_not_wait") == {"without_wait": 0.0, "after_wait": 7.0}


def test_fresh_device_memory_is_not_zero():
    assert check("fresh_memory") == {"double_is_nan": 1.0, "int": -1.0}


def test_a_block_meets_at_its_barriers():
    # the backend's fixed tree over 256 lanes: 0 + 1 + ... + 255
    assert check("block_sum") == {"sum": 255 * 256 / 2, "or_one_votes": 1.0, "or_none_votes": 0.0}


def test_lanes_that_differ_on_a_barrier_are_a_fault_said_at_the_wait():
    assert check("divergent_barrier") == {"error": 719.0, "message_names_barrier": 1.0}  # cudaErrorLaunchFailure


def test_a_captured_graph_runs_only_when_launched():
    assert check("graph_replays") == {"after_capture": 0.0, "after_two_launches": 2.0}


def test_a_block_of_too_many_lanes_is_refused_at_the_launch():
    assert check("invalid_configuration") == {"error": 9.0, "cleared": 0.0}  # cudaErrorInvalidConfiguration


def test_host_code_touching_device_memory_stops_saying_so():
    r = subprocess.run([sys.executable, "-c", "from icerubble import _engine; "
                        "_engine.cuda_emulation_check('host_touches_device_memory')"],
                       cwd=ROOT, capture_output=True, text=True, timeout=60)
    assert r.returncode != 0 and "host code touched device memory" in r.stderr, (r.returncode, r.stderr[-500:])


def test_an_unknown_scene_is_refused():
    with pytest.raises(ValueError, match="unknown emulation scene 'nope'"):
        check("nope")


def test_the_backend_runs_on_the_emulation_only_when_asked(monkeypatch):
    monkeypatch.delenv(gpu.EMULATION_ENV, raising=False)
    assert not gpu.available() and gpu.EMULATION_ENV in gpu.why_unavailable()
    monkeypatch.setenv(gpu.EMULATION_ENV, "1")
    assert gpu.available() and "emulation" in gpu.device_name()
