"""Stability stress matrix: extreme but legal parameters on a small bonded scene.

Every run either completes, with a complete result holding no NaN or inf
(except the datasets where NaN means "never": a bond point that never split or
failed), or stops with a message that says why (the step, the time, where), and
then leaves no file that looks complete and no NaN/inf in any file it wrote.

The scene: one row of six bonded blocks under the consolidated layer, 330
triangles, 1 mm of travel (~0.7 s per run at the base values). Each parameter
goes to the ends of a range a user could plausibly type (decades beyond Table
1), one at a time; then random mixtures of the extremes that cost little to
run (a seed fixes them).
"""
import glob
import os
import random
import re

import h5py
import numpy as np
import pytest

from icerubble import parameters as P
from icerubble.engine import InstabilityError
from icerubble.files.h5io import open_complete
from icerubble.geometry import meshing
from icerubble.run.punch_through_run import PunchThrough, RunOptions
from tests.run.punch_through_scenes import brick_pile

BASE = dict(penalty=2e10, target_travel=0.001, ramp_time=0.05)
DT_FRACTION = 0.8

# each parameter at the ends of its plausible range (Table 1 value in the comment)
EXTREMES = {
    "penalty": [1e6, 1e8, 1e12],          # 2e11 Pa
    "E": [1e6, 1e8, 5e10],                 # 2e9 Pa
    "nu": [0.0, 0.49],                     # 0.3
    "mu": [0.0, 1.0, 5.0],                 # 0.3
    "tau_cr": [1.0, 1e8],                  # 50 kPa
    "sigma_cr": [1.0, 1e8],                # 10 kPa
    "G": [1e-6, 1e5],                      # 15 J/m²
    "strength_bottom_fraction": [1e-4, 1.0],
    "damping": [1.0, 10.0],                # 0
    "viscosity": [0.0, 1e7],               # 2.5e4 Pa s
    "c_w": [0.0, 1e7],                     # 2.5e4 Pa s (linear drag)
    "C_d": [0.0, 10.0],                    # 1 (quadratic drag)
    "drag_model": ["none"],
    "v_final": [0.01, 2.0],                # 0.1 m/s
    "ramp_time": [0.0, 0.2],               # 2 s
    "rho_i": [300.0, 1005.0],              # 920 kg/m³ (water 1010)
    "force_direction": [P.OTHER_FORCE_DIRECTION],
}
DT_FRACTIONS = [0.2, 1.0]
# extremes that shrink the stable step (or lengthen the run) by 5-20x: one at a time only
COSTLY = {("penalty", 1e12), ("E", 5e10), ("E", 1e6), ("damping", 10.0), ("v_final", 0.01),
          ("viscosity", 1e7), ("ramp_time", 0.2)}
# the water drag law and its constants: at most one of them in a mixture
DRAG = {"drag_model", "c_w", "C_d"}
N_MIXTURES = 16

# datasets whose NaN means "never happened" (docs/results_format.md)
NAN_MEANS_NEVER = {"t_split", "y_I_split", "t_fail", "y_I_fail", "delta_n_fail", "delta_t_fail",
                   "split_tn", "split_tt"}
CLEAR_STOP = re.compile(r"run stopped at step \d+ \(t = |did not come to rest|exceeds the (contact )?stable step")


def _legal(params):
    """Drag constants go with their law (validate refuses c_w under quadratic drag)."""
    p = dict(params)
    if "c_w" in p:
        p["drag_model"] = "linear"
    if p.get("drag_model") == "none":
        p.pop("C_d", None)
    return p


def _cases():
    cases = []
    for name, values in EXTREMES.items():
        for v in values:
            cases.append((f"{name}={v:g}" if not isinstance(v, str) else f"{name}={v}",
                          _legal(dict(BASE, **{name: v})), DT_FRACTION))
    for f in DT_FRACTIONS:
        cases.append((f"dt_fraction={f:g}", dict(BASE), f))
    # sure to stop: a step far above the stable step (legal for validate, which
    # cannot know the mesh), so the stop branch below is exercised too
    cases.append(("dt=1e-3", dict(BASE, dt=1e-3), None))
    rng = random.Random(20261123)
    cheap = [(n, v) for n, vs in EXTREMES.items() for v in vs if (n, v) not in COSTLY]
    for i in range(N_MIXTURES):
        picks = {}
        for n, v in rng.sample(cheap, len(cheap)):
            if n not in picks and not (n in DRAG and DRAG & set(picks)):
                picks[n] = v
            if len(picks) == 5:
                break
        f = rng.choice([DT_FRACTION, 1.0])
        label = f"mix{i}:" + ",".join(f"{k}={v}" for k, v in picks.items()) + f",dt_fraction={f:g}"
        cases.append((label, _legal(dict(BASE, **picks)), f))
    return cases


CASES = _cases()


def test_the_matrix_has_at_least_50_legal_runs():
    assert len(CASES) >= 51
    assert len({label for label, _, _ in CASES}) == len(CASES)
    for _, params, _ in CASES:
        P.validate(params)   # legal: a run would accept them


@pytest.fixture(scope="module")
def mesh_path(tmp_path_factory):
    d = tmp_path_factory.mktemp("stress_scene")
    brick_pile(d / "pile.h5", width=6.0, rows=1)
    meshing.mesh_pile_file(str(d / "pile.h5"), str(d / "mesh.h5"), element_size=0.3)
    return d / "mesh.h5"


def _non_finite(path):
    """Names of the datasets (and /parameters attributes) of an HDF5 file holding NaN or inf
    where the format does not give NaN a meaning."""
    bad = []

    def visit(name, obj):
        if isinstance(obj, h5py.Dataset) and obj.dtype.kind == "f" and obj.size:
            if os.path.basename(name) in NAN_MEANS_NEVER:
                if np.isinf(obj[()]).any():
                    bad.append(name)
            elif not np.isfinite(obj[()]).all():
                bad.append(name)

    with h5py.File(path, "r") as f:
        f.visititems(visit)
        if "parameters" in f:
            for k, v in f["parameters"].attrs.items():
                if isinstance(v, (float, np.floating)) and not np.isfinite(v):
                    bad.append(f"parameters@{k}")
    return bad


@pytest.mark.parametrize("label,params,dt_fraction", CASES, ids=[c[0] for c in CASES])
def test_extreme_run_completes_or_stops_saying_why(mesh_path, tmp_path, label, params, dt_fraction):
    out = tmp_path / "run.h5"
    try:
        PunchThrough(mesh_path, out, params=params,
                     options=RunOptions(threads=1, progress_every_s=1e9, vtu=False,
                                        dt_fraction=dt_fraction, settle_max_time=2.0)).run()
    except (InstabilityError, RuntimeError, ValueError) as e:
        print(f"{label}: stopped: {e}")
        assert CLEAR_STOP.search(str(e)), f"{label}: unclear stop: {e}"
        with pytest.raises(ValueError):
            open_complete(out).close()
    else:
        with open_complete(out) as f:
            y = f["force/y_I"][()]
            assert y[-1] >= params["target_travel"], f"{label}: stopped at y_I = {y[-1]}"
        print(f"{label}: complete")
    for h5 in glob.glob(str(tmp_path / "*.h5")):
        assert not _non_finite(h5), f"{label}: non-finite values in {h5}: {_non_finite(h5)}"
