"""The mistakes a command-line user makes, as `composer.Error` subclasses.

`composer.cli.main` prints any `composer.Error` (these, and those the library raises) as one
line on stderr and exits with status 2; no traceback reaches the user.
"""

from __future__ import annotations

from composer import errors

TRAIN_INSTALL = "pip install torch==2.13.0 && pip install -e '.[train]'"


class CliError(errors.Error):
    """Base of the errors only the command-line tool raises."""


class UnknownTaskError(CliError):
    """The task named on the command line is not registered."""


class MissingExtraError(CliError):
    """A command needs an optional dependency that is not installed."""


class OutputError(CliError):
    """An output file or directory cannot be written."""


class PolicyError(CliError):
    """A saved policy or checkpoint cannot be found, read, or used on the task."""


class RecipeError(CliError, ValueError):
    """A training recipe, or a task given recipes, is not what `recipes.register` takes."""


class UntrustedPolicyError(PolicyError):
    """A saved policy can only be loaded by unpickling, which runs code from the file:
    refused unless the user passes --trust-policy."""
