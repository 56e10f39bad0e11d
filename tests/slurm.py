"""A single-node SLURM cluster in a temporary folder, for the scale-out test (`make test-cluster`).

Debian's `slurmctld`, `slurmd` and `munge` (installed by `.ci/run` where apt is available), run
as root without systemd: munged with its own key and socket, then slurmctld and slurmd in the
foreground (``-D``), each a child of the test, stopped by PID when the test ends, pass or fail.
No cgroups (``proctrack/linuxproc``, ``task/none``) and no accounting database: the plugin
follows jobs with ``squeue`` and the scheduler's record of every finished job is the job
completion log (``jobcomp/filetxt``), one line per job with its id, name, state and exit code.
Ports are picked free on 127.0.0.1, so the cluster touches nothing outside its folder.

Its configuration is not at /etc/slurm, so clients find it through ``SLURM_CONF``; but the
slurm plugin's job step drops every ``SLURM_*`` variable before its inner ``srun``, so the
cluster's ``bin/`` holds an ``srun`` that sets it and runs the real one, first on ``PATH``.
"""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import time
from dataclasses import dataclass, field
from pathlib import Path

DAEMONS = ("/usr/sbin/munged", "/usr/sbin/slurmctld", "/usr/sbin/slurmd", "/usr/sbin/mungekey")
CLIENTS = ("sbatch", "squeue", "scancel", "srun", "sinfo")
#: The controller must run on the host it names: the machine's short host name (also the node's).
NODE = socket.gethostname().split(".")[0]
PARTITION = "cloth"


def missing() -> str | None:
    """Why a cluster cannot start here (one line), or None."""
    if os.geteuid() != 0:
        return "the SLURM test runs its daemons as root"
    absent = [path for path in DAEMONS if not os.access(path, os.X_OK)]
    absent += [name for name in CLIENTS if shutil.which(name) is None]
    if absent:
        return f"SLURM is not installed ({', '.join(absent)}; Debian: slurmctld slurmd munge)"
    return None


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@dataclass
class Cluster:
    """A running single-node cluster; ``env`` is what its clients need (``SLURM_CONF``)."""

    root: Path
    env: dict[str, str]
    completions: Path
    processes: list[subprocess.Popen] = field(default_factory=list)

    def jobs(self) -> list[dict[str, str]]:
        """Finished jobs from the completion log: JobId, JobName, JobState, ExitCode, ..."""
        if not self.completions.is_file():
            return []
        records = []
        for line in self.completions.read_text().splitlines():
            pairs = (item.split("=", 1) for item in line.split() if "=" in item)
            records.append(dict(pairs))
        return records

    def queue(self) -> list[tuple[str, ...]]:
        """(job id, name, state, comment) of the jobs in the queue."""
        out = subprocess.run(
            ["squeue", "--noheader", "--format=%i|%j|%T|%k"],
            env=self.env,
            capture_output=True,
            text=True,
            check=True,
        ).stdout
        return [tuple(line.split("|")) for line in out.splitlines() if line.strip()]

    def stop(self) -> None:
        for process in reversed(self.processes):
            if process.poll() is None:
                process.send_signal(signal.SIGTERM)
        deadline = time.monotonic() + 10
        for process in reversed(self.processes):
            try:
                process.wait(max(deadline - time.monotonic(), 0.1))
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()


