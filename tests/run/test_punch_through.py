"""The punch-through run on a tiny constructed scene (two rows of bonded
blocks under the consolidated layer, ~700 triangles): rest state, F(y_I),
where the bonds fail first, energy balance, checkpoint/resume, bad input."""
import json
import os
import signal

import h5py
import numpy as np
import pytest

from icerubble.code_identity import source_hash
from icerubble.code_identity import code_version
from icerubble.files.h5io import open_complete
from icerubble.run import checkpoint as ckpt
from icerubble.run.loading import MEAN_FORCE_MIN_TRAVEL
from icerubble.run.driver import RunInterrupted, catching_stop_signals
from icerubble.run.punch_through_run import PunchThrough, RunOptions
from tests.h5_edits import broken
from tests.run.punch_through_scenes import brick_mesh

# A short, fast punch: a 0.2 s ramp and 3 mm of travel. Coarse (0.2 m)
# elements, a 10x softer penalty than Table 1 and dt = 5e-6 s keep it in seconds.
PARAMS = dict(dt=5e-6, penalty=2e10, target_travel=0.003, ramp_time=0.2, damping=0.1)


@pytest.fixture(scope="module")
def mesh_path(tmp_path_factory):
    return brick_mesh(tmp_path_factory.mktemp("scene"))


@pytest.fixture(scope="module")
def finished(mesh_path, tmp_path_factory):
    out = tmp_path_factory.mktemp("run") / "run.h5"
    run = PunchThrough(mesh_path, out, params=PARAMS,
                       options=RunOptions(threads=1, progress_every_s=1e9, vtu=True))
    run.run()
    return run, out


def net_buoyancy_under_indenter(run):
    """(ρ_w - ρ_i) g × solid area of the keel under the indenter [N/m]: what
    the indenter would carry if it were held while the keel settled."""
    p, sc = run.params, run.scene
    return (p["rho_w"] - p["rho_i"]) * p["g"] * sc.indenter_width * sc.keel_depth


def test_at_rest_before_loading(finished):
    """Paper 2.4: the system is in balance before the indenter moves. The
    settle criterion leaves each free body in balance on average over 2 ms
    (docs/model.md §3.4), to 1e-4 of its weight; the force holding the indenter at rest
    must be a small fraction (2 %) of the keel buoyancy it would otherwise
    carry (~1.4 kN/m here)."""
    run, _ = finished
    assert abs(run.state.F_at_rest) < 0.02 * net_buoyancy_under_indenter(run)


def test_force_record_starts_at_zero_and_rises(finished):
    run, out = finished
    with open_complete(out, "icerubble-run") as f:
        y, F = f["force/y_I"][:], f["force/F"][:]
        assert f["force/F"].attrs["units"] == "N/m"
        assert np.all(np.diff(y) >= -1e-12)
        # docs/model.md §4: F samples at least every 0.1 mm of travel
        assert np.max(np.diff(y)) <= 1e-4
        F_peak = F.max()
        # the bonded keel resists: the peak is far above the rest force and
        # above the buoyancy of the keel under the indenter
        assert F_peak > 10 * abs(F[0]) and F_peak > net_buoyancy_under_indenter(run)
        assert y[np.argmax(F)] > 0.0
        assert len(f["snapshots"]) == 1  # 1 mm (the next, 5 mm, is beyond 3 mm)
        assert f.attrs["complete"] == 1 and f["parameters"].attrs["tau_cr"] == 50e3


def test_bonds_fail_first_near_the_indenter(finished):
    """The first bond points to split lie within the region the indenter
    loads: under it or within one keel depth of its edges."""
    run, out = finished
    with open_complete(out) as f:
        t_split = f["bonds/t_split"][:]
        pos = f["bonds/position"][:]
        mode = f["bonds/mode"][:]
    split = np.flatnonzero(np.isfinite(t_split))
    assert len(split) >= 5
    first = split[np.argsort(t_split[split])[:5]]
    reach = run.scene.indenter_width / 2 + run.scene.keel_depth
    assert np.all(np.abs(pos[first, 0]) <= reach)
    assert set(np.unique(mode)) <= {0, 1, 2}


