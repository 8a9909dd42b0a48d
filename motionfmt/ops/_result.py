"""What an operation gives back: the result's bytes and name, read into a document on first use
(a caller done with the inputs lets them go first, so the two are not held together)."""

from __future__ import annotations

import functools

from motiontool.motionfmt.document import MotionDocument, loads

__all__ = ["ReadOnUse"]


class ReadOnUse:
    """A mixin for an operation's (frozen) result dataclass that has ``data`` (the result's
    bytes) and ``path`` (its name)."""

    data: bytes
    path: str

    @functools.cached_property
    def document(self) -> MotionDocument:
        """The result, read as a document (on first use)."""
        return loads(self.data, self.path)
