"""One local Ray cluster for every Ray test of a session, shared by pytest-xdist's workers,
so that the tests pay Ray's start and stop once, not once per command or per worker: `ray
start --head`, started by the first worker that needs it and stopped by the last that used
it (a JSON file under a lock in the workers' common temporary folder keeps its address and
users), with two CPUs per worker, so that tests running at once never wait for each
other's env runners. tests/conftest.py makes `ray_cluster` a fixture of every test folder.
The cluster runs without token authentication (RAY_AUTH_MODE=disabled, also in the
environment of the commands that join it), so that a test's own process, which imported
Ray already, joins it too; tests/cli/test_train_ray.py's two-node cluster has a token.

Every Ray instance of the tests listens on 127.0.0.1 only: importing this module sets
Ray's switch for an instance of one machine (LOOPBACK_ONLY, read when Ray is imported) in
the test process, and so in every command it starts. Ray then gives its nodes the address
127.0.0.1 and binds its servers to it (without the switch, Ray on Linux turns 127.0.0.1
into the machine's interface address, listens on every interface, and reaches a cluster's
127.0.0.1 through that address, where a loopback cluster does not listen). The session's
cluster is started with `--node-ip-address 127.0.0.1` too. A cluster of several nodes
needs the switch off (`ray start --address` refuses to join otherwise): tests of one set
LOOPBACK_ONLY to "1" in their commands' environment.

    def test_x(ray_cluster):
        composer("train", ..., "--address", ray_cluster.address, env=ray_cluster.environment())
"""

from __future__ import annotations

import contextlib
import dataclasses
import fcntl
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from composer.cli.engines.ray.instance import LOOPBACK, LOOPBACK_ONLY
from tests.cli.helpers import environment

CPUS = 2
os.environ.setdefault(LOOPBACK_ONLY, "0")  # before any test imports Ray (see above)


@dataclasses.dataclass(frozen=True)
class RayCluster:
    """A running cluster: its address."""

    address: str

    def environment(self, **extra: str) -> dict[str, str]:
        """The environment of a command that joins the cluster (see helpers.environment):
        without token authentication, whatever token this machine has."""
        return environment(RAY_AUTH_MODE="disabled", **extra)


@pytest.fixture(scope="session")
def ray_cluster(tmp_path_factory: pytest.TempPathFactory) -> Iterator[RayCluster]:
    """The session's cluster (see the module docstring); skips without Ray's RLlib."""
    pytest.importorskip("ray.rllib", reason="Ray's RLlib is not installed: pip install -e '.[ray]'")
    base = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        base = base.parent  # the workers' common folder
    with _shared_state(base / "ray_cluster") as state:
        if not state:
            state.update(_start_cluster(base))
        state["users"].append(os.getpid())
        cluster = RayCluster(state["address"])
    try:
        yield cluster
    finally:
        with _shared_state(base / "ray_cluster") as state:
            state["users"].remove(os.getpid())
            if not state["users"]:
                stop_node(state["pid"])
                shutil.rmtree(state["temp"], ignore_errors=True)
                state.clear()


def _start_cluster(base: Path) -> dict[str, Any]:
    """Start the session's cluster; its state: address, pid, temporary folder, no users."""
    workers = int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1"))
    address = f"{LOOPBACK}:{free_port()}"
    temp = tempfile.mkdtemp(prefix="ray", dir="/tmp")  # Ray's socket paths must be short
    log = base / "ray_cluster.log"
    node = start_node("--head", "--port", address.rpartition(":")[2], "--include-dashboard",
                      "false", "--temp-dir", temp, env=RayCluster(address).environment(),
                      log=log, cpus=CPUS * workers)  # fmt: skip
    try:
        wait_started(node, log)
    except BaseException:
        stop_node(node.pid)
        shutil.rmtree(temp, ignore_errors=True)
        raise
    return {"address": address, "pid": node.pid, "temp": temp, "users": []}


@contextlib.contextmanager
def _shared_state(path: Path) -> Iterator[dict[str, Any]]:
    """Within `with`, under a lock: the JSON state at `path` ({} if none), written back
    after (removed when emptied); not written if the block raises."""
    with open(path.with_suffix(".lock"), "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        state = json.loads(path.read_text()) if path.exists() else {}
        yield state
        if state:
            path.write_text(json.dumps(state))
        else:
            path.unlink(missing_ok=True)


def free_port() -> int:
    """A TCP port nothing listens on (now)."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def start_node(
    *options: str, env: dict[str, str], log: Path, cpus: int = CPUS
) -> subprocess.Popen[bytes]:
    """`ray start OPTIONS --block` in its own session, its output into the file `log` (no
    pipe: the node outlives the worker that started it); SIGTERM to it stops its node. A
    head started with LOOPBACK_ONLY "0" in `env` gets `--node-ip-address 127.0.0.1` (the
    address Ray gives it then anyway, said on its command line)."""
    ray_cli = os.path.join(os.path.dirname(sys.executable), "ray")
    if env.get(LOOPBACK_ONLY) == "0":
        options = (*options, "--node-ip-address", LOOPBACK)
    with open(log, "wb") as output:
        return subprocess.Popen(
            [ray_cli, "start", *options, "--block", "--num-cpus", str(cpus),
             "--disable-usage-stats", "--object-store-memory", str(80 * 1024**2)],
            env=env, stdout=output, stderr=subprocess.STDOUT, start_new_session=True,
        )  # fmt: skip


def wait_started(node: subprocess.Popen[bytes], log: Path, seconds: float = 300) -> None:
    """Wait until `ray start` says its node runs; raise if it ended first or took longer
    than `seconds`."""
    deadline = time.monotonic() + seconds
    while b"This command will now block" not in log.read_bytes():
        if node.poll() is not None or time.monotonic() > deadline:
            raise AssertionError(f"ray start did not start: {log.read_text(errors='replace')}")
        time.sleep(0.1)


def stop_node(pid: int) -> None:
    """Stop a node `start_node` started, by its process id (this process need not have
    started it): SIGTERM, then SIGKILL to its whole process group if it does not stop."""
    with contextlib.suppress(ProcessLookupError):
        os.killpg(pid, signal.SIGTERM)
    deadline = time.monotonic() + 60
    while _running(pid):
        if time.monotonic() > deadline:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(pid, signal.SIGKILL)
            return
        time.sleep(0.1)


def _running(pid: int) -> bool:
    """Whether process `pid` runs (reaped here if this process started it and it ended)."""
    with contextlib.suppress(ChildProcessError):
        if os.waitpid(pid, os.WNOHANG)[0] == pid:
            return False
    try:
        with open(f"/proc/{pid}/stat") as stat:
            return stat.read().rpartition(")")[2].split()[0] != "Z"
    except FileNotFoundError:
        return False
    except OSError:  # no /proc: ask the kernel whether it exists
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return False
        return True