def test_the_recorded_split_traction_met_the_failure_criterion(finished):
    """/bonds/split_tn, split_tt: at every point that split, the recorded traction
    reaches eq 5 (t_e >= sigma_cr with the point's strengths and the run's mu); NaN
    exactly where no split happened."""
    from icerubble import cohesive_law
    _, out = finished
    with open_complete(out) as f:
        b = {k: f["bonds"][k][:] for k in ("t_split", "split_tn", "split_tt", "sigma_cr", "tau_cr")}
        mu = f["parameters"].attrs["mu"]
        assert f["bonds/split_tn"].attrs["units"] == "Pa"
    split = np.isfinite(b["t_split"])
    assert split.any()
    assert np.array_equal(np.isfinite(b["split_tn"]), split) and np.array_equal(np.isfinite(b["split_tt"]), split)
    assert np.all(cohesive_law.criterion_reached(b["split_tn"][split], b["split_tt"][split],
                                                 b["sigma_cr"][split], b["tau_cr"][split], mu))


def test_energy_balance_through_bond_failure(finished):
    """Stored + dissipated = initial + supplied: the balance residual stays
    below 1e-3 of the energy flowing through the run (the scheme's residual is
    O(dt²); splitting, softening and contact must not create energy)."""
    run, _ = finished
    e = run.model.energies()
    assert abs(e["residual"]) < 1e-3 * e["scale"]
    assert e["cohesive"] > 0 and e["friction"] >= 0 and e["drag"] > 0


def test_fields_open_in_paraview_format(finished):
    run, out = finished
    from icerubble.files.vtu import read_vtu
    d = str(out)[:-3] + "_fields"
    back = read_vtu(f"{d}/run_0000.vtu")
    assert back["Points"].shape[0] == len(back["u_total"])


def test_resumed_run_gives_the_same_record(mesh_path, tmp_path, finished):
    """Interrupted during loading (after bonds have split), the run leaves a
    checkpoint and no result file; resumed, it writes the same F(y_I) record
    as the uninterrupted run."""
    run0, out0 = finished
    out = tmp_path / "run.h5"
    stop = run0.model.step_count - 4000
    run = PunchThrough(mesh_path, out, params=PARAMS,
                       options=RunOptions(threads=1, progress_every_s=1e9, vtu=True,
                                          stop_after_steps=stop))
    with pytest.raises(KeyboardInterrupt):
        run.run()
    assert not out.exists() and (tmp_path / "run.checkpoint.h5").exists()
    # field pieces may exist, but no ParaView collection that looks complete
    pvd = tmp_path / "run_fields" / "run.pvd"
    assert list((tmp_path / "run_fields").glob("*.vtu")) and not pvd.exists()
    again = PunchThrough(mesh_path, out, params=PARAMS,
                         options=RunOptions(threads=1, progress_every_s=1e9, vtu=True))
    again.run(resume=True)
    assert pvd.read_text().count("<DataSet") == len(again.state.vtu_entries) == len(run0.state.vtu_entries)
    with h5py.File(out0) as a, h5py.File(out) as b:
        # bit for bit: same thread count, the checkpoint holds the whole state
        # (split mesh, bonds, energy ledger, friction warm start)
        np.testing.assert_array_equal(b["force/y_I"][:], a["force/y_I"][:])
        np.testing.assert_array_equal(b["force/F"][:], a["force/F"][:])
        np.testing.assert_array_equal(np.isfinite(b["bonds/t_split"][:]), np.isfinite(a["bonds/t_split"][:]))
        # the energy record too, sampled at the same times (issue 11: it was
        # sampled every ENERGY_EVERY force samples counted from the resume)
        np.testing.assert_array_equal(b["energy/t"][:], a["energy/t"][:])
        np.testing.assert_array_equal(b["energy/residual"][:], a["energy/residual"][:])
    assert not (tmp_path / "run.checkpoint.h5").exists()


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGUSR1, signal.SIGINT])
def test_a_scheduler_signal_stops_the_run_with_a_checkpoint_it_resumes_from(mesh_path, tmp_path, finished,
                                                                            signum):
    """SIGTERM (scancel, preemption), SIGUSR1 (before a time limit) or SIGINT
    (Ctrl-C) while loading: the run writes its checkpoint and stops with
    RunInterrupted; run again it ends with the uninterrupted record, bit for bit."""
    run0, out0 = finished

    class Signalled(PunchThrough):
        sent = False

        def _maybe_checkpoint(self, force=False):
            # as the scheduler would, mid-run: half way, after bond points have split
            if self.state.phase == "load" and not self.sent and self.travel() > 0.5 * PARAMS["target_travel"]:
                self.sent = True
                os.kill(os.getpid(), signum)
            super()._maybe_checkpoint(force)

    out = tmp_path / "run.h5"
    opts = dict(threads=1, progress_every_s=1e9, vtu=False)
    # the handler the run found: Python's own, or SIG_IGN where the tests were started in the background
    handler_found = signal.getsignal(signum)
    with pytest.raises(RunInterrupted, match=rf"stopped by {signum.name} at step \d+ \(phase load"):
        Signalled(mesh_path, out, params=PARAMS, options=RunOptions(**opts)).run()
    assert not out.exists() and (tmp_path / "run.checkpoint.h5").exists()
    assert signal.getsignal(signum) is handler_found
    with h5py.File(tmp_path / "run.checkpoint.h5") as f:
        before = {k: float(f["driver"].attrs[k]) for k in ("wall_settle_s", "wall_load_s")}
    assert before["wall_settle_s"] > 0 and before["wall_load_s"] > 0
    PunchThrough(mesh_path, out, params=PARAMS, options=RunOptions(**opts)).run(resume=True)
    with h5py.File(out0) as a, h5py.File(out) as b:
        np.testing.assert_array_equal(b["force/F"][:], a["force/F"][:])
        np.testing.assert_array_equal(b["energy/residual"][:], a["energy/residual"][:])
        # the cost is the run's, not the resumed process's: the settle was
        # all before the stop, the loading is both processes' share
        assert b.attrs["wall_settle_s"] == before["wall_settle_s"]
        assert b.attrs["wall_load_s"] > before["wall_load_s"]
        # the step timings are the writing process's: its own steps, after the resume
        timed = json.loads(b.attrs["step_timings"])
        assert 0 < timed["steps"] < b.attrs["load_steps"] and timed["total"] > 0


