"""The ETA of a run's progress lines (icerubble/run/progress.py) is the true
remaining time, given the step rate: checked against a loading stepped with
the engine's own ramp, not against wall clocks."""
import io

import numpy as np
import pytest

from icerubble import engine
from icerubble.run.progress import Progress, loading_eta, ramp_travel, settle_eta_bound, time_to_travel

# the small scene's loading: Table 1's ramp (0.1 m/s over 2 s) to 30 mm, at its step
V_F, T, TARGET, DT = 0.1, 2.0, 0.03, 3e-6
RATE = 2000.0   # steps per wall second


def stepped_loading():
    """(times, travels) of a loading stepped at DT with the engine's speed law,
    the travel integrated step by step (midpoint speeds, as central
    differences move a driven node), independently of the closed form."""
    n = int(1.2 * time_to_travel(TARGET, V_F, T) / DT)
    t = DT * np.arange(n + 1)
    v_mid = engine.ramp_velocity(t[:-1] + 0.5 * DT, V_F, T)
    return t, np.concatenate([[0.0], np.cumsum(v_mid * DT)])


def test_the_ramps_travel_is_the_integral_of_the_engines_speed():
    t, y = stepped_loading()
    closed = np.array([ramp_travel(x, V_F, T) for x in t[::1000]])
    # midpoint rule error ~ v'' T dt^2 / 24: below a nanometre
    np.testing.assert_allclose(closed, y[::1000], rtol=0, atol=1e-9)
    for y_k in (1e-9, 1e-4, TARGET, 0.5 * V_F * T, 0.2):
        assert ramp_travel(time_to_travel(y_k, V_F, T), V_F, T) == pytest.approx(y_k, rel=1e-12)


@pytest.mark.parametrize("fraction", [0.01, 0.1, 0.5, 0.9, 0.999])
def test_the_loading_eta_is_the_time_left_at_the_step_rate(fraction):
    """At any point of the loading, the ETA at a steady step rate is the wall
    time of the steps left until the travel reaches the target, to 2 steps:
    one for rounding the last step up, one for the stepped travel's
    difference from the closed form (< 1 nm, under 1 % of the ~0.2 um one
    step travels near the target, so it moves the end by one step at most)."""
    t, y = stepped_loading()
    n_end = int(np.argmax(y >= TARGET))
    n = int(fraction * n_end)
    truth = (n_end - n) / RATE
    eta = loading_eta(t[n], TARGET, V_F, T, DT, RATE)
    assert abs(eta - truth) <= 2.0 / RATE, (eta, truth)


def test_extrapolating_the_travel_was_orders_of_magnitude_early_in_the_ramp():
    """Why the ETA is not travel left over travel rate: a tenth of the way into
    this loading (zero speed and acceleration at its start) that estimate is
    more than 100x the time left."""
    t, y = stepped_loading()
    n_end = int(np.argmax(y >= TARGET))
    n = n_end // 10
    wall = n / RATE
    extrapolated = (TARGET - y[n]) * wall / y[n]
    assert extrapolated > 100 * loading_eta(t[n], TARGET, V_F, T, DT, RATE)


def test_the_settle_bound_is_the_time_to_settle_max_time():
    """A settle that comes to rest before settle_max_time (or stops there)
    ends within the bound: its steps left are at most those to settle_max_time."""
    for t in (0.0, 0.7, 4.999):
        steps_to_max = np.ceil((5.0 - t) / DT)
        assert settle_eta_bound(t, 5.0, DT, RATE) == pytest.approx(steps_to_max / RATE)
    assert settle_eta_bound(6.0, 5.0, DT, RATE) == 0.0


def test_a_progress_line_without_a_step_rate_says_it_has_no_eta():
    out = io.StringIO()
    p = Progress("punch-through", step=100, every_s=1e9, stream=out,
                 eta=lambda t, rate: None if rate is None else f"{rate:.0f}")
    p.update(100, 0.0, "y_I 0 mm")          # no step since the start: no rate
    p.update(200, 0.1, "not printed")       # within every_s
    p.update(300, 0.2, lambda: "forced", force=True)
    lines = out.getvalue().splitlines()
    assert len(lines) == 2 and lines[0].endswith("ETA ?") and "forced" in lines[1]
    assert not lines[1].endswith("ETA ?")
