"""The loading of a punch-through run (paper section 2.4; docs/model.md §4).

The indenter top is driven down with a smooth ramp to v_final over ramp_time
(smooth_ramp_table) until its travel y_I reaches target_travel: F(y_I) every
<= 0.05 mm of travel, the energies every ENERGY_EVERY samples, u snapshots at
1, 5, 10, 20, ... mm (run/output.py). ``Loading(run).run()`` does it for a
PunchThrough ``run`` (run/punch_through_run.py), whose model, scene,
recorder and RunState it reads and moves on.
"""
import numpy as np

from .. import engine
from .progress import Progress, bond_text, loading_eta_text

# Indenter travel between two F samples at full speed (docs/model.md §4 asks <= 0.1 mm).
FORCE_SAMPLE_TRAVEL = 0.05e-3
ENERGY_EVERY = 10          # F samples per energy sample
RAMP_SAMPLES = 2001        # points of the tabulated indenter ramp
# Below this travel per sample (the first samples of the smooth ramp move
# ~1e-15 m, positions' round-off) the mean force work/travel is meaningless:
# such samples take the instantaneous force; 1 nm keeps the round-off < 1e-6.
MEAN_FORCE_MIN_TRAVEL = 1e-9


def smooth_ramp_table(t0, v_final, ramp_time, n=RAMP_SAMPLES):
    """The engine's smooth indenter ramp (engine.ramp_velocity: zero speed and
    acceleration at the start, so the rubble sees no inertial load, paper
    2.4) started at t0 instead of 0, as a velocity table."""
    if ramp_time <= 0.0:
        return np.array([t0, t0 + 1e-12]), np.array([0.0, v_final])
    tau = np.linspace(0.0, ramp_time, n)
    return t0 + tau, engine.ramp_velocity(tau, v_final, ramp_time)


class Loading:
    """The loading of `run`, from where its RunState stands (a resumed run
    goes on from its checkpoint's sample)."""

    def __init__(self, run):
        self.driver = run

    def run(self):
        r = self.driver
        m, p, o = r.model, r.params, r.options
        dt = m.dt
        chunk = max(1, int(FORCE_SAMPLE_TRAVEL / (p["v_final"] * dt)))
        prog = Progress("punch-through", m.step_count, every_s=o.progress_every_s,
                        eta=lambda t, rate: loading_eta_text(t, p["target_travel"], p["v_final"],
                                                             p["ramp_time"], dt, rate))
        # force samples of the load loop so far (the first row is the rest
        # force of settle): a resumed run samples the energy at the same ones
        k = len(r.recorder.force_rows) - 1
        # F is sampled as the mean force over each interval, work done on the
        # indenter / travel: the rubble rattles at its contact frequencies
        # (~1 kHz on the small scene), far above the sampling rate, and an
        # instantaneous sample would alias that into the record (a load cell
        # reads the mean). The instantaneous value is kept beside it.
        w_prev, y_prev = m.energies()["work_boundary"], r.travel()
        b_prev = r.scene.indenter_net_buoyancy()
        while True:
            e0 = m.timings()["element_steps"]
            m.step(chunk)
            r.state.load_steps += chunk
            r.state.load_element_steps += m.timings()["element_steps"] - e0
            y_I = r.travel()
            t_rel = m.time - r.state.t_load
            F_now = r.scene.indenter_force()
            w = m.energies()["work_boundary"]
            b_now = r.scene.indenter_net_buoyancy()   # linear in travel: mean of the ends
            F = F_now
            if y_I - y_prev > MEAN_FORCE_MIN_TRAVEL:
                F = (w - w_prev) / (y_I - y_prev) - 0.5 * (b_prev + b_now)
            w_prev, y_prev, b_prev = w, y_I, b_now
            r.recorder.force(t_rel, y_I, F, F_now)
            k += 1
            if k % ENERGY_EVERY == 0:
                r.recorder.energy(t_rel, m.energies())
            if r.recorder.wants_snapshot(y_I):
                r.output.snapshot(t_rel, y_I)
            prog.update(m.step_count, t_rel, lambda: self.text(y_I, F))
            if y_I >= p["target_travel"]:
                break
            r._maybe_checkpoint()
        prog.update(m.step_count, m.time - r.state.t_load, self.text(y_I, F), force=True)
        r.recorder.energy(m.time - r.state.t_load, m.energies())

    def text(self, y_I, F):
        r = self.driver
        return f"y_I {y_I * 1e3:8.3f} mm  F {F / 1e3:9.3f} kN/m  " + \
            bond_text(r.model, sleeping=r.state.phase == "load" and r.options.sleep is not None)
