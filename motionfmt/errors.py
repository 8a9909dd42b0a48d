"""The import path of motiontool 0.1 for its errors, which live in :mod:`motiontool.errors`
(every layer raises them; motiontool's own modules import them from there)."""

from motiontool.errors import MissingExtraError, MotionSyntaxError, MotionToolError

__all__ = ["MissingExtraError", "MotionSyntaxError", "MotionToolError"]
