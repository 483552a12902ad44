"""The differential check (`tools.mjcf_schema.check`) on its deterministic sample: every
attribute of the schema tried at least once, every child of every element placed and
repeated, every section given twice; mjcf accepts a document iff MuJoCo's reader does,
and compiles what it accepts to the model MuJoCo compiles, but where the difference is
explained (`_judge.EXPLANATIONS`, listed in docs/schema_check.md)."""

from __future__ import annotations

import pytest

from tools.mjcf_schema import check


@pytest.fixture(scope="module")
def report() -> check.Report:
    return check.run(sample=True, workers=2)


def test_the_sample_covers_every_attribute(report: check.Report) -> None:
    assert report.uncovered() == []
    assert report.kinds.keys() == {"value", "omit", "child", "repeat", "sections"}
    assert report.counts["compiled"] > 500


def test_mujoco_reads_every_minimal_document_and_none_crashes_it(report: check.Report) -> None:
    """The documents that crashed MuJoCo 4.0.0 (plugins inside a flexcomp or a replicate,
    a frame as a tuple's object) are refused by mjcf now (mjcf/schema/_refusals.py), so
    the check never gives them to MuJoCo's compile."""
    assert report.unreadable == []
    assert [case.subject for case in report.crashes] == []


def test_no_disagreement_but_the_explained_and_the_open_ones(report: check.Report) -> None:
    unexplained = [finding.line() for finding in report.findings if not finding.explained]
    assert unexplained == []