def test_a_second_ctrl_c_stops_at_once():
    """The first Ctrl-C asks for a stop at the end of the chunk (a checkpoint
    is written then); a second one, for a person who will not wait, raises
    KeyboardInterrupt at once, as Python's own handler does."""
    class Run:
        pass
    run = Run()
    handler_found = signal.getsignal(signal.SIGINT)
    with catching_stop_signals(run):
        os.kill(os.getpid(), signal.SIGINT)
        assert run._stop_signal == signal.SIGINT
        with pytest.raises(KeyboardInterrupt):
            os.kill(os.getpid(), signal.SIGINT)
    assert signal.getsignal(signal.SIGINT) is handler_found


@pytest.mark.parametrize("bad,word", [(dict(tau_cr=0.0), "tau_cr"), (dict(sigma_cr=-1.0), "sigma_cr"),
                                      (dict(mu=-0.1), "mu"), (dict(keel_depth=-4.0), "keel_depth"),
                                      (dict(dt=0.0), "dt")])
def test_bad_parameters_stop_before_any_work(mesh_path, tmp_path, bad, word):
    with pytest.raises(ValueError, match=word):
        PunchThrough(mesh_path, tmp_path / "x.h5", params=dict(PARAMS, **bad))


def test_a_file_that_is_not_a_mesh_is_refused(tmp_path):
    junk = tmp_path / "junk.h5"
    junk.write_text("not a mesh")
    with pytest.raises(ValueError, match="mesh"):
        PunchThrough(junk, tmp_path / "x.h5", params=PARAMS)


def test_recorded_geometry_is_the_meshs(finished):
    """The analyses read keel depth and indenter width from /parameters: they
    must be the simulated scene's (two 0.3 m rows: 0.6 m), not Table 1's 4 m."""
    run, out = finished
    with open_complete(out) as f:
        p = f["parameters"].attrs
        assert p["keel_depth"] == pytest.approx(0.6, abs=1e-9)
        assert p["indenter_width"] == pytest.approx(4.0, abs=1e-9)
        assert p["domain_width"] == pytest.approx(8.0)


def test_mass_scaling_raises_the_step_and_keeps_the_balance(mesh_path, tmp_path):
    """Selective mass scaling (the paper scene's remedy for the tiny elements of
    real piles): the run's step follows the target, the added inertial mass is
    recorded, weight stays physical (the scene still comes to rest with the
    indenter force ~0) and the energy balance closes."""
    base = PunchThrough(mesh_path, tmp_path / "a.h5", params=PARAMS, options=RunOptions(threads=1))
    dt0 = base.model.stable_time_step()["dt"]
    target = 1.5 * dt0
    run = PunchThrough(mesh_path, tmp_path / "b.h5", params=dict(PARAMS, target_travel=5e-4),
                       options=RunOptions(threads=1, progress_every_s=1e9, vtu=False,
                                          dt_fraction=0.8, mass_scaling_dt=target))
    assert run.params["dt"] >= 0.8 * target * (1 - 1e-9)
    st = run.model.stable_time_step()
    assert run.meta["added_mass_fraction"] == st["added_mass_fraction"] > 0
    assert run.meta["scaled_nodes"] == st["scaled_nodes"] > 0
    run.run()
    assert abs(run.state.F_at_rest) < 0.02 * net_buoyancy_under_indenter(run)
    e = run.model.energies()
    assert abs(e["residual"]) < 1e-3 * e["scale"]
    with open_complete(tmp_path / "b.h5") as f:
        assert f.attrs["mass_scaling_dt"] == pytest.approx(target)


