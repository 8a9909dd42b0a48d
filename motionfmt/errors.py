"""The root exception of motiontool and its located variant."""

from __future__ import annotations

__all__ = ["MotionSyntaxError", "MotionToolError"]


class MotionToolError(Exception):
    """Root error of motiontool: a one-line message meant for the user, never a traceback."""


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
