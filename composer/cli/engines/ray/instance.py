"""The Ray instance a `composer train --engine ray` run uses: started for the run and gone
when the command returns, or a cluster joined and left as it was.

    with instance.running(address=None, workers=2) as cpus:   # ray.init ... ray.shutdown
        ...                                                    # build and train

Promise: a local instance is this machine's alone (it listens on 127.0.0.1 only), and
leaves no process and no session folder behind (`running` says how). What a start costs:
docs/ray.md and docs/performance_profile.md.
"""

from __future__ import annotations

import contextlib
import logging
import os
import re
import shutil
import signal
import socket
import sys
import tempfile
import threading
import time
from collections.abc import Iterator
from typing import Any

from composer.cli.engines.ray.algorithm import Layout
from composer.cli.engines.ray.files import quiet_ray
from composer.cli.errors import CliError

# Seconds to wait for a cluster's address to accept a connection.
CONNECT_SECONDS = 5.0
# Object store of a local instance: RLlib only passes episodes and weights through it.
LOCAL_OBJECT_STORE_BYTES = 256 * 1024**2
# Seconds to wait for a local instance's processes to end after ray.shutdown().
STOP_SECONDS = 15.0
# The longest temporary folder a session folder goes into: Ray's socket paths in it
# ('/ray-XXXXXXXX/session_<date>_<pid>/sockets/plasma_store', 77 bytes) must fit in 107.
MAX_TEMP_ROOT = 30
# Ray's switch for an instance of this machine alone, read when Ray is imported (its default
# on macOS and Windows): "0" gives the node the address 127.0.0.1, and Ray's servers listen
# on the loopback interface only. Without it Ray on Linux turns 127.0.0.1 (`ray.init`'s
# `_node_ip_address`, `ray start --node-ip-address`) into the machine's interface address
# and listens on every interface (measured with Ray 2.60: `ss -ltnp`).
LOOPBACK_ONLY = "RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER"
LOOPBACK = "127.0.0.1"
# What Ray's C++ core prints on every run that needs no action, dropped from stderr while
# Ray runs (everything else passes): `core_worker.cc ... the actor restart will fail`, but
# RLlib restarts a lost env runner with its own copy of the arguments, so it does not apply.
NOISE = re.compile(rb"core_worker\.cc.*actor restart will fail")


@contextlib.contextmanager
def running(address: str | None, workers: int | None) -> Iterator[int]:
    """Within `with`: Ray started locally (address None) with `workers` CPUs (this
    machine's count if None: that many env runners fit, whatever the cores) or joined at
    `address`; yields the CPUs Ray has. Raises CliError when the cluster cannot be
    reached or Ray cannot start.

    A local instance is this machine's alone: its node's address is 127.0.0.1 and every server
    of Ray's (GCS, raylet, workers) listens on the loopback interface only (`loopback_only`,
    before Ray is imported). A local instance keeps its session folder (logs, sockets) in a
    temporary folder of its own, removed after it stops, instead of adding one per run to the
    system's (Ray's default: /tmp/ray/session_*). Its processes (Ray's services, the env
    runners) are waited for after `ray.shutdown()`, which only signals them, so none is left
    when the command returns. Ray reuses the worker processes it starts with `ray.init` (one per
    CPU) for the env runners.
    """
    import ray  # only when training on Ray: the engine imports this module to check first

    quiet_ray()
    options: dict[str, Any] = {
        "logging_level": logging.ERROR,
        "log_to_driver": False,
        "configure_logging": True,
    }
    if address is not None:
        check_reachable(address)
    session = None if address is not None else tempfile.mkdtemp(prefix="ray-", dir=_temp_root())
    processes: dict[int, str] = {}
    with _without_noise():
        try:
            try:
                if session is None:
                    ray.init(address=address, **options)
                else:
                    ray.init(
                        num_cpus=workers or os.cpu_count() or 1, _temp_dir=session,
                        _node_ip_address=LOOPBACK,
                        object_store_memory=LOCAL_OBJECT_STORE_BYTES, include_dashboard=False,
                        **options,
                    )  # fmt: skip
            except (ConnectionError, RuntimeError, ValueError) as e:
                if address is None:
                    raise CliError(f"cannot start a local Ray instance: {e}") from e
                raise CliError(
                    f"cannot join the Ray cluster at {address}: {e} (is this machine's token "
                    "the cluster's? see docs/ray.md)"
                ) from e
            yield int(ray.cluster_resources().get("CPU", 0))
        finally:
            processes = _descendants()
            ray.shutdown()
    _wait_until_gone(processes)
    if session is not None:
        shutil.rmtree(session, ignore_errors=True)


