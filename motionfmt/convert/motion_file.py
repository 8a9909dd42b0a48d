"""Webots' own ``.motion`` format, as a row of the registry: read exactly as Webots reads it
(:func:`motiontool.motionfmt.reader.read_bytes`), written in the canonical spelling
(:func:`motiontool.motionfmt.writer.format_motion`: shortest round-trip numbers, ``*``)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from motiontool.motionfmt.convert.base import Exported, ExportOptions, Imported, ImportOptions
from motiontool.motionfmt.reader import read_bytes
from motiontool.motionfmt.writer import format_motion

if TYPE_CHECKING:
    from motiontool.motionfmt.motion import Motion

__all__ = ["read_motion_file", "write_motion_file"]


def read_motion_file(data: bytes, path: str, options: ImportOptions | None = None) -> Imported:
    """The motion Webots plays (:class:`MotionSyntaxError` where Webots rejects the file)."""
    read = read_bytes(data, path)
    return Imported(read.motion, path, read)


def write_motion_file(motion: Motion, options: ExportOptions) -> Exported:
    """``motion`` as a new ``.motion`` file in the canonical spelling."""
    data = format_motion(motion).encode("utf-8", "surrogateescape")
    return Exported(data, motion.n_poses, f"{motion.n_joints} joints")
