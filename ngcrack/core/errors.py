"""Whose fault an error is: the user's input (`InputError`) or not.

`InputError` is a `ValueError`: every check of what a user gives (a scene field, an
option, a path, a command-line argument, a widget's argument) raises it or a subclass
(`SceneError`, `PathError`, `MeshingError`, the command line's `UsageError`, the
explorer's `ArgumentError`), with a message that names the field and the values allowed.
The command line turns exactly this family into exit code 2 ("bad input"); any other
exception, a plain `ValueError` from numpy included, is a fault of the library or of the
system and is reported as one (`ngcrack.shell.cli_errors`).
"""

from __future__ import annotations

__all__ = ["InputError"]


class InputError(ValueError):
    """Bad input: the message names the field and what is allowed (exit code 2 on the command line)."""
