"""One local Ray cluster for every Ray test of a session (of each pytest-xdist worker), so
that the tests pay Ray's start and stop once, not once per command: `ray start --head` with
two CPUs, stopped when the session ends. tests/conftest.py makes `ray_cluster` a fixture of
every test folder. The cluster runs without token authentication (RAY_AUTH_MODE=disabled,
also in the environment of the commands that join it), so that a test's own process,
which imported Ray already, joins it too; tests/cli/test_train_ray.py's two-node cluster
has a token.

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

import dataclasses
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
from collections.abc import Iterator

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
def ray_cluster() -> Iterator[RayCluster]:
    """The session's cluster, started at its first use; skips without Ray's RLlib."""
    pytest.importorskip("ray.rllib", reason="Ray's RLlib is not installed: pip install -e '.[ray]'")
    cluster = RayCluster(f"{LOOPBACK}:{free_port()}")
    temp = tempfile.mkdtemp(prefix="ray", dir="/tmp")  # Ray's socket paths must be short
    node = start_node("--head", "--port", cluster.address.rpartition(":")[2],
                      "--include-dashboard", "false", "--temp-dir", temp,
                      env=cluster.environment())  # fmt: skip
    try:
        wait_started(node)
        yield cluster
    finally:
        stop_node(node)
        shutil.rmtree(temp, ignore_errors=True)


def free_port() -> int:
    """A TCP port nothing listens on (now)."""
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return probe.getsockname()[1]


def start_node(*options: str, env: dict[str, str], cpus: int = CPUS) -> subprocess.Popen[str]:
    """`ray start OPTIONS --block` in its own session: SIGTERM to it stops its node. A head
    started with LOOPBACK_ONLY "0" in `env` gets `--node-ip-address 127.0.0.1` (the
    address Ray gives it then anyway, said on its command line)."""
    ray_cli = os.path.join(os.path.dirname(sys.executable), "ray")
    if env.get(LOOPBACK_ONLY) == "0":
        options = (*options, "--node-ip-address", LOOPBACK)
    return subprocess.Popen(
        [ray_cli, "start", *options, "--block", "--num-cpus", str(cpus),
         "--disable-usage-stats", "--object-store-memory", str(80 * 1024**2)],
        env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
        start_new_session=True,
    )  # fmt: skip


def wait_started(node: subprocess.Popen[str]) -> None:
    """Read `ray start`'s output until its node runs (or it ended)."""
    assert node.stdout is not None
    for line in node.stdout:
        if "This command will now block" in line:
            return
    raise AssertionError(f"ray start exited with {node.wait()}")


def stop_node(node: subprocess.Popen[str]) -> None:
    """Stop a node `start_node` started (its whole process group if it does not stop)."""
    node.terminate()
    try:
        node.wait(timeout=60)
    except subprocess.TimeoutExpired:
        os.killpg(node.pid, signal.SIGKILL)
