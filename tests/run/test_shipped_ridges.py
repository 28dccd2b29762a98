"""Ridge N is one pile on every machine (issue 25; docs/reproducibility.md).

YADE's phase 1 makes another pile for the same seed on another processor, so
the ridges the study tables name ship as data (data/ridges/). These tests hold
on any machine: they check that a shipped ridge is copied, never made; that
this machine meshes it into the mesh it was meshed into where it was made
(gmsh and numpy agree); that a pile made here at a shipped ridge's name is
refused; and that a run computes the same bits with the processor features
that change floating point in glibc and numpy masked (an older processor,
emulated).
"""
import os
import platform
import shutil
import subprocess
import sys

import h5py
import numpy as np
import pytest

from icerubble.files.pile_file import read_pile
from icerubble.run import scene_cache, shipped_ridges as SR
from icerubble.run.presets import PILE_FRICTION, pile_friction, pile_scene
from icerubble.study.table_check import ridges_to_ship
from tests.paths import ROOT

# meshing a paper ridge takes 6-8 s: the suite meshes the small scenes' ridges and paper ridge 1
MESHED = [sr for sr in ridges_to_ship() if sr[0] not in ("paper", "deep")] + [("paper", 1), ("deep", 1)]


def test_every_ridge_a_table_names_is_shipped():
    entries = SR.manifest()
    for name, ridge in ridges_to_ship():
        mu = pile_friction(name)
        stem = SR.file_stem(name, ridge, mu)
        assert stem in entries, f"{name} ridge {ridge} is named in a table but not shipped (tools/make_ridges.py)"
        path = os.path.join(SR.RIDGES_DIR, SR.file_stem(pile_scene(name), ridge, mu) + "_pile.h5")
        assert SR.shipped(name, ridge, mu)[0] == path
        assert SR.digest(path) == entries[stem]["pile_digest"], f"{path} is not the pile its manifest names"
        meta = read_pile(path)["meta"]
        assert meta["settled"] == 1 and meta["friction"] == mu
        assert meta["made_on"] and meta["shipped"] == os.path.relpath(path, ROOT)


@pytest.fixture
def no_phase1(monkeypatch):
    def refuse(*a, **k):
        raise AssertionError("phase 1 ran for a shipped ridge")
    monkeypatch.setattr(scene_cache, "run_phase1", refuse)


@pytest.mark.parametrize("name,ridge", MESHED)
def test_a_shipped_ridge_is_copied_and_meshes_as_where_it_was_made(name, ridge, tmp_path, no_phase1):
    pile_path, mesh_path = scene_cache.scene_files(name, ridge, root=str(tmp_path))
    mu = pile_friction(name)
    entry = SR.manifest()[SR.file_stem(name, ridge, mu)]
    assert SR.digest(pile_path) == entry["pile_digest"]
    assert SR.digest(mesh_path) == entry["mesh_digest"], (
        f"this machine meshes {name} ridge {ridge} otherwise than where it was made: gmsh or numpy "
        "compute differently here (docs/reproducibility.md)")
    with h5py.File(mesh_path) as f:   # every result on it says where its pile came from
        assert f.attrs["pile_shipped"].endswith(SR.file_stem(pile_scene(name), ridge, mu) + "_pile.h5")
        assert f.attrs["pile_made_on"] == entry["made_on"]


def test_a_pile_made_here_at_a_shipped_ridges_name_is_refused(tmp_path, no_phase1):
    """A pile cached before ridges were shipped (made by this machine's phase 1)
    is not silently taken for the ridge every machine runs; nothing is overwritten."""
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    other = os.path.join(SR.RIDGES_DIR, SR.file_stem("small", 2, PILE_FRICTION) + "_pile.h5")
    at_name = scenes / (SR.file_stem("small", 1, PILE_FRICTION) + "_pile.h5")
    shutil.copyfile(other, at_name)
    before = at_name.read_bytes()
    with pytest.raises(ValueError, match="not this ridge's shipped pile.*Move .*small_ridge1_pilemu0.05_\\*"):
        scene_cache.scene_files("small", 1, root=str(tmp_path))
    assert at_name.read_bytes() == before


MASKED_RUN = r"""
import sys, numpy as np, h5py
from icerubble.study.line import run_one
from icerubble.run.punch_through_run import RunOptions
out = run_one("tiny", 1, out_dir=sys.argv[1], share_rest=False,
              options=RunOptions(threads=2, vtu=False, progress_every_s=1e9, dt_fraction=0.8))
with h5py.File(out) as f:
    np.save(sys.argv[2], np.stack([f["force/y_I"][:], f["force/F"][:]]))
from numpy.core._multiarray_umath import __cpu_features__
print("numpy features:", " ".join(k for k, v in __cpu_features__.items() if v))
"""


def _masks():
    """Environment that makes glibc and numpy run the code paths of an x86-64
    processor without AVX, AVX2, FMA and AVX-512 (numpy refuses to disable a
    feature this machine lacks, so only present ones are named)."""
    from numpy.core._multiarray_umath import __cpu_dispatch__, __cpu_features__
    npy = [f for f in __cpu_dispatch__ if __cpu_features__.get(f)
           and f.startswith(("AVX", "FMA", "F16C"))]
    glibc = "glibc.cpu.hwcaps=" + ",".join("-" + f for f in (
        "AVX", "AVX2", "FMA", "FMA4", "AVX512F", "AVX512DQ", "AVX512BW", "AVX512VL", "AVX512CD"))
    return dict(NPY_DISABLE_CPU_FEATURES=" ".join(npy), GLIBC_TUNABLES=glibc)


@pytest.mark.skipif(platform.machine() != "x86_64", reason="the masks name x86-64 processor features")
def test_a_run_computes_the_same_bits_on_an_older_processor(tmp_path):
    """The engine is built portable (docs/reproducibility.md): with glibc's and
    numpy's processor-specific code paths masked, the tiny scene's whole run
    (settle, bond splits, loading) writes the same force record, bit for bit."""
    records = []
    for label, extra in (("here", {}), ("masked", _masks())):
        env = dict(os.environ, OMP_NUM_THREADS="2", **extra)
        out = tmp_path / label
        r = subprocess.run([sys.executable, "-c", MASKED_RUN, str(out), str(out / "record.npy")],
                           cwd=ROOT, env=env, capture_output=True, text=True)
        assert r.returncode == 0, r.stdout[-2000:] + r.stderr[-2000:]
        if extra:   # the masks took: numpy runs without them (the same masks make
            # YADE's phase 1 another pile, docs/reproducibility.md: glibc's took too)
            active = set(r.stdout.split("numpy features:")[1].split())
            assert not active & set(extra["NPY_DISABLE_CPU_FEATURES"].split())
        records.append(np.load(out / "record.npy"))
    assert records[0].shape == records[1].shape and records[0].shape[1] > 10
    assert records[0].tobytes() == records[1].tobytes()


def test_the_paper_scenes_ridges_are_as_deep_and_loose_as_table_1s():
    """Table 1: keel depth h ~ 4 m, bulk porosity ~0.25 (void / total area,
    docs/pile_and_mesh.md); the block count fills h, the porosity is what
    phase 1's procedure (random orientations, ice-ice friction) gives."""
    ridges = [e for e in SR.manifest().values() if e["scene"] == "paper"]
    assert len(ridges) >= 4
    for e in ridges:
        assert 3.6 <= e["keel_depth"] <= 4.4, e
        assert 0.2 <= e["pile_porosity"] <= 0.3 and 0.2 <= e["mesh_porosity"] <= 0.3, e
