"""dm_control's own tests of `composer.variation`, run on ours (tests/dm_control_wheel.py):
every test passes, but those listed in DELIBERATE with the reason we differ. A listed test
that starts passing fails here too, so the list stays true."""

from __future__ import annotations

import pytest

from tests import dm_control_wheel

FILES = (
    "composer/variation/distributions_test.py",
    "composer/variation/noises_test.py",
    "composer/variation/variation_broadcaster_test.py",
    "composer/variation/variation_test.py",
)
# 'file::Class.method' -> why ours differs on purpose. None today: ours runs them all.
DELIBERATE: dict[str, str] = {}
# How many tests each file holds in dm-control 1.0.50: a file that stopped loading its tests
# would otherwise pass with nothing run.
COUNTS = {FILES[0]: 10, FILES[1]: 8, FILES[2]: 1, FILES[3]: 9}


@pytest.mark.parametrize("relative", FILES)
def test_dm_control_variation_tests_pass(relative):
    outcomes = dm_control_wheel.run_unittest_file(relative)
    assert len(outcomes) == COUNTS[relative], outcomes
    unexpected = {
        name: outcome
        for name, outcome in outcomes.items()
        if (outcome == "passed") == (f"{relative}::{name}" in DELIBERATE)
    }
    assert not unexpected, "\n\n".join(f"{name}: {why}" for name, why in unexpected.items())
