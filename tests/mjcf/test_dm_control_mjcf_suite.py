"""dm_control's own mjcf tests, run against our `mjcf` as a conformance suite.

dm-control's published wheel is fetched at test time (`tests/dm_control_wheel.py`: the
package index, a cache outside the repository; skipped when the index is unreachable),
its imports rewritten to ours, and each test file that uses only public API runs here.
Every dm_control test must pass, or be listed below with the reason it does not: a
deliberate difference (the README's table of differences says why), a test that reaches
into dm_control's private internals, or one open issue. A listed test that starts
passing fails too, so the list stays true.
"""

from __future__ import annotations

import pytest

from tests import dm_control_wheel

DELIBERATE = "deliberate"  # a row of the README's table of differences
INTERNALS = "internals"  # reaches into dm_control's private implementation

# file -> whether its class fixtures run (schema_test's setUpClass parses dm_control's own
# schema file, which only one of its tests uses).
FILES = {
    "mjcf/element_test.py": True,
    "mjcf/physics_test.py": True,
    "mjcf/copier_test.py": True,
    "mjcf/export_with_assets_test.py": True,
    "mjcf/export_with_assets_as_zip_test.py": True,
    "mjcf/traversal_utils_test.py": True,
    "mjcf/xml_validation_test.py": True,
    "mjcf/schema_test.py": False,
}

_HASHES = "asset file names are plain ('deepmind.png'), not '<name>-<sha1>'"
_FRAME = "an attachment frame is written as a MuJoCo <frame>, a <body> only when it needs one"
_MAIN = 'the global defaults stay MuJoCo\'s main class: no class="/" on every element'
_SAMEFRAME = "a frame written through a binding gets MuJoCo's sameframe value, not 0"

# (file, test) -> (kind, reason)
EXPECTED_FAILURES: dict[tuple[str, str], tuple[str, str]] = {
    ("mjcf/element_test.py", "ElementTest.testAdd"): (
        DELIBERATE,
        "add() of a top-level section merges into it, as MuJoCo merges repeated sections",
    ),
    ("mjcf/element_test.py", "ElementTest.testAssetsCanBeCopied"): (DELIBERATE, _HASHES),
    ("mjcf/element_test.py", "ElementTest.testGetAssetFromFile"): (DELIBERATE, _HASHES),
    ("mjcf/element_test.py", "ElementTest.testGetAssetsFromDict"): (DELIBERATE, _HASHES),
    ("mjcf/element_test.py", "ElementTest.testAttach"): (DELIBERATE, _FRAME),
    ("mjcf/element_test.py", "ElementTest.testAttachmentFrames"): (DELIBERATE, _FRAME),
    ("mjcf/element_test.py", "ElementTest.testAttachmentFrameChildReference"): (
        DELIBERATE,
        _MAIN,
    ),
    ("mjcf/element_test.py", "ElementTest.testDefaultIdentifier"): (DELIBERATE, _MAIN),
    ("mjcf/element_test.py", "ElementTest.testChildren"): (
        DELIBERATE,
        "a child that may appear once (option.flag) is made when first read, not with its "
        "parent, so all_children() lists it from then on",
    ),
    ("mjcf/element_test.py", "ElementTest.testAttributeError"): (
        INTERNALS,
        "sets the private _spec of an element and expects the error its property raises",
    ),
    ("mjcf/physics_test.py", "PhysicsTest.test_assign_while_dirty0"): (
        DELIBERATE,
        "an item write into a view of an MjData field is not tracked (plain numpy views)",
    ),
    ("mjcf/physics_test.py", "PhysicsTest.test_assign_while_dirty1"): (
        DELIBERATE,
        "step() clears is_dirty: it leaves every derived value fresh",
    ),
    ("mjcf/physics_test.py", "PhysicsTest.test_bind_mocap_body"): (
        DELIBERATE,
        "mocap bodies bind together with other bodies; their mocap fields then raise",
    ),
    ("mjcf/physics_test.py", "PhysicsTest.test_error_when_pickling_synchronizing_array_wrapper"): (
        INTERNALS,
        "reads the private message mjcf.physics._PICKLING_NOT_SUPPORTED",
    ),
    ("mjcf/physics_test.py", "PhysicsTest.test_exceptions"): (
        INTERNALS,
        "constructs dm_control's Binding class directly, Binding(physics, namespace, index)",
    ),
    ("mjcf/physics_test.py", "PhysicsTest.test_plugins_elasticity"): (
        DELIBERATE,
        "MuJoCo 4 has no <composite> (refused, naming <flexcomp>)",
    ),
    ("mjcf/physics_test.py", "PhysicsTest.test_write_to_ipos"): (DELIBERATE, _SAMEFRAME),
    **{
        ("mjcf/physics_test.py", f"PhysicsTest.test_write_to_{field}{index}"): (
            DELIBERATE,
            _SAMEFRAME,
        )
        for field in ("pos", "quat")
        for index in range(3)
    },
    ("mjcf/traversal_utils_test.py", "TraversalUtilsTest.test_resolve_actuator_defaults"): (
        DELIBERATE,
        "commit_defaults refuses a position whose class sets <velocity kv>: dm_control copies "
        "kv across shortcuts, which MuJoCo 4 compiles otherwise",
    ),
    ("mjcf/schema_test.py", "SchemaTest.test_namespace_universe_is_closed"): (
        INTERNALS,
        "walks dm_control's own schema file (schema.parse_schema, collect_namespaces)",
    ),
}


@pytest.mark.parametrize("relative", sorted(FILES))
def test_dm_control_mjcf_tests_pass_or_differ_as_listed(relative: str) -> None:
    outcomes = dm_control_wheel.run_unittest_file(relative, class_fixtures=FILES[relative])
    assert "import" not in outcomes, outcomes.get("import")
    listed = {test for (file, test) in EXPECTED_FAILURES if file == relative}
    unknown = sorted(listed - set(outcomes))
    assert unknown == [], f"listed tests that {relative} does not have"
    problems = []
    for test, outcome in sorted(outcomes.items()):
        expected = EXPECTED_FAILURES.get((relative, test))
        passed = outcome == "passed"
        if expected is None and not passed:
            problems.append(f"{test} {outcome}")
        elif expected is not None and passed:
            problems.append(f"{test} passes now: remove it from the list ({expected[1]})")
    assert problems == [], "\n\n".join(problems)
