"""SLURM for real: a one-node SLURM cluster on this machine runs part of the quick workflow with
``profiles/slurm``, and its tables equal a local run's byte for byte.

The test installs nothing (``bash scripts/setup.sh --cluster`` installs Debian's ``slurm-wlm`` and
``munge`` as root). It writes a single-node ``slurm.conf`` for this host into a temporary folder
(CPUs and RealMemory of this machine, no accounting database, ``MinJobAge=3600`` so that
finished jobs stay visible to ``squeue`` during and after the run), creates a MUNGE key, starts
``munged``, ``slurmctld`` and ``slurmd`` in the foreground on private sockets and ports, and stops
exactly those processes (by PID) afterwards. Snakemake then runs the linear sweeps (eigenvalues,
PS, LA, LN of four models, RD maps) and Table 4.1's model columns of ``config/quick.yaml``:

- locally: ``snakemake -j2`` into ``<tmp>/local``;
- on SLURM: ``snakemake --executor slurm --profile profiles/slurm`` into ``<tmp>/slurm``, with
  ``--slurm-status-command squeue`` (without slurmdbd ``sacct`` cannot report job states) and a
  short first status poll.

Asserted: every non-local job was a SLURM job (its SLURM job id in Snakemake's log, in
``squeue --states=all`` as COMPLETED with the rule's name in the comment, and in slurmctld's log
with exit status 0), the local rule (``linear_table_4_1``, rules/cluster.smk) was not, and every
CSV table of the SLURM run equals the local run's byte for byte (same code, same machine,
deterministic algorithms: any difference would mean the jobs ran different code or config).

Skipped with the reason without root or the packages, unless ``PEDALREPRO_REQUIRE_CLUSTER=1``
(set by .ci/run), which makes it fail instead.
"""

from __future__ import annotations

import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest
import yaml

from pedalrepro import paths

pytestmark = pytest.mark.cluster

DAEMONS = {"munged": "/usr/sbin/munged", "slurmctld": "/usr/sbin/slurmctld",
           "slurmd": "/usr/sbin/slurmd"}
CLIENTS = ["sbatch", "squeue", "scontrol", "srun", "munge", "unmunge"]
PARTITION = "main"  # the profile's default slurm_partition (profiles/slurm/config.yaml)

# The subset of config/quick.yaml: tables whose jobs are the linear sweeps (SLURM) plus one local
# rule. Expected SLURM jobs: linear_eigen, linear_ps, linear_time_la, linear_time_ln, linear_rd;
# local: linear_table_4_1 (which also writes the moved-inputs table of pedalrepro.sensitivity).
TARGET_TABLES = ["eigen_summary", "rd_summary", "table_4_1_model", "table_4_1_model_moved_inputs"]
SLURM_RULES = {"linear_eigen": 1, "linear_ps": 1, "linear_time_la": 1, "linear_time_ln": 1,
               "linear_rd": 1}
LOCAL_RULES = {"linear_table_4_1"}


def _missing() -> str | None:
    if os.name != "posix" or os.geteuid() != 0:
        return "needs root to start slurmd and munged (CI runs as root)"
    absent = [p for p in DAEMONS.values() if not os.access(p, os.X_OK)]
    absent += [c for c in CLIENTS if shutil.which(c) is None]
    if absent:
        return (f"SLURM/MUNGE not installed ({', '.join(absent)} missing): "
                "bash scripts/setup.sh --cluster")
    return None


def _require_cluster() -> None:
    reason = _missing()
    if reason:
        if os.environ.get("PEDALREPRO_REQUIRE_CLUSTER") == "1":
            pytest.fail(f"cluster test required (PEDALREPRO_REQUIRE_CLUSTER=1) but {reason}")
        pytest.skip(reason)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _real_memory_mb() -> int:
    """Total memory in MB as slurmd counts it, minus 5 % so slurmd never finds it too low."""
    total_kb = next(int(line.split()[1]) for line in Path("/proc/meminfo").read_text().splitlines()
                    if line.startswith("MemTotal:"))
    return int(total_kb / 1024 * 0.95)