def start(root: Path, cpus: int, memory_mb: int) -> Cluster:
    """Start munged, slurmctld and slurmd under ``root``; raise RuntimeError (with the logs'
    tails) if the node is not idle within 30 s. The caller stops the cluster."""
    for name in ("munge", "state", "spool", "log"):
        (root / name).mkdir(parents=True, exist_ok=True)
    os.chmod(root / "munge", 0o700)
    key, munge_socket = root / "munge" / "munge.key", root / "munge" / "socket"
    subprocess.run(["/usr/sbin/mungekey", "--create", "--keyfile", str(key)], check=True)
    conf = root / "slurm.conf"
    completions = root / "log" / "jobcomp.txt"
    conf.write_text(
        "\n".join(
            [
                "ClusterName=cloth",
                f"SlurmctldHost={NODE}(127.0.0.1)",
                f"SlurmctldPort={_free_port()}",
                f"SlurmdPort={_free_port()}",
                "SlurmUser=root",
                "SlurmdUser=root",
                f"AuthInfo=socket={munge_socket}",
                f"StateSaveLocation={root / 'state'}",
                f"SlurmdSpoolDir={root / 'spool'}",
                f"SlurmctldPidFile={root / 'slurmctld.pid'}",
                f"SlurmdPidFile={root / 'slurmd.pid'}",
                f"SlurmctldLogFile={root / 'log' / 'slurmctld.log'}",
                f"SlurmdLogFile={root / 'log' / 'slurmd.log'}",
                "ProctrackType=proctrack/linuxproc",
                "TaskPlugin=task/none",
                "JobAcctGatherType=jobacct_gather/none",
                "AccountingStorageType=accounting_storage/none",
                "JobCompType=jobcomp/filetxt",
                f"JobCompLoc={completions}",
                "SchedulerType=sched/backfill",
                "SelectType=select/cons_tres",
                "SelectTypeParameters=CR_Core_Memory",
                "ReturnToService=2",
                "MailProg=/bin/true",
                "MinJobAge=600",
                "KillWait=5",
                f"NodeName={NODE} NodeAddr=127.0.0.1 CPUs={cpus} RealMemory={memory_mb} "
                "State=UNKNOWN",
                f"PartitionName={PARTITION} Nodes={NODE} Default=YES MaxTime=INFINITE State=UP",
                "",
            ]
        )
    )
    shims = root / "bin"
    shims.mkdir(exist_ok=True)
    srun = shims / "srun"
    srun.write_text(f'#!/bin/sh\nSLURM_CONF={conf} exec {shutil.which("srun")} "$@"\n')
    srun.chmod(0o755)
    env = {**os.environ, "SLURM_CONF": str(conf), "PATH": f"{shims}:{os.environ['PATH']}"}
    cluster = Cluster(root, env, completions)
    log = root / "log"

    def launch(*command: str, name: str) -> None:
        with open(log / f"{name}.out", "wb") as out:
            process = subprocess.Popen(
                command, env=env, stdout=out, stderr=subprocess.STDOUT, start_new_session=True
            )
            cluster.processes.append(process)

    try:
        launch(
            "/usr/sbin/munged",
            "--foreground",
            "--force",
            f"--key-file={key}",
            f"--socket={munge_socket}",
            f"--pid-file={root / 'munge' / 'munged.pid'}",
            f"--seed-file={root / 'munge' / 'seed'}",
            f"--log-file={log / 'munged.log'}",
            name="munged",
        )
        _wait(lambda: munge_socket.exists(), 10, "munged", log)
        launch("/usr/sbin/slurmctld", "-D", "-i", "-f", str(conf), name="slurmctld")
        launch("/usr/sbin/slurmd", "-D", "-N", NODE, "-f", str(conf), name="slurmd")
        _wait(lambda: _idle(env), 30, "the node", log)
    except BaseException:
        cluster.stop()
        raise
    return cluster


def _idle(env: dict[str, str]) -> bool:
    out = subprocess.run(
        ["sinfo", "--noheader", "--format=%T"], env=env, capture_output=True, text=True
    )
    return out.returncode == 0 and out.stdout.strip() in ("idle", "mixed", "allocated")


def _wait(ready, seconds: float, what: str, log: Path) -> None:
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        if ready():
            return
        time.sleep(0.3)
    tails = []
    for path in sorted(log.glob("*")):
        lines = path.read_text(errors="replace").splitlines()[-5:]
        tails.append(f"--- {path.name}\n" + "\n".join(lines))
    raise RuntimeError(f"{what} did not come up in {seconds:.0f} s\n" + "\n".join(tails))
