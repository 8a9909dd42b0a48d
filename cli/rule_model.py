"""What one diagnostic code means: the entry ``motiontool rule CODE`` prints.

Every code of :data:`~motiontool.motionfmt.diagnostics.CODES` has one :class:`Rule` in
:data:`motiontool.cli.rules.RULES`: what Webots does with such a file, an example that
triggers it, how to fix it and the example fixed. The tests run ``validate`` on every example
and on every fixed example, so an explanation cannot say something ``validate`` does not do.
"""

from __future__ import annotations

from dataclasses import dataclass

from motiontool.motionfmt.diagnostics import CODES, FixKind

__all__ = ["Example", "Rule"]

SYNTAX_ONLY = ("--robot", "none")
"""``validate`` options of an example that needs no robot."""


@dataclass(frozen=True)
class Example:
    """A file that triggers a code, and how ``validate`` is run on it.

    Attributes:
        data: the file's bytes.
        name: its file name.
        args: the ``validate`` options that make the code appear (``--robot nao``, ...).
        siblings: other files in the same folder, ``(name, bytes)`` (MT309 compares a Left
            file with its Right sibling); only ``name`` is validated.
        missing: modules that are not installed for the code to appear (MT902: a check
            skipped without Pinocchio).
    """

    data: bytes
    name: str = "example.motion"
    args: tuple[str, ...] = SYNTAX_ONLY
    siblings: tuple[tuple[str, bytes], ...] = ()
    missing: tuple[str, ...] = ()


@dataclass(frozen=True)
class Rule:
    """One code explained.

    Attributes:
        code: a key of :data:`~motiontool.motionfmt.diagnostics.CODES` (which gives its
            severity and title).
        webots: what Webots does with a file that has it, in a few sentences.
        example: a file that triggers it.
        fix: how to fix it, for people.
        fixed: ``example``'s file fixed (``validate`` with the same options no longer reports
            the code), or None where the fix is not an edit of the file (install a library,
            name a robot).
        row: what the code is about, in the codes table of docs/commands.md (Markdown); None:
            the code shares the row of the code before it (MT101 to MT110 share MT100's).
    """

    code: str
    webots: str
    example: Example
    fix: str
    fixed: bytes | None = None
    row: str | None = None

    @property
    def autofix(self) -> str | None:
        """``safe`` (``validate --fix`` fixes it), ``unsafe`` (only with ``--unsafe-fixes``)
        or None (no automatic fix: see :attr:`fix`)."""
        kind = CODES[self.code].fix
        if kind is None:
            return None
        return "safe" if kind is FixKind.SAFE else "unsafe"