def test_run_interrupted_while_settling_resumes(mesh_path, tmp_path, finished):
    """A checkpoint written before loading starts (nothing recorded yet)
    resumes into the same run."""
    run0, out0 = finished
    out = tmp_path / "run.h5"
    run = PunchThrough(mesh_path, out, params=PARAMS,
                       options=RunOptions(threads=1, progress_every_s=1e9, vtu=False, stop_after_steps=1))
    with pytest.raises(KeyboardInterrupt):
        run.run()
    assert run.state.phase == "settle" and not out.exists()
    again = PunchThrough(mesh_path, out, params=PARAMS,
                         options=RunOptions(threads=1, progress_every_s=1e9, vtu=False))
    again.run(resume=True)
    with h5py.File(out0) as a, h5py.File(out) as b:
        np.testing.assert_array_equal(b["force/F"][:], a["force/F"][:])


def test_force_samples_are_the_mean_force_over_each_interval(finished):
    """F is sampled as work on the indenter / travel since the last sample,
    minus the indenter's net buoyancy (linear in travel over a sample): so
    sum F dy_I plus the integral of that buoyancy is the boundary's work
    over the run (energy record, last row). Samples that moved less than
    MEAN_FORCE_MIN_TRAVEL (the ramp's first steps) take the instantaneous
    force: their share of the work is off by at most 2 max|F| dy each;
    otherwise the identity holds to round-off (1e-9). The instantaneous
    samples carry the rubble's vibration: their mean over the record agrees
    with the interval means' to 5 % of the peak, their scatter is larger."""
    run, out = finished
    with open_complete(out, "icerubble-run") as f:
        y, F, Fi = f["force/y_I"][:], f["force/F"][:], f["force/F_instant"][:]
        w_end = f["energy/work_boundary"][-1]
    sc, p = run.scene, run.params
    # net buoyancy is linear in travel: (rho_w g w_I) per m of travel plus its rest value
    b = lambda yy: sc.indenter_net_buoyancy() + p["rho_w"] * p["g"] * sc.indenter_width * (yy - y[-1])
    work = np.sum(F[1:] * np.diff(y)) + np.sum(0.5 * (b(y[1:]) + b(y[:-1])) * np.diff(y))
    dy = np.diff(y)
    tiny = dy <= MEAN_FORCE_MIN_TRAVEL
    assert abs(work - w_end) <= 1e-9 * abs(w_end) + 2 * np.abs(F).max() * dy[tiny].sum()
    assert dy[tiny].sum() < 1e-3 * y[-1]
    assert abs(np.mean(Fi[1:]) - np.mean(F[1:])) < 0.05 * F.max()
    assert np.std(np.diff(Fi)) >= np.std(np.diff(F))


def test_a_settle_at_a_larger_step_rests_in_the_same_balance_and_loads_at_the_loading_masses(mesh_path, tmp_path):
    """Dynamic relaxation: the settle runs with more inertial mass and a larger
    step (weight stays physical, so the rest it reaches balances the same
    loads), then the loading's masses and step come back exactly."""
    opts = dict(threads=1, progress_every_s=1e9, vtu=False, dt_fraction=0.8)
    base = PunchThrough(mesh_path, tmp_path / "a.h5", params=PARAMS, options=RunOptions(**opts))
    dt0 = base.model.stable_time_step()["dt"]
    base.run()
    fast = PunchThrough(mesh_path, tmp_path / "b.h5", params=PARAMS,
                        options=RunOptions(settle_mass_scaling_dt=4 * dt0, **opts))
    seen = []
    step = fast.model.step

    def counting(n):
        seen.append((fast.state.phase, fast.model.dt, n))
        step(n)
    fast.model.step = counting
    fast.run()
    settle_dt = {dt for phase, dt, _ in seen if phase == "settle"}
    load_dt = {dt for phase, dt, _ in seen if phase == "load"}
    assert load_dt == {base.model.dt}
    assert max(settle_dt) > 3.0 * base.model.dt          # 0.8 of 4x the stable step
    # the loading's masses exactly: the settle's were dropped
    np.testing.assert_array_equal(fast.model.mass, base.model.mass)
    # at rest in balance: holding the indenter takes ~nothing, in both
    assert abs(fast.state.F_at_rest) < 0.02 * net_buoyancy_under_indenter(fast)
    e = fast.model.energies()
    assert abs(e["residual"]) < 1e-3 * e["scale"]
    # the bonded rows have one rest state: the same cohesive peak
    with h5py.File(tmp_path / "a.h5") as a, h5py.File(tmp_path / "b.h5") as b:
        assert b["force/F"][:].max() == pytest.approx(a["force/F"][:].max(), rel=1e-3)
        assert b.attrs["settle_mass_scaling_dt"] == 4 * dt0


