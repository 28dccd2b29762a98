"""Progress lines for long runs: step, simulated time, what the phase is
measured by, wall time and an ETA that says what kind of estimate it is.

Loading: the ETA is the steps left until the indenter reaches the target
travel, under its known displacement law, over the measured step rate. It
used to extrapolate the travel done per wall second, which the smooth ramp
makes wrong by orders of magnitude: the indenter starts with zero speed and
acceleration, its travel grows as v_f pi^2 t^4 / (6 T^3) at first, so a tenth
of the way into a loading that ends inside the ramp it had done ~1e-4 of the
travel and the estimate was ~1000x the truth (22,560 s printed for a small-scene
loading that took 137 s). Steps, unlike travel, come at a steady rate.

Settling: how long the scene takes to come to rest is not known ahead, so
the ETA is an upper bound, the time to settle_max_time at the step rate
(past it the run stops with an error), printed as "<= ... (settle_max_time)".
"""
import math
import sys
import time


def ramp_travel(t, v_final, ramp_time):
    """Travel [m] at time t [s] after the start of the smooth ramp
    v = v_f (t/T - sin(2 pi t/T) / (2 pi)) for t < T, v_f after
    (engine ramp_velocity, docs/model.md §4), integrated in closed form."""
    if t <= 0.0:
        return 0.0
    T = ramp_time
    if T <= 0.0:
        return v_final * t
    if t >= T:
        return v_final * (0.5 * T + (t - T))
    return v_final * (t * t / (2.0 * T) + T * (math.cos(2.0 * math.pi * t / T) - 1.0) / (4.0 * math.pi ** 2))


def time_to_travel(y, v_final, ramp_time):
    """The time [s] from the start of the ramp at which the travel is y [m]
    (the inverse of ramp_travel: bisection inside the ramp, where the speed
    is >= 0 so the travel only grows)."""
    if y <= 0.0:
        return 0.0
    T = ramp_time
    if T <= 0.0:
        return y / v_final
    y_ramp = 0.5 * v_final * T
    if y >= y_ramp:
        return T + (y - y_ramp) / v_final
    lo, hi = 0.0, T
    for _ in range(100):   # 2^-100 of T: below any step
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ramp_travel(mid, v_final, T) < y else (lo, mid)
    return hi


def loading_eta(t, target_travel, v_final, ramp_time, dt, steps_per_s):
    """Wall seconds left of a loading at time t [s] after its start: the
    steps of size dt until the ramp's travel reaches target_travel, at
    steps_per_s. None without a rate yet."""
    if not steps_per_s or steps_per_s <= 0.0:
        return None
    steps = max(0, math.ceil((time_to_travel(target_travel, v_final, ramp_time) - t) / dt))
    return steps / steps_per_s


def settle_eta_bound(t, max_time, dt, steps_per_s):
    """Upper bound of the wall seconds left of a settle at simulated time t
    [s] since its start: the steps to max_time at steps_per_s."""
    if not steps_per_s or steps_per_s <= 0.0:
        return None
    return max(0, math.ceil((max_time - t) / dt)) / steps_per_s


class Progress:
    """Prints at most every `every_s` wall seconds (and when forced):

        [label] step N  t T s  <text>  wall W s  ETA <eta>

    step: the step count when the phase starts (for the step rate); text:
    a string or a callable making it (called only for a printed line). eta:
    callable (t, steps per wall second) -> text, or None. The step rate is
    measured over the interval since the previous line (the first: since
    construction), so it follows a step cost that changes as the rubble
    breaks up or the far field falls asleep."""

    def __init__(self, label, step, every_s=10.0, eta=None, stream=None):
        self.label = label
        self.every = float(every_s)
        self.eta = eta
        self.stream = stream or sys.stdout
        self.t0 = self.last = time.perf_counter()
        self.last_step = step
        self.printed = False

    def update(self, step, t, text="", force=False):
        now = time.perf_counter()
        if self.printed and not force and now - self.last < self.every:
            return
        rate = (step - self.last_step) / (now - self.last) if now > self.last and step > self.last_step else None
        self.last, self.last_step, self.printed = now, step, True
        eta = self.eta(t, rate) if self.eta is not None else None
        text = text() if callable(text) else text   # made only when printed
        print(f"[{self.label}] step {step:>10d}  t {t:8.4f} s  {text}  wall {now - self.t0:7.0f} s"
              f"  ETA {eta or '?'}", file=self.stream, flush=True)


def loading_eta_text(t, target_travel, v_final, ramp_time, dt, steps_per_s):
    s = loading_eta(t, target_travel, v_final, ramp_time, dt, steps_per_s)
    return None if s is None else f"{s:.0f} s"


def settle_eta_text(t, max_time, dt, steps_per_s):
    s = settle_eta_bound(t, max_time, dt, steps_per_s)
    return None if s is None else f"<= {s:.0f} s (settle_max_time {max_time:g} s)"


def bond_text(model, sleeping=False):
    """The bond points split and failed so far, and (sleeping far field on)
    the share of triangles awake: the tail of a progress line."""
    c = model.bonds.counts
    text = f"bonds split {c['split']}/{c['points']} failed {c['failed']}"
    if sleeping:
        z = model.sleep_counts()
        text += f"  triangles awake {100.0 * z['awake_triangles'] / z['triangles']:.0f} %"
    return text
