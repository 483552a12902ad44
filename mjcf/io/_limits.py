"""Limits in force on untrusted input, read one way for `mjcf.archives` (unpacking) and
`mjcf.budget` (compiling): what the program set, else the environment variables' values
over the defaults."""

from __future__ import annotations

import os
from collections.abc import Callable, Mapping
from typing import Any, TypeVar

_Limits = TypeVar("_Limits")


def in_force(
    program: _Limits | None,
    kind: Callable[..., _Limits],
    variables: Mapping[str, tuple[Callable[[str], Any], Any]],
) -> _Limits:
    """`program`'s limits if it set them (not None), else `kind` made of one value for
    each environment variable of `variables` (name -> (parser, default), in the order of
    `kind`'s arguments): the variable read by its parser where it is set and not empty,
    else the default. Raises what a parser raises."""
    if program is not None:
        return program
    values = []
    for variable, (parse, default) in variables.items():
        text = os.environ.get(variable)
        values.append(parse(text) if text else default)
    return kind(*values)
