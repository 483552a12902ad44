"""Argument parsing as every command and engine option does it: options matched exactly,
mistakes raised as one-line UsageErrors, and the value types they share.

    parser = arguments.Parser(prog='composer')   # allow_abbrev off; .error raises UsageError
    parser.add_argument('--episodes', type=arguments.positive_int)

A train parser's help can end with text made only when the help is shown
(`Parser(epilog_source=...)`): the recipe table, which imports the tasks.
"""

from __future__ import annotations

import argparse
import difflib
import re
from collections.abc import Callable, Sequence
from typing import Any, NoReturn

import mjcf
from composer.cli.errors import CliError
from mjcf import archives


class UsageError(CliError):
    """The command line does not parse: an unknown option, a missing or bad value; `prog`
    is the command it concerns ('composer train')."""

    def __init__(self, message: str, prog: str = "composer") -> None:
        super().__init__(message)
        self.prog = prog


class Parser(argparse.ArgumentParser):
    """An ArgumentParser that matches options exactly and raises UsageError (one line,
    with a did-you-mean for an invalid choice) instead of printing usage and exiting; its
    help ends with `epilog_source()` when given."""

    def __init__(self, epilog_source: Callable[[], str] | None = None, **kwargs: Any) -> None:
        super().__init__(allow_abbrev=False, **kwargs)
        self.epilog_source = epilog_source

    def error(self, message: str) -> NoReturn:
        """Raise UsageError naming this command; argparse calls it for any mistake."""
        invalid = re.search(r"invalid choice: '?([^' ]+)'? \(choose from (.*)\)", message)
        if invalid:
            choices = [c.strip(" '") for c in invalid.group(2).split(",")]
            message += did_you_mean(invalid.group(1), choices, quote="'")
        raise UsageError(f"{message} (see: {self.prog} --help)", prog=self.prog)

    def format_help(self) -> str:
        """The help, its epilog made now if it has an `epilog_source`."""
        if self.epilog_source is not None:
            self.epilog = self.epilog_source()
        return super().format_help()


def positive_int(text: str) -> int:
    """An argparse type: a whole number of at least 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {value}")
    return value


def byte_size(text: str) -> int:
    """An argparse type: a number of bytes, with K, M, G or T after it if you like."""
    try:
        return archives.parse_size(text)
    except mjcf.UnpackLimitError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def ratio(text: str) -> float:
    """An argparse type: a number of at least 1."""
    try:
        return archives.parse_ratio(text)
    except mjcf.UnpackLimitError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def did_you_mean(word: str, known: Sequence[str], quote: str = "") -> str:
    """'; did you mean --timesteps?' for the closest of `known`, or ''."""
    close = difflib.get_close_matches(word, known, n=1, cutoff=0.6)
    return f"; did you mean {quote}{close[0]}{quote}?" if close else ""


def flags(names: Sequence[str]) -> str:
    """'--n-envs and --vec' for the destinations ['n_envs', 'vec']."""
    return " and ".join("--" + name.replace("_", "-") for name in names)
