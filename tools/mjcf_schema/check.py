"""Differential check: mjcf accepts exactly the MJCF that MuJoCo's reader accepts.

    python -m tools.mjcf_schema.check           # the full sweep (minutes)
    python -m tools.mjcf_schema.check --sample  # the deterministic sample the tests run

For every element and attribute of ``mjcf_schema.json`` it builds small MJCF
documents (``_cases.py``) and checks, for each, that ``mujoco.MjSpec.from_string``
reads it if and only if ``mjcf.from_xml_string`` does and the same change made
through the API is accepted; and, when they accept it, that MuJoCo compiles the
original text and mjcf's ``to_xml_string()`` into equal models (``_judge.py``).
Each disagreement is printed with the explanation that accounts for it, if one
does (``_judge.EXPLANATIONS``: where mjcf is deliberately stricter, or leaves a check
to MuJoCo's compile); the exit status is 1 when an unexplained one is found. The last
result is summarized in ``docs/schema_check.md``.
"""

from __future__ import annotations

import argparse
import collections
import itertools
import json
import sys
import time
from collections.abc import Callable
from dataclasses import dataclass, field, replace

import mujoco

from mjcf import schema
from tools.mjcf_schema import _workers
from tools.mjcf_schema._cases import Case, CaseMaker
from tools.mjcf_schema._judge import Finding

SCHEMA_FILE = schema.DATA_FILE


@dataclass
class Report:
    """What a sweep found."""

    mujoco_version: str
    sample: bool
    seconds: float = 0.0
    counts: dict[str, int] = field(default_factory=dict)
    kinds: dict[str, int] = field(default_factory=dict)
    covered: set[str] = field(default_factory=set)
    attributes: set[str] = field(default_factory=set)
    findings: list[Finding] = field(default_factory=list)
    unreadable: list[str] = field(default_factory=list)  # minimal documents MuJoCo refuses
    crashes: list[Case] = field(default_factory=list)  # documents that crash MuJoCo

    def uncovered(self) -> list[str]:
        """Attributes of the schema that no case tried."""
        return sorted(self.attributes - self.covered)


def run(
    sample: bool = False,
    limit: int | None = None,
    workers: int = 2,
    progress: Callable[[str], None] | None = None,
) -> Report:
    """Run the check over the installed schema; ``sample``: the deterministic subset;
    ``progress`` receives a line of text now and then."""
    data = json.loads(SCHEMA_FILE.read_text())
    report = Report(mujoco.__version__, sample)
    start = time.perf_counter()
    maker = CaseMaker(data)
    maker.learn()
    report.unreadable = maker.failures
    cases = list(itertools.islice(maker.all_cases(sample), limit))
    for case in cases:
        report.covered.update(case.coverage)
    report.kinds = dict(collections.Counter(case.kind for case in cases))
    if progress is not None:
        progress(f"{len(cases)} cases")

    def judged(count: int) -> None:
        if progress is not None:
            progress(f"{count}/{len(cases)} judged, {time.perf_counter() - start:.0f} s")

    findings, report.counts, report.crashes = _workers.judge_all(cases, workers, judged)
    report.findings = _judged_again_alone(findings, workers)
    report.attributes = {
        f"{key}/{name}"
        for key, element in data["elements"].items()
        for name in element["attributes"]
    }
    report.seconds = time.perf_counter() - start
    return report


def _judged_again_alone(findings: list[Finding], workers: int) -> list[Finding]:
    """The findings, those unexplained explained as "not reproduced alone" if judging
    their case again, alone in a fresh process, finds no unexplained disagreement: a
    worker judges a hundred documents in one process, and MuJoCo's bindings are not
    always the same after some of them (one '1e-400' in a default class once disagreed
    only after what its worker had judged before)."""
    cases = {f.case.subject: f.case for f in findings if not f.explained}
    again, _, crashes = _workers.judge_all(list(cases.values()), workers, chunk=1)
    reproduced = {f.case.subject for f in again if not f.explained}
    reproduced.update(case.subject for case in crashes)
    return [
        f if f.explained or f.case.subject in reproduced
        else replace(f, explained="not reproduced alone")
        for f in findings
    ]  # fmt: skip


def _progress(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def main(argv: list[str] | None = None) -> int:
    """Command line entry point; returns the exit status."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sample", action="store_true", help="run the deterministic sample")
    parser.add_argument("--limit", type=int, help="stop after this many cases")
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress on stderr")
    args = parser.parse_args(argv)
    report = run(args.sample, args.limit, progress=None if args.quiet else _progress)
    for line in report.unreadable:
        print("minimal document refused:", line)
    for case in report.crashes:
        print("MuJoCo crashes (or runs over its time) on:", case.subject)
    for finding in report.findings:
        print(finding.line())
    unexplained = [finding for finding in report.findings if not finding.explained]
    explained = collections.Counter(f.explained for f in report.findings if f.explained)
    counts = report.counts
    print(
        f"{counts.get('cases', 0)} documents {report.kinds}: {counts.get('accepted', 0)} "
        f"accepted by both, {counts.get('compiled', 0)} compiled and compared; "
        f"{len(report.findings)} disagreements, {len(unexplained)} unexplained, explained: "
        f"{dict(explained)}; {len(report.crashes)} crash MuJoCo; {report.seconds:.1f} s"
    )
    return 1 if unexplained or report.unreadable else 0


if __name__ == "__main__":
    sys.exit(main())
