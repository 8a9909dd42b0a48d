"""The command stream of a run: the targets Webots' player holds at each control step while the
motions play one after another, then while the last targets are held. A run reads it a chunk
at a time (:func:`command_stream`), so that it is never held whole."""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from typing import TYPE_CHECKING, NamedTuple

from motiontool.errors import MotionToolError
from motiontool.motionfmt import Motion
from motiontool.motionfmt.player import Holder, iter_commands, played_steps, steps_span

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = [
    "CHUNK_STEPS",
    "MAX_RUN_STEPS",
    "CommandChunks",
    "command_matrix",
    "command_stream",
    "each_loops",
]

CHUNK_STEPS = 2048
"""Control steps a run simulates and measures at once: 41 s at the Nao's 20 ms, 16 s at the
UR5e's 8 ms; a longer run goes on a chunk at a time, in flat memory (larger chunks gain no
speed, and hold more)."""

MAX_RUN_STEPS = 2_000_000
"""Most control steps a run simulates (11 h at the Nao's 20 ms): its memory stays flat, but a
longer run would compute for hours; it is refused in one line before it starts."""

Chunk = tuple["npt.NDArray[np.float64]", "npt.NDArray[np.bool_]"]
"""(K, J) targets in force and (K, J) whether each was sent, for K consecutive steps."""


def each_loops(loops: int | Sequence[int], count: int) -> list[int]:
    """The cycles of each of ``count`` motions: ``loops`` each, or ``loops`` as given (one per
    motion)."""
    if isinstance(loops, int):
        return [loops] * count
    if len(loops) != count:
        raise MotionToolError(f"{len(loops)} loop counts for {count} motions")
    return list(loops)


class CommandChunks(NamedTuple):
    """The command stream of a run, to be read once (:func:`command_stream`).

    Attributes:
        chunks: the targets in force at each step (a step without a command keeps the previous
            target; before the first, the initial one) and whether the motion sent them, in
            consecutive chunks of at most ``CHUNK_STEPS`` steps.
        lengths: the number of steps of each motion.
        ignored: the motion columns that are not motors (ignored, as Webots does).
        steps: the control steps of the whole run, the motions' and the hold's.
    """

    chunks: Iterator[Chunk]
    lengths: list[int]
    ignored: list[str]
    steps: int


def command_stream(
    motions: Sequence[Motion],
    joints: Sequence[str],
    timestep_ms: int,
    initial: npt.NDArray[np.float64],
    *,
    reverse: bool = False,
    loops: int | Sequence[int] = 1,
    hold_steps: int = 0,
    chunk_steps: int | None = None,
) -> CommandChunks:
    """The targets in force at each control step of the sequence ``motions``, in chunks.

    Args:
        motions: played one after another; each starts at the step after the previous ends.
        joints: the robot's J motors.
        timestep_ms: control step, ms.
        initial: (J,) positions the motors hold before their first command, rad (m).
        reverse, loops: Webots' reverse and loop modes, applied to each motion (``loops``: one
            count for every motion, or one per motion: the elements of a chain).
        hold_steps: steps appended after the last motion, with no command.
        chunk_steps: steps a chunk holds at most (None: :data:`CHUNK_STEPS`).

    Raises:
        PlaybackNeverEndsError: a motion never stops at this time step: before any chunk.
        MotionToolError: more than :data:`MAX_RUN_STEPS` steps, before any chunk; (while the
            chunks are read) a motion commands a non-finite target.
    """
    counts = each_loops(loops, len(motions))
    lengths = [
        played_steps(m.duration_ms, timestep_ms, reverse=reverse, loops=n)
        for m, n in zip(motions, counts, strict=True)
    ]
    steps = sum(lengths) + hold_steps
    if steps > MAX_RUN_STEPS:
        raise MotionToolError(
            f"the run: {steps_span(steps, timestep_ms, 'control steps')}, more than the "
            f"{MAX_RUN_STEPS:,} a run simulates; trim the motion (motiontool trim), play fewer "
            "loops or hold the last targets for less time"
        )
    motors = set(joints)
    ignored = list(dict.fromkeys(n for m in motions for n in m.joints if n not in motors))
    size = chunk_steps or CHUNK_STEPS  # read when called: a test may set it
    streams = _streams(motions, joints, timestep_ms, reverse, counts, hold_steps, size)
    return CommandChunks(_sized(_held(streams, joints, initial), size), lengths, ignored, steps)


def _streams(
    motions: Sequence[Motion],
    joints: Sequence[str],
    timestep_ms: int,
    reverse: bool,
    loops: Sequence[int],
    hold_steps: int,
    size: int,
) -> Iterator[tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_], Sequence[str]]]:
    """Each motion's stream, then the hold steps (no command), as (targets, sent, columns)."""
    import numpy as np

    for motion, n in zip(motions, loops, strict=True):
        for s in iter_commands(motion, timestep_ms, reverse=reverse, loops=n, chunk_steps=size):
            yield s.targets, s.commanded, s.joints
    for done in range(0, hold_steps, size):
        n = min(size, hold_steps - done)
        yield np.full((n, len(joints)), np.nan), np.zeros((n, len(joints)), dtype=np.bool_), joints


def _held(
    streams: Iterator[tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_], Sequence[str]]],
    joints: Sequence[str],
    initial: npt.NDArray[np.float64],
) -> Iterator[Chunk]:
    """What the motors hold at each step of ``streams``, each chunk going on from what the one
    before left held (:class:`motiontool.motionfmt.player.Holder`)."""
    import numpy as np

    holder = Holder(joints, initial=initial)
    for targets, sent, names in streams:
        held = holder.hold(targets, sent, names)
        if not bool(np.isfinite(held.targets[held.sent]).all()):  # play() checks the files first
            raise MotionToolError("a motion commands a non-finite target (nan or inf): not played")
        yield held.targets, held.sent


def _sized(chunks: Iterator[Chunk], size: int) -> Iterator[Chunk]:
    """``chunks`` joined and cut into chunks of ``size`` steps (the last may be shorter): one
    chunk for a run of up to ``size`` steps, however many motions it plays."""
    import numpy as np

    parts: list[Chunk] = []
    held = 0
    for chunk in chunks:
        parts.append(chunk)
        held += len(chunk[0])
        while held >= size:
            targets = np.concatenate([p[0] for p in parts])
            sent = np.concatenate([p[1] for p in parts])
            yield targets[:size], sent[:size]
            parts = [(targets[size:], sent[size:])]
            held -= size
    if held:
        yield np.concatenate([p[0] for p in parts]), np.concatenate([p[1] for p in parts])


def command_matrix(
    stream: CommandChunks,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_], list[int], list[str]]:
    """The whole of a command stream (:func:`command_stream`), in memory.

    Returns:
        targets (S, J) float64, commanded (S, J) bool, the number of steps of each motion, and
        the motion columns that are not motors.
    """
    import numpy as np

    chunks = list(stream.chunks)
    targets = np.concatenate([c[0] for c in chunks])
    commanded = np.concatenate([c[1] for c in chunks])
    return targets, commanded, stream.lengths, stream.ignored
