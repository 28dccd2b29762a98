"""The shape every punch-through run has, whichever model runs it (the
FEM-DEM engine, run/punch_through_run.py; the rigid blocks on YADE's engines,
rigid_dem/punch_through.py): start, take up its own checkpoint or begin
afresh, settle unless already past it, load, write the result, remove the
checkpoint. A run sent SIGTERM or SIGUSR1 (what a scheduler sends before it
stops a job) or SIGINT (Ctrl-C) notes it, writes its checkpoint at the end
of its chunk of steps and stops with RunInterrupted (the YADE scripts then
exit 75): running it again resumes it.
"""
import contextlib
import os
import signal
import threading

# What a scheduler sends before it stops a run: SIGTERM (scancel, preemption,
# node shutdown; SLURM follows with SIGKILL after KillWait, 30 s by default)
# and SIGUSR1 (sbatch --signal, some minutes before the time limit); and
# SIGINT, Ctrl-C: a person stopping a run wants to keep the hours it has
# computed as much as a scheduler does.
STOP_SIGNALS = (signal.SIGTERM, signal.SIGUSR1, signal.SIGINT)


class RunInterrupted(RuntimeError):
    """The run stopped on a signal after writing its checkpoint: running it
    again with resume=True continues it, bit for bit."""


@contextlib.contextmanager
def catching_stop_signals(run):
    """While inside: SIGTERM, SIGUSR1 and SIGINT only set run._stop_signal
    (the run checks it between its chunks of steps); the previous handlers
    come back after. A second Ctrl-C while the first is pending raises
    KeyboardInterrupt at once, as Python's own handler (the last checkpoint
    on disk stays whole: it is written atomically). Outside the main thread
    (where Python takes no handlers) nothing is caught."""
    run._stop_signal = None

    def note(signum, frame):
        if signum == signal.SIGINT and run._stop_signal is not None:
            raise KeyboardInterrupt("Ctrl-C twice: stopped at once, without a checkpoint of this moment")
        run._stop_signal = signum
    catch = threading.current_thread() is threading.main_thread()
    previous = {s: signal.signal(s, note) for s in STOP_SIGNALS} if catch else {}
    try:
        yield
    finally:
        for s, h in previous.items():
            signal.signal(s, h)


class Driver:
    """A punch-through run's order of phases. A model's run provides:

    - ``ckpt_path``, ``out_path``;
    - ``start()``: what precedes either path (the rigid model builds its YADE scene);
    - ``resume(path)``: take up its own checkpoint;
    - ``begin()``: what a run not resumed does first (the FEM-DEM run loads a
      shared rest state where there is one);
    - ``settled()``: whether the settle is behind it;
    - ``settle()``, ``load()``, ``write()``: the phases; the result's wall
      times are each model's own record, counted across resumes.
    """

    def start(self):
        pass

    def begin(self):
        pass

    def run(self, resume=False):
        # a signal only sets a flag: the run stops at the end of its chunk of
        # steps (< 1 s), where the state is whole, after writing its checkpoint
        with catching_stop_signals(self):
            self.start()
            if resume and os.path.exists(self.ckpt_path):
                self.resume(self.ckpt_path)
            else:
                self.begin()
            if not self.settled():
                self.settle()
            self.load()
            self.write()
        if os.path.exists(self.ckpt_path):
            os.remove(self.ckpt_path)
        return self.out_path
