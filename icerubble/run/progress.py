"""Progress lines for long runs: steps, simulated time, y_I, F and ETA."""
import sys
import time


class Progress:
    """Prints at most every `every_s` wall seconds. The ETA extrapolates the
    indenter travel rate of the run so far (travel, not steps, is what ends a
    punch-through run).
    """

    def __init__(self, target_travel, every_s=10.0, stream=None, label="punch-through"):
        self.target = float(target_travel)
        self.every = float(every_s)
        self.stream = stream or sys.stdout
        self.label = label
        self.t0 = time.perf_counter()
        self.last = -1e30
        self.start_travel = None

    def update(self, step, t, y_I, F=None, force=False, extra=None):
        now = time.perf_counter()
        if not force and now - self.last < self.every:
            return
        self.last = now
        if self.start_travel is None:
            self.start_travel = y_I
        wall = now - self.t0
        done = y_I - self.start_travel
        left = max(self.target - y_I, 0.0)   # the last step overshoots the target
        if done > 0 and wall > 0:
            eta = f"{left * wall / done:8.0f} s"
        else:
            eta = "       ? s"
        f_txt = "" if F is None else f"  F {F / 1e3:9.3f} kN/m"
        if extra is not None:
            f_txt += "  " + (extra() if callable(extra) else str(extra))
        print(f"[{self.label}] step {step:>10d}  t {t:8.4f} s  y_I {y_I * 1e3:8.3f} mm{f_txt}"
              f"  wall {wall:7.0f} s  ETA {eta}", file=self.stream, flush=True)
