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
by the library error by error, then ends with one message that names only the
file: the first located error is taken for the location, and ``str(e)`` lists
the errors before that message. ``e.messages`` is everything the run printed
(notes, warnings, errors with their source lines and carets).
"""

import re

__all__ = ["Error", "InputError", "UsageError", "ConfigError", "FileError", "InternalError"]

# gcc's form, which deflex's diagnostics follow (src/diag/diagnostics.cpp):
# FILE:LINE:COL: error: TEXT, or FILE: error: TEXT without a location.
_LOCATED = re.compile(r"^(?P<file>.+?):(?P<line>\d+):(?P<col>\d+): error: ")
_FILE_ONLY = re.compile(r"^(?P<file>[^\n]+?): error: ")

# The command line's option names in the library's messages (src/job/checks.cpp,
# setup.cpp), as the keywords of deflex.Job name them.
_KEYWORDS = {
    "--tolerance": "tolerance_mm", "--gain": "gain", "--feed-limit": "feed_limit_N",
    "--cl-spacing": "cl_spacing_mm", "--max-iterations": "max_iterations", "--threads": "threads",
    "--cell-mm": "cell_mm", "--spindle": "spindle_rpm", "--feed": "feed_mm_per_min",
    "--part-gap": "part_gap_mm", "--block-delete": "block_delete", "--max-blocks": "max_blocks",
    "--material-file": "material_file", "--material": "material", "--kt": "kt_N_per_mm2",
    "--kr": "kr_N_per_mm2", "--ka": "ka_N_per_mm2", "--stock-from": "stock_from", "--stock": "stock",
    "--machine": "machine", "--tool": "tool", "--strict": "strict", "--reference": "reference",
}
_FLAG = re.compile(r"--[a-z][a-z-]*")


def _as_keywords(message):
    """The message with the command line's flags named as keywords."""
    return _FLAG.sub(lambda m: _KEYWORDS.get(m.group(0), m.group(0)), message)


class Error(Exception):
    """A failure of a deflex run or call; see the module's documentation."""

    exit_code = None

    def __init__(self, message, messages="", exit_code=None):
        if exit_code is not None:
            self.exit_code = exit_code
        self.message = _as_keywords(message) if self.exit_code == 2 else message
        self.messages = messages
        self.file = self.line = self.column = None
        errors = [ln for ln in messages.splitlines() if _LOCATED.match(ln)]
        where = _LOCATED.match(self.message) or (errors and _LOCATED.match(errors[0]))
        if where:
            self.file, self.line, self.column = where["file"], int(where["line"]), int(where["col"])
        elif m := _FILE_ONLY.match(self.message):
            self.file = m["file"]
        text = self.message
        if errors and not _LOCATED.match(self.message):
            text = "\n".join(errors + [self.message])
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
