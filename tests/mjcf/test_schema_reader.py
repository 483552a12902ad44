"""The schema generator's reader (tools/mjcf_schema/_reader.py): MuJoCo's XML reader in a
child process, which no document can leave stalled."""

from __future__ import annotations

import pytest

from tools.mjcf_schema._probe import FILES
from tools.mjcf_schema._reader import Reader, ReaderError

ATTACH_WITHOUT_PREFIX = (
    '<mujoco><asset><model name="m" file="probe_model.xml"/></asset>'
    '<worldbody><body name="b"><attach prefix="" model="m"/></body></worldbody></mujoco>'
)
# Reading a 100x100 grid takes MuJoCo seconds.
SLOW = (
    '<mujoco><worldbody><body name="b"><flexcomp name="f" type="grid" count="100 100 1"'
    ' spacing="1 1 1" dim="2"/></body></worldbody></mujoco>'
)


def test_errors_and_what_mujoco_writes_back() -> None:
    reader = Reader(FILES)
    error, written = reader.read("<mujoco><bogus/></mujoco>")
    assert error is not None and "unrecognized element" in error and written is None
    error, written = reader.read(
        '<mujoco><worldbody><geom name="g" size="1"/></worldbody></mujoco>', write_back=True
    )
    assert error is None and written is not None and '<geom name="g"' in written
    assert reader.read("<mujoco/>") == (None, None)


def test_a_document_that_upsets_mujoco_does_not_stall_the_next_one() -> None:
    # In one process, MuJoCo 4.0.0 spins forever on the attach's warning (empty
    # prefix) after a <model> without a file failed with an "unknown exception".
    reader = Reader(FILES, seconds=30)
    error, _ = reader.read('<mujoco><asset><model name="a"/></asset></mujoco>')
    assert error
    assert reader.read(ATTACH_WITHOUT_PREFIX) == (None, None)


def test_a_document_read_for_too_long_is_an_error_and_reading_goes_on() -> None:
    reader = Reader(FILES, seconds=0.5)
    with pytest.raises(ReaderError, match=r"took over 0\.5 s to read:\n<mujoco>"):
        reader.read(SLOW)
    assert reader.read("<mujoco/>") == (None, None)