class LocalSlurm:
    """munged + slurmctld + slurmd for this host only, everything under ``root``."""

    def __init__(self, root: Path):
        self.root = root
        self.node = socket.gethostname().split(".")[0]
        self.procs: dict[str, subprocess.Popen] = {}
        self.conf = root / "slurm.conf"
        self.socket = root / "munge" / "munge.socket"
        self.ctld_log = root / "log" / "slurmctld.log"
        # snakemake-executor-plugin-slurm-jobstep (0.6.1) drops every SLURM_* variable, SLURM_CONF
        # included, before its `srun` inside the job; a real cluster's srun then finds
        # /etc/slurm/slurm.conf (or a configless slurmd), this private cluster's config is not
        # there, so an `srun` first on PATH puts SLURM_CONF back and runs the real srun.
        self.bin = root / "bin"
        self.env = dict(os.environ, SLURM_CONF=str(self.conf),
                        PATH=f"{self.bin}{os.pathsep}{os.environ.get('PATH', '')}")

    def write_config(self) -> None:
        for d in ("munge", "log", "state", "spool", "run", "bin"):
            (self.root / d).mkdir(mode=0o700, parents=True, exist_ok=True)
        srun = self.bin / "srun"
        srun.write_text(f"#!/bin/sh\nSLURM_CONF={self.conf} exec {shutil.which('srun')} \"$@\"\n")
        srun.chmod(0o700)
        key = self.root / "munge" / "munge.key"
        key.write_bytes(os.urandom(1024))
        key.chmod(0o400)
        r = self.root
        self.ctld_port = _free_port()
        self.conf.write_text(f"""\
# One-node SLURM for tests/workflow/test_cluster.py (temporary; no accounting database).
ClusterName=pedalrepro-test
SlurmctldHost={self.node}(127.0.0.1)
SlurmctldPort={self.ctld_port}
SlurmdPort={_free_port()}
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket={self.socket}
StateSaveLocation={r}/state
SlurmdSpoolDir={r}/spool
SlurmctldPidFile={r}/run/slurmctld.pid
SlurmdPidFile={r}/run/slurmd.pid
SlurmctldLogFile={self.ctld_log}
SlurmdLogFile={r}/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU_Memory
ReturnToService=2
MinJobAge=3600
InactiveLimit=0
KillWait=5
Waittime=0
NodeName={self.node} NodeAddr=127.0.0.1 CPUs={os.cpu_count()} RealMemory={_real_memory_mb()} \
State=UNKNOWN
PartitionName={PARTITION} Nodes={self.node} Default=YES MaxTime=INFINITE State=UP
""")

    def _start(self, name: str, args: list[str]) -> None:
        log = open(self.root / "log" / f"{name}.out", "w")  # noqa: SIM115 - closed with the proc
        self.procs[name] = subprocess.Popen([DAEMONS[name], *args], env=self.env, stdout=log,
                                            stderr=subprocess.STDOUT, start_new_session=True)

    def _wait(self, what: str, check, timeout_s: float = 30.0) -> None:
        deadline = time.monotonic() + timeout_s
        while time.monotonic() < deadline:
            for name, proc in self.procs.items():
                if proc.poll() is not None:
                    out = (self.root / "log" / f"{name}.out").read_text()
                    raise RuntimeError(f"{name} exited ({proc.returncode}) while waiting for "
                                       f"{what}:\n{out}\n{self.logs()}")
            if check():
                return
            time.sleep(0.5)
        raise RuntimeError(f"timed out waiting for {what}\n{self.logs()}")

    def _run(self, *cmd: str) -> subprocess.CompletedProcess:
        return subprocess.run(cmd, env=self.env, capture_output=True, text=True, timeout=60)

    def start(self) -> None:
        self.write_config()
        r = self.root / "munge"
        self._start("munged", ["--foreground", "--force", f"--socket={self.socket}",
                               f"--key-file={r}/munge.key", f"--pid-file={r}/munged.pid",
                               f"--seed-file={r}/munged.seed", f"--log-file={r}/munged.log"])
        self._wait("munged", lambda: self.socket.exists()
                   and subprocess.run(f"munge -n -S {self.socket} | unmunge -S {self.socket}",
                                      shell=True, capture_output=True).returncode == 0)
        self._start("slurmctld", ["-D", "-i", "-f", str(self.conf)])
        self._wait("slurmctld", lambda: self._run("scontrol", "ping").returncode == 0
                   and "UP" in self._run("scontrol", "ping").stdout)
        self._start("slurmd", ["-D", "-f", str(self.conf), "-N", self.node])
        self._wait("the node to be idle", lambda: "idle" in self._run(
            "sinfo", "-h", "-N", "-o", "%t").stdout, timeout_s=60)

    def stop(self) -> None:
        """Stop the daemons this object started (by PID), slurmd first."""
        for name in ("slurmd", "slurmctld", "munged"):
            proc = self.procs.get(name)
            if proc is None or proc.poll() is not None:
                continue
            proc.send_signal(signal.SIGTERM)
            try:
                proc.wait(timeout=20)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait(timeout=10)

    def logs(self) -> str:
        out = []
        for f in sorted((self.root / "log").glob("*")):
            out.append(f"--- {f.name}\n" + "\n".join(f.read_text().splitlines()[-30:]))
        return "\n".join(out)


