"""dm_control's own tests of `utils.rewards`, `utils.transformations` and
`utils.inverse_kinematics` run on `composer.utils` (tests/dm_control_wheel.py: the published
wheel, imports rewritten, dm_control's three modules deleted; the inverse kinematics test
builds `mjcf.Physics` where it built `dm_control.mujoco.Physics`, which does not load on
MuJoCo 4). Every one of them passes, so there is no table of differences; the counts make
sure each file ran all its tests. Skips when the wheel cannot be fetched."""

from __future__ import annotations

import logging
import warnings

import pytest

from composer.utils import inverse_kinematics, rewards, transformations
from tests import dm_control_wheel

TEST_FILES = {
    "utils/rewards_test.py": 34,
    "utils/transformations_test.py": 24,
    "utils/inverse_kinematics_test.py": 37,
}


@pytest.fixture(autouse=True)
def _quiet():
    """dm_control's tests log freely (absl) and warn (deprecations): not ours to judge."""
    logging.disable(logging.WARNING)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        yield
    logging.disable(logging.NOTSET)


@pytest.mark.parametrize("relative", list(TEST_FILES))
def test_dm_control_utils_tests_pass_on_ours(relative):
    outcomes = dm_control_wheel.run_unittest_file(relative)
    failing = {name: text for name, text in outcomes.items() if text != "passed"}
    assert not failing, "\n\n".join(f"{name}: {text}" for name, text in failing.items())
    assert len(outcomes) == TEST_FILES[relative]


def test_the_rewritten_wheel_runs_dm_control_code_on_our_utils():
    """Their implementation is gone from the rewritten tree, and their code that imports it
    (manipulation's rewards, the Jaco arm's inverse kinematics, locomotion's mocap
    transformations) gets ours."""
    package = dm_control_wheel.rewritten() / "dm_control" / "utils"
    assert sorted(path.name for path in package.glob("*.py") if "test" not in path.name) == [
        "__init__.py",
        "containers.py",
        "io.py",
        "xml_tools.py",
    ]
    reach = dm_control_wheel.import_module("dm_control.manipulation.reach")
    assert reach.rewards is rewards
    arms = dm_control_wheel.import_module("dm_control.entities.manipulators.base")
    assert arms.inverse_kinematics is inverse_kinematics
    tracking = dm_control_wheel.import_module("dm_control.locomotion.tasks.reference_pose.utils")
    assert tracking.tr is transformations


def test_rewrite_turns_imports_of_the_three_utils_into_ours():
    rewrite = dm_control_wheel.rewrite
    assert rewrite("from dm_control.utils import rewards\n") == (
        "from composer.utils import rewards\n"
    )
    assert rewrite("    from dm_control.utils import transformations as tr  # angles\n") == (
        "    from composer.utils import transformations as tr\n"
    )
    assert rewrite("from dm_control.utils import containers, inverse_kinematics as ik\n") == (
        "from composer.utils import inverse_kinematics as ik; "
        "from dm_control.utils import containers\n"
    )
    assert rewrite("from dm_control.utils.rewards import tolerance\n") == (
        "from composer.utils.rewards import tolerance\n"
    )
    kept = "from dm_control.utils import io as resources\nfrom dm_control.utils.io import x\n"
    assert rewrite(kept) == kept
