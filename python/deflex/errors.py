"""The exceptions deflex raises: one class per failure class, as the command
line has one exit code per class (``deflex --help``).

=================  =========  ==============================================
class              exit code  raised for
=================  =========  ==============================================
``InputError``     1          errors in a program (G-code), the reference's
``UsageError``     2          a setting out of range or contradicting another,
                              before anything runs (also a ``ValueError``)
``ConfigError``    3          config.yaml, a machine profile, a dialect, a
                              tool or material library, a job file
``FileError``      4          a file that cannot be read or written
``InternalError``  70         a bug in deflex
=================  =========  ==============================================

All derive from ``deflex.Error``. ``str(e)`` is the message with its location
(``part.nc:120:14: error: ...``); ``e.file``, ``e.line`` and ``e.column`` hold
it where there is one (``None`` where not). A program with errors is reported
error by error, then ends with one message that names only the file: the
library hands those errors over with the failure, ``e.errors`` lists them as
``(file, line, column, text)``, the first gives the location, and ``str(e)``
shows them before that message. ``e.settings`` names the settings a
``UsageError`` is about, by their ``deflex.Job`` keywords. ``e.messages`` is
everything the run printed (notes, warnings, errors with their source lines
and carets).
"""

import re

__all__ = ["Error", "InputError", "UsageError", "ConfigError", "FileError", "InternalError"]

# gcc's form, which deflex's diagnostics follow (src/diag/diagnostics.cpp),
# for the few failures that put their location in the message itself (the
# writer's self-check, a calibration file): FILE:LINE:COL: error: TEXT, or
# FILE: error: TEXT without a location.
_LOCATED = re.compile(r"^(?P<file>.+?):(?P<line>\d+):(?P<col>\d+): error: ")
_FILE_ONLY = re.compile(r"^(?P<file>[^\n]+?): error: ")


class Error(Exception):
    """A failure of a deflex run or call; see the module's documentation."""

    exit_code = None

    def __init__(self, message, messages="", exit_code=None, errors=(), settings=()):
        if exit_code is not None:
            self.exit_code = exit_code
        self.message = message
        self.messages = messages
        self.errors = [tuple(e) for e in errors]
        self.settings = list(settings)
        self.file = self.line = self.column = None
        if self.errors:
            self.file, self.line, self.column = self.errors[0][:3]
        elif where := _LOCATED.match(self.message):
            self.file, self.line, self.column = where["file"], int(where["line"]), int(where["col"])
        elif m := _FILE_ONLY.match(self.message):
            self.file = m["file"]
        text = "\n".join([e[3].rstrip("\n") for e in self.errors] + [self.message])
        super().__init__(text)


class InputError(Error):
    """Errors in a program (exit code 1)."""
    exit_code = 1


class UsageError(Error, ValueError):
    """A bad setting, found before anything runs (exit code 2)."""
    exit_code = 2


class ConfigError(Error):
    """config.yaml, a machine profile, a dialect, a library or a job file (exit code 3)."""
    exit_code = 3


class FileError(Error):
    """A file that cannot be read or written (exit code 4)."""
    exit_code = 4


class InternalError(Error):
    """A bug in deflex (exit code 70)."""
    exit_code = 70