@pytest.fixture(scope="module")
def slurm(tmp_path_factory):
    _require_cluster()
    cluster = LocalSlurm(tmp_path_factory.mktemp("slurm"))
    try:
        cluster.start()
        yield cluster
    finally:
        cluster.stop()


def _snakemake(targets: list[str], args: list[str], env: dict,
               log: Path) -> subprocess.CompletedProcess:
    env = dict(env)
    env["PATH"] = str(Path(sys.executable).parent) + os.pathsep + env.get("PATH", "")
    env.pop("PEDALREPRO_RESULTS", None)
    cmd = [sys.executable, "-m", "snakemake", *targets, "--configfile", "config/quick.yaml",
           *args]
    start = time.perf_counter()
    proc = subprocess.run(cmd, cwd=paths.ROOT, env=env, capture_output=True, text=True,
                          timeout=1800)
    log.write_text(f"$ {' '.join(cmd)}\n# {time.perf_counter() - start:.1f} s, exit "
                   f"{proc.returncode}\n{proc.stdout}{proc.stderr}")
    return proc


def _local_reference(request, tmp_path: Path) -> Path:
    """Results folder of a local run of config/quick.yaml holding the target tables.

    When this pytest session also runs the end-to-end workflow test, its local quick run (fixture
    ``quick_workflow``, the whole quick profile with ``-j2``) is the reference, which saves a
    second local run in CI; otherwise (``pytest -m cluster``) the target tables are built
    locally here."""
    if any(item.get_closest_marker("workflow") for item in request.session.items):
        quick = request.getfixturevalue("quick_workflow")
        if quick.returncode == 0:
            return quick.results
    local = tmp_path / "local"
    ran = _snakemake(_targets(local), ["-j2", "--config", f"results_dir={local}"], os.environ,
                     tmp_path / "local.log")
    assert ran.returncode == 0, (tmp_path / "local.log").read_text()[-4000:]
    return local


def _targets(results: Path) -> list[str]:
    return [str(results / "tables" / f"{t}.csv") for t in TARGET_TABLES]