def test_the_settle_step_must_exceed_the_loadings():
    with pytest.raises(ValueError, match="settle_mass_scaling_dt"):
        RunOptions(mass_scaling_dt=2e-6, settle_mass_scaling_dt=1e-6)


def test_a_run_stopped_while_settling_at_the_larger_step_resumes_into_the_same_run(mesh_path, tmp_path):
    opts = dict(threads=1, progress_every_s=1e9, vtu=False, dt_fraction=0.8)
    dt0 = PunchThrough(mesh_path, tmp_path / "x.h5", params=PARAMS,
                       options=RunOptions(**opts)).model.stable_time_step()["dt"]
    opts["settle_mass_scaling_dt"] = 4 * dt0
    PunchThrough(mesh_path, tmp_path / "a.h5", params=PARAMS, options=RunOptions(**opts)).run()
    run = PunchThrough(mesh_path, tmp_path / "b.h5", params=PARAMS, options=RunOptions(stop_after_steps=50, **opts))
    with pytest.raises(KeyboardInterrupt):
        run.run()
    assert run.state.phase == "settle"
    PunchThrough(mesh_path, tmp_path / "b.h5", params=PARAMS, options=RunOptions(**opts)).run(resume=True)
    with h5py.File(tmp_path / "a.h5") as a, h5py.File(tmp_path / "b.h5") as b:
        np.testing.assert_array_equal(b["force/F"][:], a["force/F"][:])


@pytest.mark.parametrize("phase_stop", ["load", "settle"])
def test_a_mass_scaled_run_with_a_contact_reach_resumes_into_the_same_run(mesh_path, tmp_path, phase_stop):
    """The `balanced`/`fast` numerics (mass scaling to a target step, the
    contact step bound within a reach, a settle at a larger step): the model
    rebuilt from a checkpoint gets the same masses and step bound again, so a
    resumed run is the uninterrupted one bit for bit. Before, a resumed run had
    neither and stopped at its first step (its dt above the unscaled bound)."""
    opts = dict(threads=1, progress_every_s=1e9, vtu=False, dt_fraction=0.8)
    dt0 = PunchThrough(mesh_path, tmp_path / "x.h5", params=PARAMS,
                       options=RunOptions(**opts)).model.stable_time_step()["dt"]
    opts.update(mass_scaling_dt=1.5 * dt0, contact_reach=0.05, settle_mass_scaling_dt=3 * dt0)
    whole = PunchThrough(mesh_path, tmp_path / "a.h5", params=PARAMS, options=RunOptions(**opts))
    assert whole.meta["added_mass_fraction"] > 0
    whole.run()
    stop = 50 if phase_stop == "settle" else whole.model.step_count - 2000
    run = PunchThrough(mesh_path, tmp_path / "b.h5", params=PARAMS,
                       options=RunOptions(stop_after_steps=stop, **opts))
    with pytest.raises(KeyboardInterrupt):
        run.run()
    assert run.state.phase == phase_stop
    again = PunchThrough(mesh_path, tmp_path / "b.h5", params=PARAMS, options=RunOptions(**opts))
    again.run(resume=True)
    np.testing.assert_array_equal(again.model.mass, whole.model.mass)
    with h5py.File(tmp_path / "a.h5") as a, h5py.File(tmp_path / "b.h5") as b:
        np.testing.assert_array_equal(b["force/F"][:], a["force/F"][:])
        np.testing.assert_array_equal(b["energy/residual"][:], a["energy/residual"][:])


