"""A one-node SLURM on this machine, for the cluster tests: munge, a
controller and a compute node on this host, configured in a temporary folder
and on ports of their own so nothing clashes with a SLURM already there. Both
daemons are reached at 127.0.0.1: a fresh machine need not resolve its own
host name (a debootstrap chroot or a container has no /etc/hosts entry for it).

    with LocalSlurm(tmp_dir) as cluster:
        env = cluster.env          # SLURM_CONF for sbatch, squeue, scancel, ...

Needs root and Debian's slurm-wlm and munge (make deps installs them). If
SLURM cannot start, SlurmStartError says why (the tests fail with it, they do
not skip).
"""
import os
import pwd
import shutil
import socket
import subprocess
import time

CTLD_PORT, SLURMD_PORT = 16817, 16818
MUNGE_DIRS = ("/etc/munge", "/var/run/munge", "/var/log/munge", "/var/lib/munge")


class SlurmStartError(RuntimeError):
    pass


def _munge_works():
    """A credential can be made: munged answers on its socket (a munged process
    elsewhere, e.g. outside a chroot, does not count)."""
    try:
        return subprocess.run(["munge", "-n"], capture_output=True, timeout=10).returncode == 0
    except (OSError, subprocess.TimeoutExpired):
        return False


def _ensure_munge():
    """munged running with a key (started once per machine; left running)."""
    if _munge_works():
        return
    for tool in ("munged", "slurmctld", "slurmd", "sbatch"):
        if shutil.which(tool) is None and not os.path.exists(f"/usr/sbin/{tool}"):
            raise SlurmStartError(f"{tool} is not installed (make deps installs slurm-wlm and munge)")
    try:
        munge = pwd.getpwnam("munge")
    except KeyError:
        raise SlurmStartError("there is no 'munge' user (is the munge package installed?)") from None
    for d in MUNGE_DIRS:
        os.makedirs(d, exist_ok=True)
        os.chown(d, munge.pw_uid, munge.pw_gid)
    key = "/etc/munge/munge.key"
    if not os.path.exists(key):
        with open(key, "wb") as f:
            f.write(os.urandom(1024))
    os.chown(key, munge.pw_uid, munge.pw_gid)
    os.chmod(key, 0o400)
    r = subprocess.run(["runuser", "-u", "munge", "--", "/usr/sbin/munged", "--force"],
                       capture_output=True, text=True)
    if r.returncode != 0 or not _munge_works():
        raise SlurmStartError(f"munged did not start or does not answer: {r.stderr.strip()}")


class LocalSlurm:
    def __init__(self, root):
        self.root = os.fspath(root)
        self.host = socket.gethostname().split(".")[0]
        self.conf = os.path.join(self.root, "slurm.conf")
        self.env = dict(os.environ, SLURM_CONF=self.conf)
        self.pids = []

    def _write_conf(self):
        for d in ("state", "spool", "log"):
            os.makedirs(os.path.join(self.root, d), exist_ok=True)
        cpus = os.cpu_count() or 1
        with open("/proc/meminfo") as f:
            mem_mib = int(f.readline().split()[1]) // 1024
        r = self.root
        with open(self.conf, "w") as f:
            f.write(f"""ClusterName=icerubble-test
SlurmctldHost={self.host}(127.0.0.1)
SlurmUser=root
SlurmctldPort={CTLD_PORT}
SlurmdPort={SLURMD_PORT}
AuthType=auth/munge
StateSaveLocation={r}/state
SlurmdSpoolDir={r}/spool
SlurmctldPidFile={r}/slurmctld.pid
SlurmdPidFile={r}/slurmd.pid
SlurmctldLogFile={r}/log/slurmctld.log
SlurmdLogFile={r}/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
JobAcctGatherType=jobacct_gather/none
MpiDefault=none
KillWait=30
MinJobAge=300
NodeName={self.host} NodeAddr=127.0.0.1 CPUs={cpus} RealMemory={max(mem_mib - 2048, 1024)} State=UNKNOWN
PartitionName=test Nodes={self.host} Default=YES MaxTime=INFINITE State=UP
""")

    def __enter__(self):
        _ensure_munge()
        self._write_conf()
        for daemon in ("/usr/sbin/slurmctld", "/usr/sbin/slurmd"):
            r = subprocess.run([daemon, "-f", self.conf], env=self.env, capture_output=True, text=True)
            if r.returncode != 0:
                self.__exit__()
                raise SlurmStartError(f"{daemon} did not start: {r.stderr.strip()} (log in {self.root}/log)")
        deadline = time.time() + 60
        while time.time() < deadline:
            r = subprocess.run(["sinfo", "-h", "-N", "-o", "%T"], env=self.env, capture_output=True, text=True)
            if r.returncode == 0 and r.stdout.strip() in ("idle", "mixed", "allocated"):
                return self
            time.sleep(0.5)
        state = r.stdout.strip() or r.stderr.strip()
        self.__exit__()
        raise SlurmStartError(f"the SLURM node did not come up within 60 s (sinfo: {state!r}; "
                              f"logs in {self.root}/log)")

    def __exit__(self, *exc):
        subprocess.run(["scancel", "--full", "--user=root"], env=self.env, capture_output=True)
        for name in ("slurmd.pid", "slurmctld.pid"):
            path = os.path.join(self.root, name)
            try:
                pid = int(open(path).read().split()[0])
                os.kill(pid, 15)
            except (OSError, ValueError, IndexError):
                continue
            for _ in range(100):   # wait until it is gone, so the next start finds its ports free
                try:
                    os.kill(pid, 0)
                except OSError:
                    break
                time.sleep(0.1)
        return False