def test_slurm_runs_the_linear_sweeps_and_tables_match_a_local_run(slurm, request, tmp_path):
    local = _local_reference(request, tmp_path)
    remote = tmp_path / "slurm"

    slurm_logs = tmp_path / "slurm_logs"
    ran = _snakemake(_targets(remote), ["--executor", "slurm", "--profile", "profiles/slurm",
                      "--config", f"results_dir={remote}",
                      "--slurm-status-command", "squeue",
                      "--slurm-init-seconds-before-status-checks", "5",
                      "--slurm-no-account", "--slurm-logdir", str(slurm_logs),
                      "--slurm-keep-successful-logs", "--latency-wait", "5"],
                     slurm.env, tmp_path / "slurm.log")
    log = ran.stdout + ran.stderr
    assert ran.returncode == 0, log[-4000:] + "\n" + slurm.logs()

    # SLURM ran every non-local job: Snakemake's log names one SLURM job id per submitted job ...
    submitted = [int(j) for j in re.findall(r"submitted with SLURM jobid (\d+)", log)]
    assert len(submitted) == sum(SLURM_RULES.values()), log[-4000:]
    assert len(set(submitted)) == len(submitted)
    # ... squeue (finished jobs stay listed for MinJobAge=3600 s) shows each COMPLETED, with the
    # rule's name in the comment and the runtime (minutes) and mem_mb the profile sets for it ...
    queue = slurm._run("squeue", "--states=all", "--noheader", "--format=%i|%T|%l|%m|%k").stdout
    jobs = {int(i): (state, limit, mem, comment) for i, state, limit, mem, comment in
            (line.split("|", 4) for line in queue.splitlines() if line.strip())}
    assert set(jobs) == set(submitted), queue
    assert {j[0] for j in jobs.values()} == {"COMPLETED"}, queue
    rules = [re.match(r"rule_([a-z0-9_]+?)(_wildcards_.*)?$", j[3]).group(1)
             for j in jobs.values()]
    assert {r: rules.count(r) for r in set(rules)} == SLURM_RULES, queue
    assert not LOCAL_RULES & set(rules)
    rule_of = dict(zip(jobs, rules, strict=True))
    profile = yaml.safe_load((paths.ROOT / "profiles" / "slurm" / "config.yaml").read_text())
    for rule, (_, limit, mem, _) in zip(rules, jobs.values(), strict=True):
        want = {**profile["default-resources"], **profile["set-resources"].get(rule, {})}
        assert (limit, mem) == (f"{int(want['runtime'])}:00", f"{int(want['mem_mb'])}M"), (
            rule, queue)
    # ... and slurmctld logged each one finishing with exit status 0 on our node.
    ctld = slurm.ctld_log.read_text()
    for job in submitted:
        assert re.search(rf"_job_complete: JobId={job} WEXITSTATUS 0", ctld), ctld[-3000:]
    # The SLURM job logs (kept: <logdir>/rule_<rule>/[<wildcards>/]<job id>.log), one per job
    # id, each from a Snakemake that ran that rule's one job to the end inside the allocation.
    job_logs = {int(p.stem): p for p in slurm_logs.rglob("*.log")}
    assert set(job_logs) == set(submitted)
    for job, path in job_logs.items():
        text = path.read_text()
        rule = path.relative_to(slurm_logs).parts[0].removeprefix("rule_")
        assert rule == rule_of[job], (job, rule, queue)
        assert f"Finished jobid: 0 (Rule: {rule})" in text and "1 of 1 steps (100%) done" in text, (
            text[-2000:])

    # Every table of the SLURM run equals the local run's byte for byte.
    tables = sorted(p.relative_to(remote) for p in (remote / "tables").rglob("*.csv"))
    assert {p.stem for p in tables} == set(TARGET_TABLES)
    differ = [str(p) for p in tables if (local / p).read_bytes() != (remote / p).read_bytes()]
    assert not differ, f"tables differ between the SLURM run and the local run {local}: {differ}"
    print(f"SLURM ran {len(submitted)} jobs (ids {sorted(submitted)}); {len(tables)} tables equal "
          f"to the local run's ({local}) byte for byte")