def authenticate(address: str | None) -> None:
    """Before Ray is imported: join the cluster at `address` with token authentication
    when this machine has a token (RAY_AUTH_TOKEN, the file RAY_AUTH_TOKEN_PATH names, or
    ~/.ray/auth_token) and RAY_AUTH_MODE does not say otherwise, as `ray start` does. Ray
    2.60 reads RAY_AUTH_MODE once, when imported, and `ray.init(address=...)` does not turn
    token mode on itself."""
    if address is None or "RAY_AUTH_MODE" in os.environ:
        return
    token_file = os.environ.get("RAY_AUTH_TOKEN_PATH") or os.path.join("~", ".ray", "auth_token")
    if os.environ.get("RAY_AUTH_TOKEN") or os.path.isfile(os.path.expanduser(token_file)):
        os.environ["RAY_AUTH_MODE"] = "token"


def loopback_only(address: str | None) -> None:
    """Before Ray is imported: a local instance (`address` None) binds to 127.0.0.1 only
    (LOOPBACK_ONLY), unless the environment says otherwise."""
    if address is None:
        os.environ.setdefault(LOOPBACK_ONLY, "0")


def machine_cpus() -> int:
    """The CPUs this process may run on."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


def oversubscribed(layout: Layout) -> str | None:
    """A note when a local instance runs more env runners than this machine has CPUs:
    they share the cores, so sampling is no faster than with as many as CPUs."""
    cpus = machine_cpus()
    if layout.address is not None or layout.workers <= cpus:
        return None
    return (
        f"note: {layout.workers} env runners on this machine's {cpus} CPUs take turns on "
        f"them: sampling is no faster than with --workers {cpus} (see docs/ray.md)"
    )


def check_capacity(layout: Layout, cpus: int) -> None:
    """Raise CliError when the cluster has fewer CPUs than env runners (one each): Ray
    would wait for them forever."""
    if layout.workers > cpus:
        raise CliError(
            f"the Ray cluster at {layout.address} has {cpus} CPUs, and --workers "
            f"{layout.workers} needs one each; add machines (`ray start --address=...`) "
            "or give fewer --workers"
        )


def check_reachable(address: str) -> None:
    """Raise CliError unless `address` is 'auto' or a HOST:PORT that accepts a connection
    within CONNECT_SECONDS (ray.init retries an unreachable address for minutes)."""
    if address == "auto":
        return
    host, colon, port = address.rpartition(":")
    if not colon or not host or not port.isdigit():
        raise CliError(
            f"--address {address!r}: expected HOST:PORT, the address `ray start --head` "
            "printed (e.g. 10.0.0.1:6379), or 'auto' for the cluster of this machine"
        )
    try:
        socket.create_connection((host.strip("[]"), int(port)), timeout=CONNECT_SECONDS).close()
    except OSError as e:
        raise CliError(
            f"cannot reach the Ray cluster at {address}: {e.strerror or e}; start one with "
            "`ray start --head` (see docs/ray.md)"
        ) from e


def _temp_root() -> str | None:
    """Where a local instance's session folder goes: RAY_TMPDIR, else the system's
    temporary folder, or /tmp where that one's path is too long for the socket names Ray
    makes in it (macOS's; at most 107 bytes in all); None: Ray's own choice."""
    if os.environ.get("RAY_TMPDIR"):
        return os.environ["RAY_TMPDIR"]
    system = tempfile.gettempdir()
    if len(system) <= MAX_TEMP_ROOT or not os.path.isdir("/tmp"):
        return system
    return "/tmp"


@contextlib.contextmanager
def _without_noise() -> Iterator[None]:
    """Within `with`: lines written to file descriptor 2 (Ray's C++ core) that match NOISE
    are dropped, the rest passed on; Python's `sys.stderr` writes straight to where stderr
    went before (a terminal stays a terminal for progress bars)."""
    try:
        sys.stderr.flush()
        terminal = os.dup(2)
        read_end, write_end = os.pipe()
    except (OSError, ValueError):  # no usable stderr: nothing to keep clean
        yield
        return
    python_stderr = sys.stderr
    sys.stderr = os.fdopen(
        os.dup(terminal), "w", buffering=1,
        encoding=python_stderr.encoding or "utf-8", errors="backslashreplace",
    )  # fmt: skip
    os.dup2(write_end, 2)
    os.close(write_end)
    forwarder = threading.Thread(target=_forward, args=(read_end, terminal), daemon=True)
    forwarder.start()
    try:
        yield
    finally:
        sys.stderr.flush()
        sys.stderr.close()
        sys.stderr = python_stderr
        os.dup2(terminal, 2)  # the pipe's last writer here: the forwarder sees its end
        forwarder.join(timeout=1.0)


def _forward(read_end: int, terminal: int) -> None:
    """Copy lines from `read_end` to `terminal` until the pipe ends, dropping NOISE."""
    pending = b""
    with contextlib.suppress(OSError), os.fdopen(read_end, "rb", buffering=0) as pipe:
        while chunk := pipe.read(65536):
            *lines, pending = (pending + chunk).split(b"\n")
            kept = b"".join(line + b"\n" for line in lines if not NOISE.search(line))
            if kept:
                os.write(terminal, kept)
    if pending and not NOISE.search(pending):
        os.write(terminal, pending)
    os.close(terminal)


def _descendants() -> dict[int, str]:
    """This process's descendants (Linux: read from /proc; elsewhere none), by pid, each
    with its start time, so a pid reused later is not mistaken for it."""
    table: dict[int, tuple[int, str]] = {}
    with contextlib.suppress(OSError):
        for entry in os.listdir("/proc"):
            if entry.isdigit():
                with contextlib.suppress(OSError, IndexError, ValueError):
                    stat = _stat(int(entry))
                    table[int(entry)] = (int(stat[1]), stat[19])
    found: dict[int, str] = {}
    parents = [os.getpid()]
    while parents:
        parent = parents.pop()
        for pid, (ppid, started) in table.items():
            if ppid == parent and pid not in found:
                found[pid] = started
                parents.append(pid)
    return found


def _stat(pid: int) -> list[str]:
    """The fields of /proc/PID/stat after the command name (state, ppid, ...)."""
    with open(f"/proc/{pid}/stat") as file:
        text = file.read()
    return text[text.rindex(")") + 2 :].split()


def _alive(pid: int, started: str) -> bool:
    try:
        stat = _stat(pid)
    except (OSError, ValueError):
        return False
    return stat[19] == started and stat[0] != "Z"


def _wait_until_gone(processes: dict[int, str]) -> None:
    """Wait up to STOP_SECONDS for `processes` (pid: start time) to end, then kill the
    rest: Ray's own processes, which ray.shutdown() signalled."""
    deadline = time.monotonic() + STOP_SECONDS
    alive = dict(processes)
    while alive and time.monotonic() < deadline:
        alive = {pid: started for pid, started in alive.items() if _alive(pid, started)}
        if alive:
            time.sleep(0.05)
    for pid in alive:
        with contextlib.suppress(OSError):
            os.kill(pid, signal.SIGKILL)
