"""A study on a SLURM cluster: one job-array task per table line.

The scheduler is SLURM's own (sbatch, squeue); nothing here schedules. The
study's folder (study_folder.py) also keeps each submitted job-array script,
submit_<k>.sh; a line's log holds every attempt of it, appended.

Each array task is one table line (the array index is the line number, as
yade-batch numbers them), run as

    YADE_BATCH=<table>:<line> yade -j<cpus-per-task> -n -x yade_scripts/punch_through.py

Preemption and time limits: the script asks for --requeue (SLURM requeues a
task whose node failed or that was preempted) and for SIGUSR1 some minutes
before the time limit (--signal); the run then writes its checkpoint and stops
(exit 75), and the task requeues itself; either way the next attempt resumes
from the checkpoint, bit for bit. A task cancelled by scancel stops the same
way on SIGTERM and is resumed by `icerubble study resubmit`.
"""
import os
import shlex
import shutil
import subprocess

from .folder import open_study, save_study, table_of
from .outcome import BATCH_SUMMARY, EXIT_INTERRUPTED, JOB_START, log_path
from .table_check import read_table
# seconds before the time limit at which the run is told to checkpoint and stop
SIGNAL_GRACE_S = 300


def _require(tool):
    if shutil.which(tool) is None:
        raise ValueError(f"{tool} is not on PATH: this machine cannot reach a SLURM cluster "
                         "(Debian: apt-get install slurm-client)")


def job_script(table, log_dir, out_dir, lines, punch_through, cpus_per_task=2, time=None,
               partition=None, account=None, extra=(), grace_s=SIGNAL_GRACE_S, workdir=None):
    """The sbatch script of a job array over `lines` of `table`."""
    q = shlex.quote
    opts = [f"--job-name=icerubble-{os.path.splitext(os.path.basename(table))[0]}",
            f"--array={','.join(str(n) for n in lines)}",
            f"--cpus-per-task={int(cpus_per_task)}",
            "--ntasks=1",
            f"--output={log_path(log_dir, '%a')}",
            "--open-mode=append",          # a requeued attempt appends to its line's log
            "--requeue",
            f"--signal=B:USR1@{int(grace_s)}"]
    if time:
        opts.append(f"--time={time}")
    if partition:
        opts.append(f"--partition={partition}")
    if account:
        opts.append(f"--account={account}")
    if workdir:
        opts.append(f"--chdir={workdir}")
    opts += list(extra)
    head = "\n".join(f"#SBATCH {o}" for o in opts)
    return f"""#!/bin/bash
{head}
# One punch-through run per array task: table line $SLURM_ARRAY_TASK_ID.
echo "{JOB_START}: job ${{SLURM_ARRAY_JOB_ID}}_${{SLURM_ARRAY_TASK_ID}} on $(hostname), $(date), restart ${{SLURM_RESTART_COUNT:-0}}"
export ICERUBBLE_OUT_DIR={q(out_dir)}
export OMP_NUM_THREADS=$SLURM_CPUS_PER_TASK
export YADE_BATCH={q(table)}:$SLURM_ARRAY_TASK_ID
yade -j$SLURM_CPUS_PER_TASK -n -x {q(punch_through)} &
run=$!
# USR1 (before the time limit, --signal) and TERM (scancel, preemption) go to
# the run: it writes its checkpoint and exits {EXIT_INTERRUPTED}
time_limit=0
trap 'time_limit=1; kill -USR1 $run 2>/dev/null' USR1
trap 'kill -TERM $run 2>/dev/null' TERM
while :; do
  wait $run; rc=$?
  kill -0 $run 2>/dev/null || break   # wait returned for a trapped signal: the run goes on
done
echo "{BATCH_SUMMARY} ================"
echo "status  : $rc"
if [ $rc -eq {EXIT_INTERRUPTED} ] && [ $time_limit -eq 1 ]; then
  # stopped for the time limit: back in the queue, to resume from the checkpoint
  scontrol requeue "${{SLURM_ARRAY_JOB_ID}}_${{SLURM_ARRAY_TASK_ID}}"
fi
exit $rc
"""


def submit(table, out, punch_through, sbatch_options=None, env=None):
    """Submit every line of `table` as one job array into a new study in
    `out`; returns (job id, study folder). sbatch_options: cpus_per_task,
    time, partition, account, extra (a list of further sbatch options)."""
    _require("sbatch")
    opts = dict(cpus_per_task=2, time=None, partition=None, account=None, extra=[])
    opts.update(sbatch_options or {})
    if not (isinstance(opts["cpus_per_task"], int) and opts["cpus_per_task"] >= 1):
        raise ValueError(f"--cpus-per-task = {opts['cpus_per_task']}: must be a whole number >= 1")
    log_dir, study = open_study(table, out, "slurm", sbatch=opts, punch_through=punch_through)
    if study["jobs"]:
        raise ValueError(f"{table} was already submitted into {study['out']} (jobs "
                         f"{', '.join(j['id'] for j in study['jobs'])}): `icerubble study status "
                         f"{study['out']}` tells each line's state, `icerubble study resubmit` sends "
                         "the lines without a complete result")
    lines = [n for n, row, _ in read_table(table_of(log_dir, study))[1] if row is not None]
    return send(log_dir, study, lines, env), log_dir


def send(log_dir, study, lines, env=None):
    """One job array over `lines` of the study's table; returns its job id."""
    if not lines:
        raise ValueError(f"{log_dir}: no line to submit")
    script = os.path.join(log_dir, f"submit_{len(study['jobs']) + 1}.sh")
    with open(script, "w") as f:
        f.write(job_script(table_of(log_dir, study), log_dir, study["out"], lines, study["punch_through"],
                           workdir=study["workdir"], **study["sbatch"]))
    r = subprocess.run(["sbatch", "--parsable", script], capture_output=True, text=True, env=env)
    if r.returncode != 0:
        raise ValueError(f"sbatch refused {script}: {r.stderr.strip() or r.stdout.strip()}")
    job = r.stdout.strip().split(";")[0]
    study["jobs"].append(dict(id=job, lines=list(lines)))
    save_study(log_dir, study)
    return job


def queue(job_ids, env=None):
    """{table line: scheduler state} of the tasks of `job_ids` SLURM still
    knows (pending, running, or recently ended)."""
    if not job_ids:
        return {}
    _require("squeue")
    states = {}
    for job in job_ids:   # one at a time: squeue refuses the whole list if one id has expired
        r = subprocess.run(["squeue", "-h", "-r", "-j", job, "-o", "%i %T"], capture_output=True, text=True,
                           env=env)
        if r.returncode != 0:
            if "Invalid job id" in r.stderr:
                continue
            raise ValueError(f"squeue failed: {r.stderr.strip()}")
        for ln in r.stdout.split("\n"):
            parts = ln.split()
            if len(parts) == 2 and "_" in parts[0]:
                task = parts[0].split("_", 1)[1]
                if task.isdigit():
                    states[int(task)] = parts[1]
    return states
