"""Judge cases in child processes, so that a document that crashes MuJoCo (some
do: a ``<plugin/>`` without a plugin inside a ``<flexcomp>``) or keeps it busy
for long (a grid of two billion points) is reported instead of ending the sweep.

Cases go to up to ``workers`` forked processes in chunks; each reports every case
it has judged as it goes, so when one dies (a crash, or the alarm that ends a case
running over ``CASE_SECONDS``) the case it was judging is the one that did it, and
the rest of its chunk goes to a new process. So does the rest of the chunk of a worker
in which MuJoCo's bindings failed (`_judge.bindings_failed`): MuJoCo 4.0.0's may hang
on a later document there, which would be reported as a crash that is not one.
"""

from __future__ import annotations

import collections
import faulthandler
import multiprocessing
import resource
import signal
from collections.abc import Callable, Sequence
from multiprocessing.connection import Connection, wait
from typing import cast

import mujoco

from tools.mjcf_schema._cases import Case
from tools.mjcf_schema._judge import Finding, Judge, bindings_failed

_CHUNK = 100
# Address space of a worker: cases ask for huge arrays (nstack="2147483647"), which
# MuJoCo then fails to allocate instead of taking the machine's memory.
_MEMORY_LIMIT = 4 << 30
CASE_SECONDS = 20
# Sent by a worker that must be replaced before the rest of its chunk (`bindings_failed`).
_REPLACE = "replace"


def _judge_chunk(cases: Sequence[Case], connection: Connection) -> None:
    resource.setrlimit(resource.RLIMIT_AS, (_MEMORY_LIMIT, _MEMORY_LIMIT))
    mujoco.set_mju_user_warning(lambda message: None)  # no MUJOCO_LOG.TXT, no noise
    faulthandler.disable()  # a crash is expected here, and reported by the parent
    signal.signal(signal.SIGALRM, signal.SIG_DFL)  # ends the process, even inside MuJoCo
    for case in cases:
        judge = Judge()
        signal.alarm(CASE_SECONDS)
        judge.run(case)
        signal.alarm(0)
        connection.send((judge.findings, judge.counts))
        if bindings_failed():
            connection.send(_REPLACE)
            break
    connection.close()


def judge_all(
    cases: Sequence[Case],
    workers: int,
    progress: Callable[[int], None] | None = None,
    chunk: int = _CHUNK,
) -> tuple[list[Finding], dict[str, int], list[Case]]:
    """(findings, counts, cases that crash MuJoCo or time out), over ``cases`` in
    order, ``chunk`` cases to a process; ``progress`` is called with the number of
    cases judged so far."""
    context = multiprocessing.get_context("fork")
    pending = collections.deque(
        (start, cases[start : start + chunk]) for start in range(0, len(cases), chunk)
    )
    # receiver -> [index of the next case, its chunk's cases, process]
    running: dict[Connection, list] = {}
    results: dict[int, list[Finding]] = {}
    counts: collections.Counter[str] = collections.Counter()
    crashes: list[Case] = []
    while pending or running:
        while pending and len(running) < workers:
            start, some = pending.popleft()
            receiver, sender = context.Pipe(duplex=False)
            process = context.Process(target=_judge_chunk, args=(some, sender), daemon=True)
            process.start()
            sender.close()
            running[receiver] = [start, start + len(some), process]
        for ready in wait(list(running)):
            receiver = cast(Connection, ready)
            state = running[receiver]
            index, end, process = state
            try:
                message = receiver.recv()
            except EOFError:  # the process ended: done, or died judging case `index`
                receiver.close()
                process.join()
                del running[receiver]
                if index < end:
                    crashes.append(cases[index])
                    if index + 1 < end:
                        pending.appendleft((index + 1, cases[index + 1 : end]))
                continue
            if message == _REPLACE:  # the rest of its chunk goes to a fresh process
                receiver.close()
                process.join()
                del running[receiver]
                if index < end:
                    pending.appendleft((index, cases[index:end]))
                continue
            findings, case_counts = message
            results[index] = findings
            counts.update(case_counts)
            state[0] = index + 1
            if progress is not None and counts["cases"] % chunk == 0:
                progress(counts["cases"])
    findings = [finding for index in sorted(results) for finding in results[index]]
    return findings, dict(counts), crashes
