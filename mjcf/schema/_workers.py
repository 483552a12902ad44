"""Judge cases in child processes, so that a document that crashes MuJoCo (some
do: a ``<plugin/>`` without a plugin inside a ``<flexcomp>``) or keeps it busy
for long (a grid of two billion points) is reported instead of ending the sweep.

Cases go to up to ``workers`` forked processes in chunks; a chunk whose process
dies (a crash, or the alarm that ends a case running over ``CASE_SECONDS``) is
split in halves and run again, down to the single case that does it.
"""

from __future__ import annotations

import collections
import multiprocessing
import resource
import signal
from collections.abc import Callable, Sequence
from multiprocessing.connection import Connection, wait

import mujoco

from mjcf.schema._cases import Case
from mjcf.schema._judge import Finding, Judge

_CHUNK = 100
# Address space of a worker: cases ask for huge arrays (nstack="2147483647"), which
# MuJoCo then fails to allocate instead of taking the machine's memory.
_MEMORY_LIMIT = 4 << 30
CASE_SECONDS = 20


def _judge_chunk(cases: Sequence[Case], connection: Connection) -> None:
    resource.setrlimit(resource.RLIMIT_AS, (_MEMORY_LIMIT, _MEMORY_LIMIT))
    mujoco.set_mju_user_warning(lambda message: None)  # no MUJOCO_LOG.TXT, no noise
    signal.signal(signal.SIGALRM, signal.SIG_DFL)  # ends the process, even inside MuJoCo
    judge = Judge()
    for case in cases:
        signal.alarm(CASE_SECONDS)
        judge.run(case)
    signal.alarm(0)
    connection.send((judge.findings, judge.counts))
    connection.close()


def judge_all(
    cases: Sequence[Case], workers: int, progress: Callable[[int], None] | None = None
) -> tuple[list[Finding], dict[str, int], list[Case]]:
    """(findings, counts, cases that crash MuJoCo or time out), over ``cases`` in
    order; ``progress`` is called with the number of cases judged so far."""
    context = multiprocessing.get_context("fork")
    pending = collections.deque(
        (start, cases[start : start + _CHUNK]) for start in range(0, len(cases), _CHUNK)
    )
    running: dict[Connection, tuple[int, Sequence[Case], multiprocessing.Process]] = {}
    results: dict[int, list[Finding]] = {}
    counts: collections.Counter[str] = collections.Counter()
    crashes: list[Case] = []
    while pending or running:
        while pending and len(running) < workers:
            start, chunk = pending.popleft()
            receiver, sender = context.Pipe(duplex=False)
            process = context.Process(target=_judge_chunk, args=(chunk, sender), daemon=True)
            process.start()
            sender.close()
            running[receiver] = (start, chunk, process)
        for receiver in wait(list(running)):
            start, chunk, process = running.pop(receiver)
            try:
                findings, chunk_counts = receiver.recv()
            except EOFError:  # the process died
                process.join()
                if len(chunk) == 1:
                    crashes.append(chunk[0])
                else:
                    half = len(chunk) // 2
                    pending.appendleft((start + half, chunk[half:]))
                    pending.appendleft((start, chunk[:half]))
                continue
            finally:
                receiver.close()
            process.join()
            results[start] = findings
            counts.update(chunk_counts)
            if progress is not None:
                progress(counts["cases"])
    findings = [finding for start in sorted(results) for finding in results[start]]
    return findings, dict(counts), crashes
