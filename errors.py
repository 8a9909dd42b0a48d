"""The root exception of motiontool and its located variant."""

from __future__ import annotations

__all__ = ["MissingExtraError", "MotionSyntaxError", "MotionToolError", "OutputError"]


class MotionToolError(Exception):
    """Root error of motiontool: a one-line message meant for the user, never a traceback."""


class OutputError(MotionToolError):
    """A file the command writes cannot be written (``cannot write 'PATH': No space left on
    device``): not the input's fault, so a batch stops on it instead of counting a failed
    run."""


class MotionSyntaxError(MotionToolError):
    """A problem located in a file: prints as ``path:line:col: message``.

    Attributes:
        path: the file, as the user named it.
        line: 1-based line number.
        column: 1-based column of the first byte of the offending token.
    """

    def __init__(self, message: str, path: str = "<string>", line: int = 1, column: int = 1):
        self.message = message
        self.path = path
        self.line = line
        self.column = column
        super().__init__(f"{path}:{line}:{column}: {message}")


class MissingExtraError(MotionToolError):
    """A feature needs a library of an extra that is not installed; the message says which
    ``pip install`` brings it: ``motiontool play needs MuJoCo: pip install 'motiontool[sim]'``.

    Attributes:
        module: the module that could not be imported (``mujoco``).
        extra: the extra of the motiontool package that installs it (``sim``).
        what: the command or feature that needs it (``motiontool play``).
        library: the library as people call it (``MuJoCo``).
    """

    def __init__(self, module: str, extra: str, what: str, library: str | None = None):
        self.module = module
        self.extra = extra
        self.what = what
        self.library = library or module
        super().__init__(f"{what} needs {self.library}: pip install 'motiontool[{extra}]'")