def test_a_run_with_the_sleeping_far_field_resumes_into_the_same_run(mesh_path, tmp_path):
    """Sleeping on (bricks fall asleep now and then): the checkpoint carries
    the sleep state, the frozen bodies' reference forces and the open balance
    window, so the resumed run is the uninterrupted one bit for bit."""
    opts = dict(threads=1, progress_every_s=1e9, vtu=False, dt_fraction=0.8,
                sleep=dict(velocity=1e-3, force=1e-2, quiet_time=2e-3))
    whole = PunchThrough(mesh_path, tmp_path / "a.h5", params=PARAMS, options=RunOptions(**opts))
    asleep_at = []   # load steps (chunk ends) with bodies asleep
    step = whole.model.step

    def watching(n):
        step(n)
        if whole.state.phase == "load" and whole.model.sleep_counts()["asleep_nodes"] > 0:
            asleep_at.append(whole.model.step_count)
    whole.model.step = watching
    whole.run()
    assert whole.state.load_element_steps < whole.state.load_steps * whole.model.n_triangles   # some slept
    assert asleep_at
    run = PunchThrough(mesh_path, tmp_path / "b.h5", params=PARAMS,
                       options=RunOptions(stop_after_steps=asleep_at[len(asleep_at) // 2], **opts))
    with pytest.raises(KeyboardInterrupt):
        run.run()
    assert run.state.phase == "load" and run.model.sleep_counts()["asleep_nodes"] > 0
    again = PunchThrough(mesh_path, tmp_path / "b.h5", params=PARAMS, options=RunOptions(**opts))
    again.run(resume=True)
    with h5py.File(tmp_path / "a.h5") as a, h5py.File(tmp_path / "b.h5") as b:
        np.testing.assert_array_equal(b["force/F"][:], a["force/F"][:])
        np.testing.assert_array_equal(b["energy/residual"][:], a["energy/residual"][:])


def test_a_checkpoint_of_another_physics_version_is_refused(mesh_path, tmp_path):
    """A checkpoint written by code that settled, slept or computed forces
    otherwise cannot be continued by this code: refused, naming both
    versions, before anything is loaded."""
    opts = dict(threads=1, progress_every_s=1e9, vtu=False)
    run = PunchThrough(mesh_path, tmp_path / "a.h5", params=PARAMS, options=RunOptions(stop_after_steps=1, **opts))
    with pytest.raises(KeyboardInterrupt):
        run.run()
    with h5py.File(tmp_path / "a.checkpoint.h5", "a") as f:
        f["driver"].attrs["physics_version"] = 2
    again = PunchThrough(mesh_path, tmp_path / "a.h5", params=PARAMS, options=RunOptions(**opts))
    with pytest.raises(ValueError, match="physics version 2, this code is version"):
        again.run(resume=True)


def test_a_checkpoint_of_other_code_is_refused_and_one_of_this_code_resumes(mesh_path, tmp_path, finished):
    """Only the code that wrote a checkpoint continues it (code_identity.py):
    a checkpoint recording another source hash, or none (written before they
    were recorded), is refused naming the code that wrote it, the code that
    runs and what to do; the untouched one resumes into the run in one go."""
    _, out0 = finished
    opts = dict(threads=1, progress_every_s=1e9, vtu=False)
    run = PunchThrough(mesh_path, tmp_path / "a.h5", params=PARAMS, options=RunOptions(stop_after_steps=1, **opts))
    with pytest.raises(KeyboardInterrupt):
        run.run()
    saved = tmp_path / "a.checkpoint.h5"

    def other_code(f):
        f.attrs["source_hash"], f.attrs["code_version"] = "0123456789abcdef", "0.1.0+gdeadbee"

    def older_code(f):
        del f.attrs["source_hash"]
    for edit, says in ((other_code, r"written by code 0\.1\.0\+gdeadbee \(source 0123456789abcdef\)"),
                       (older_code, r"before checkpoints recorded the source")):
        folder = tmp_path / edit.__name__
        folder.mkdir()
        broken(saved, folder, edit)
        again = PunchThrough(mesh_path, folder / "a.h5", params=PARAMS, options=RunOptions(**opts))
        with pytest.raises(ValueError, match=says) as e:
            again.run(resume=True)
        assert f"this is code {code_version()} (source {source_hash()})" in str(e.value)
        assert "Delete the checkpoint" in str(e.value) and "with the code that wrote it" in str(e.value)
        assert not (folder / "a.h5").exists()
    PunchThrough(mesh_path, tmp_path / "a.h5", params=PARAMS, options=RunOptions(**opts)).run(resume=True)
    with h5py.File(out0) as a, h5py.File(tmp_path / "a.h5") as b:
        assert b.attrs["source_hash"] == a.attrs["source_hash"] == source_hash()
        np.testing.assert_array_equal(b["force/F"][:], a["force/F"][:])


def rest_state_of_another_run(mesh_path, tmp_path):
    """The options of a plain run, a run settled at another step with other
    masses (mass scaling to twice the plain step), and its rest state."""
    base = dict(threads=1, progress_every_s=1e9, vtu=False, dt_fraction=0.8)
    dt0 = PunchThrough(mesh_path, tmp_path / "x.h5", params=PARAMS,
                       options=RunOptions(**base)).model.stable_time_step()["dt"]
    settler = PunchThrough(mesh_path, tmp_path / "settle.h5", params=PARAMS,
                           options=RunOptions(mass_scaling_dt=2 * dt0, **base))
    return base, settler, settler.settle_only(tmp_path / "rest.checkpoint.h5")


def test_a_run_loads_from_another_runs_rest_state_with_its_own_masses_and_step(mesh_path, tmp_path):
    """bench/paper_peak.py compares loading numerics from one rest state: a
    run started from another run's rest state (settled at another step with
    other masses) loads with its own masses and step, exactly those it would
    have had itself, and refuses a rest state of other parameters or one
    that is not at the start of loading."""
    base, settler, rest = rest_state_of_another_run(mesh_path, tmp_path)
    own = PunchThrough(mesh_path, tmp_path / "own.h5", params=PARAMS, options=RunOptions(**base))
    assert own.params["dt"] < settler.params["dt"]
    # as loading starts: its own masses (no mass scaling) and step, not the settler's
    probe = PunchThrough(mesh_path, tmp_path / "p.h5", params=PARAMS, options=RunOptions(**base))
    ckpt.restore(probe, rest, from_rest=True)
    np.testing.assert_array_equal(probe.model.mass, own.model.mass)
    assert probe.model.dt == own.params["dt"]
    loader = PunchThrough(mesh_path, tmp_path / "b.h5", params=PARAMS, options=RunOptions(**base))
    loader.run_from_rest(rest)
    with open_complete(tmp_path / "b.h5") as f:
        y, F = f["force/y_I"][:], f["force/F"][:]
        assert f.attrs["rest_state_from"] == os.path.abspath(rest)
        assert f.attrs["rest_state_dt"] == settler.params["dt"]
        assert F[0] == settler.state.F_at_rest and y[-1] >= PARAMS["target_travel"]
        assert F.max() > 10 * abs(F[0])
    # another friction coefficient: not this run's rest state
    other = PunchThrough(mesh_path, tmp_path / "c.h5", params=dict(PARAMS, mu=0.5), options=RunOptions(**base))
    with pytest.raises(ValueError, match=r"other parameters \(mu\)"):
        other.run_from_rest(rest)
    # a checkpoint from within the settle is no rest state
    early = PunchThrough(mesh_path, tmp_path / "d.h5", params=PARAMS,
                         options=RunOptions(stop_after_steps=1, **base))
    with pytest.raises(KeyboardInterrupt):
        early.run()
    late = PunchThrough(mesh_path, tmp_path / "e.h5", params=PARAMS, options=RunOptions(**base))
    with pytest.raises(ValueError, match="not at the start of loading"):
        late.run_from_rest(tmp_path / "d.checkpoint.h5")
    # nor is that run's own checkpoint, left while settling, a load to resume
    with pytest.raises(ValueError, match="checkpoint of a settle"):
        PunchThrough(mesh_path, tmp_path / "d.h5", params=PARAMS, options=RunOptions(**base)).run_from_rest(rest)
    # a rest state written where the run keeps (and removes) its own checkpoint
    with pytest.raises(ValueError, match="rest_path=.* is this run's own checkpoint"):
        late.settle_only(late.ckpt_path)


def test_a_load_from_a_rest_state_interrupted_resumes_into_the_same_run(mesh_path, tmp_path, capsys):
    """A run loading from another run's rest state (run_from_rest), stopped
    after bond points have split, resumes from its own checkpoint (not the
    rest state again) into the uninterrupted run, bit for bit, and still names
    the rest state it came from."""
    base, settler, rest = rest_state_of_another_run(mesh_path, tmp_path)
    whole = PunchThrough(mesh_path, tmp_path / "a.h5", params=PARAMS, options=RunOptions(**base))
    whole.run_from_rest(rest)
    run = PunchThrough(mesh_path, tmp_path / "b.h5", params=PARAMS,
                       options=RunOptions(stop_after_steps=whole.model.step_count - 2000, **base))
    with pytest.raises(KeyboardInterrupt):
        run.run_from_rest(rest)
    assert run.state.phase == "load" and run.model.bonds.counts["split"] > 0
    assert not (tmp_path / "b.h5").exists() and os.path.exists(run.ckpt_path)
    stopped_at = run.model.step_count
    capsys.readouterr()
    PunchThrough(mesh_path, tmp_path / "b.h5", params=PARAMS, options=RunOptions(**base)).run_from_rest(rest)
    assert f"resumed from {run.ckpt_path} at step {stopped_at}, phase load" in capsys.readouterr().out
    with h5py.File(tmp_path / "a.h5") as a, h5py.File(tmp_path / "b.h5") as b:
        np.testing.assert_array_equal(b["force/F"][:], a["force/F"][:])
        np.testing.assert_array_equal(b["energy/residual"][:], a["energy/residual"][:])
        assert b.attrs["rest_state_from"] == a.attrs["rest_state_from"] == os.path.abspath(rest)


def test_an_indenter_held_while_settling_never_moves_and_keys_its_own_rest_state(mesh_path, tmp_path, finished):
    """settle_indenter='held': the indenter is held where it was meshed from
    the first step (its top at zero velocity), so the loading starts from its
    meshed place exactly and whatever the keel pushes on it at rest is
    F_at_rest; the free settle of the same scene moved it. The settle reads
    the choice, so the two never share a rest state."""
    from icerubble.run import rest_states
    run = PunchThrough(mesh_path, tmp_path / "held.h5", params=dict(PARAMS, target_travel=5e-4, settle_indenter="held"),
                       options=RunOptions(threads=1, progress_every_s=1e9, vtu=False))
    meshed = run.scene.indenter_top_y()
    run.run()
    assert run.state.y_top0 == meshed                        # held from the first step: not a bit moved
    free, _ = finished
    assert free.state.y_top0 != meshed                       # the free indenter found its own balance
    assert np.isfinite(run.state.F_at_rest)
    with open_complete(tmp_path / "held.h5", "icerubble-run") as f:
        assert f["force/F"][0] == run.state.F_at_rest          # the record starts from the push at rest
    keys = [rest_states.settle_identity(r.params, r.scene.mesh, r.options, 1) for r in (run, free)]
    assert keys[0] != keys[1]


def _rewrite_source_hash(path, value):
    with h5py.File(path, "r+") as f:
        f.attrs["source_hash"] = value


def test_a_rest_state_made_by_other_code_starts_a_run_that_names_that_code(mesh_path, tmp_path):
    """A rest state is a run's starting state, as its mesh is, not a run it
    continues: one settled by other code (another build's bytes: a rest state
    made on the CPU's build, carried to a GPU machine that builds its own)
    starts the load, and the result names that code beside the rest state,
    also after the load is interrupted and resumed. The load's own
    checkpoint is continued only by the code that wrote it."""
    base, settler, rest = rest_state_of_another_run(mesh_path, tmp_path)
    _rewrite_source_hash(rest, "0123456789abcdef")
    run = PunchThrough(mesh_path, tmp_path / "b.h5", params=PARAMS,
                       options=RunOptions(stop_after_steps=settler.model.step_count + 200, **base))
    with pytest.raises(KeyboardInterrupt):
        run.run_from_rest(rest)
    with h5py.File(run.ckpt_path) as f:
        assert f["driver"].attrs["rest_state_source_hash"] == "0123456789abcdef"
        own = f.attrs["source_hash"]
    _rewrite_source_hash(run.ckpt_path, "fedcba9876543210")
    with pytest.raises(ValueError, match="a run continued by other code is not one run"):
        PunchThrough(mesh_path, tmp_path / "b.h5", params=PARAMS, options=RunOptions(**base)).run_from_rest(rest)
    _rewrite_source_hash(run.ckpt_path, own)
    PunchThrough(mesh_path, tmp_path / "b.h5", params=PARAMS, options=RunOptions(**base)).run_from_rest(rest)
    with open_complete(tmp_path / "b.h5") as f:
        assert f.attrs["rest_state_source_hash"] == "0123456789abcdef"
        assert f.attrs["rest_state_code_version"] == f.attrs["code_version"]   # one checkout; the hash rewritten
        assert f.attrs["source_hash"] == own
