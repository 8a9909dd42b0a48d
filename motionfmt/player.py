"""The command stream a Webots controller sends while it plays a motion.

Reproduces ``wbu_motion_play`` + ``wb_robot_step``: at every step, *before* the physics step, each
joint's target is computed at the playback time ``elapsed`` (ms), then ``elapsed`` advances by the
time step. The interpolation is evaluated with the same double-precision expression and order of
operations as Webots' C code, so the targets are bit-identical::

    v[a] + (double)(elapsed - t[a]) * (v[b] - v[a]) / (double)(t[b] - t[a])

with ``a, b = a + 1`` the first segment such that ``t[a] <= elapsed <= t[b]``. A segment touching a
``*`` cell gives that joint no command, and so does a target that comes out exactly equal to
Webots' -9999999.9 marker (``motion_actuate`` skips it). A ``nan`` or ``inf`` cell IS a command:
Webots sends the NaN or infinity (``inf - inf`` interpolates to NaN) to the motor. So "no
command" is a separate mask (``commanded``), never NaN in the targets alone.

``elapsed`` is a C ``int`` (:mod:`.clock`): where adding the time step passes 2147483647 ms
before the motion ends, it wraps negative and the stream goes on as Webots' does, perhaps for
ever. :func:`iter_commands` gives the stream in chunks of bounded size, whatever its length;
:func:`sample` gives it whole.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, NamedTuple

from motiontool.errors import MotionToolError
from motiontool.motionfmt.clock import (  # the default step: re-exported, where callers find it
    WEBOTS_DEFAULT_TIMESTEP_MS,
    PlaybackNeverEndsError,
    clock_overflow,
    end_step,
    wrap_int,
)
from motiontool.motionfmt.reader import NO_VALUE_MARKER
from motiontool.motionfmt.units import MS_PER_S

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.motionfmt.motion import Motion

__all__ = [
    "MAX_HELD_STEPS",
    "WEBOTS_DEFAULT_TIMESTEP_MS",
    "CommandStream",
    "Held",
    "Holder",
    "StreamTooLongError",
    "commands_at",
    "elapsed_steps",
    "hold_targets",
    "iter_commands",
    "iter_elapsed",
    "played_steps",
    "require_held",
    "sample",
    "step_count",
    "steps_span",
    "targets_at",
]


@dataclass(frozen=True, eq=False)
class CommandStream:
    """What the controller commands, step by step.

    Attributes:
        joints: J joint names (the motion's columns).
        timestep_ms: the controller time step in milliseconds.
        elapsed_ms: int64 array (S,): the playback time of each step, in milliseconds.
        targets: float64 array (S, J): the position sent to each motor at each step (radians,
            metres for linear joints); NaN where the joint gets no command at that step, and
            also where the command itself is NaN (see ``commanded``).
        commanded: bool array (S, J): True where Webots' player sends a target to the joint at
            that step (the target may be NaN or infinite). When built without it, it is derived
            as ``~isnan(targets)``.
    """

    joints: tuple[str, ...]
    timestep_ms: int
    elapsed_ms: npt.NDArray[np.int64]
    targets: npt.NDArray[np.float64]
    commanded: npt.NDArray[np.bool_] = None  # type: ignore[assignment]  # derived when None

    def __post_init__(self) -> None:
        import numpy as np

        if self.commanded is None:
            object.__setattr__(self, "commanded", ~np.isnan(self.targets))


CHUNK_STEPS = 4096
"""Steps :func:`iter_commands` computes at once: (4096, J) arrays, whatever the duration."""


def _check_play(timestep_ms: int, loops: int) -> None:
    if timestep_ms <= 0:
        raise ValueError(f"timestep_ms must be positive, got {timestep_ms}")
    if loops < 1:
        raise ValueError(f"loops must be >= 1, got {loops}")


def step_count(
    duration_ms: int, timestep_ms: int, *, reverse: bool = False, loops: int = 1
) -> int | None:
    """How many steps (rows) the command stream has, or None where the motion never stops
    (Webots' clock wraps: :func:`motiontool.motionfmt.clock.clock_overflow`).

    Forward: ``end_step + 1`` a cycle (``ceil(D / T) + 1`` when the clock does not wrap).
    Reverse: ``ceil(D / T) + 1`` (counting down never wraps). Times ``loops``.
    """
    _check_play(timestep_ms, loops)
    if reverse:
        return (-(-duration_ms // timestep_ms) + 1) * loops
    last = end_step(duration_ms, timestep_ms)
    return None if last is None else (last + 1) * loops


def played_steps(
    duration_ms: int, timestep_ms: int, *, reverse: bool = False, loops: int = 1
) -> int:
    """:func:`step_count` of a motion that is played to its end.

    Raises:
        PlaybackNeverEndsError: the motion never stops at this time step (Webots' clock wraps).
    """
    _check_play(timestep_ms, loops)
    overflow = None if reverse else clock_overflow(duration_ms, timestep_ms)
    if overflow is not None and not overflow.ends:
        raise PlaybackNeverEndsError(overflow)
    steps = step_count(duration_ms, timestep_ms, reverse=reverse, loops=loops)
    assert steps is not None  # the clock does not wrap forever
    return steps


def iter_elapsed(
    duration_ms: int,
    timestep_ms: int,
    *,
    reverse: bool = False,
    loops: int = 1,
    chunk_steps: int = CHUNK_STEPS,
    max_steps: int | None = None,
) -> Iterator[npt.NDArray[np.int64]]:
    """:func:`elapsed_steps` in int64 chunks of at most ``chunk_steps`` steps, in order; the
    first ``max_steps`` steps only (None: every step).

    Endless where the motion never stops (its clock wraps: see :func:`step_count`) and
    ``max_steps`` is None.
    """
    import numpy as np

    _check_play(timestep_ms, loops)
    if chunk_steps < 1:
        raise ValueError(f"chunk_steps must be >= 1, got {chunk_steps}")
    if reverse:
        steps: int | None = -(-duration_ms // timestep_ms) + 1
        start, step = duration_ms, -timestep_ms  # counts down to the first time <= 0: no wrap
    else:
        last = end_step(duration_ms, timestep_ms)
        steps = None if last is None else last + 1
        start, step = 0, timestep_ms
    left = max_steps
    for _ in range(loops):
        done, elapsed = 0, start
        while steps is None or done < steps:
            n = chunk_steps if steps is None else min(chunk_steps, steps - done)
            if left is not None:
                if left <= 0:
                    return
                n = min(n, left)
                left -= n
            chunk = elapsed + np.arange(n, dtype=np.int64) * step  # |values| < 2**44: no overflow
            if not reverse:  # C int arithmetic, as Webots' player adds the time step
                chunk = (chunk + 2**31) % 2**32 - 2**31
            yield chunk
            done += n
            elapsed = wrap_int(elapsed + n * step)


MAX_HELD_STEPS = 2_000_000
"""Most controller steps (or grid poses) held whole in memory: 11 h at the Nao's 20 ms step,
about 0.5 GB of arrays for its 26 joints. :func:`iter_commands` streams any number."""


class StreamTooLongError(MotionToolError):
    """A whole command stream (or grid) of more than :data:`MAX_HELD_STEPS` steps was asked
    for: refused before it is built, rather than exhausting the machine's memory."""


def require_held(steps: int, step_ms: int, what: str = "the command stream") -> None:
    """Refuse to hold ``steps`` of ``step_ms`` ms whole in memory past :data:`MAX_HELD_STEPS`.

    Raises:
        StreamTooLongError: ``the command stream: 100,000,001 steps of 20 ms (555.6 h), ...``.
    """
    if steps > MAX_HELD_STEPS:
        raise StreamTooLongError(
            f"{what}: {steps_span(steps, step_ms)}, more than the {MAX_HELD_STEPS:,} held in "
            "memory at once; trim the motion first (motiontool trim), or read its command "
            "stream a chunk at a time (motiontool sample)"
        )


def steps_span(steps: int, step_ms: int, noun: str = "steps") -> str:
    """``100,000,001 steps of 20 ms (555.6 h)``: how long ``steps`` of ``step_ms`` ms last."""
    hours = steps * step_ms / MS_PER_S / 3600
    return f"{steps:,} {noun} of {step_ms} ms ({hours:,.1f} h)"


def elapsed_steps(
    duration_ms: int, timestep_ms: int, *, reverse: bool = False, loops: int = 1
) -> npt.NDArray[np.int64]:
    """Playback times (ms) at which a controller stepping every ``timestep_ms`` computes targets.

    Forward: ``0, T, 2T, ...`` up to and including the first multiple of ``T`` that is
    ``>= duration_ms``, in C ``int`` arithmetic (where ``kT`` passes 2147483647 ms the time
    wraps negative and goes on until it lands in ``[duration_ms, 2147483647]``). Reverse:
    ``D, D - T, ...`` down to the first value ``<= 0``. With ``loops > 1`` the cycle repeats,
    as Webots' loop mode restarts at the other end.

    Raises:
        PlaybackNeverEndsError: the clock wraps and the motion never stops at this time step.
        StreamTooLongError: more than :data:`MAX_HELD_STEPS` steps.
    """
    import numpy as np

    steps = played_steps(duration_ms, timestep_ms, reverse=reverse, loops=loops)
    require_held(steps, timestep_ms)
    cycle = np.concatenate(
        list(iter_elapsed(duration_ms, timestep_ms, reverse=reverse, chunk_steps=1 << 20))
    )
    return np.tile(cycle, loops)


def commands_at(
    motion: Motion, elapsed_ms: npt.NDArray[np.int64]
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
    """What Webots' player sends at the given playback times (ms).

    Returns:
        ``targets`` float64 (S, J), rad (m for linear joints), NaN where no command is sent (and
        where the command is NaN), and ``commanded`` bool (S, J): whether a target is sent.
    """
    import numpy as np

    t, v, c = motion.times_ms, motion.values, motion.commanded
    e = np.asarray(elapsed_ms, dtype=np.int64)
    if t.shape[0] == 1:
        out = np.repeat(v, e.shape[0], axis=0)
        sent = np.repeat(c, e.shape[0], axis=0)
    else:  # interpolate every step in its segment, then set the steps at either end
        a = np.clip(np.searchsorted(t, e, side="left") - 1, 0, t.shape[0] - 2)
        va = v[a]
        sent = c[a] & c[a + 1]
        with np.errstate(invalid="ignore", over="ignore", divide="ignore"):  # as in C
            out = v[a + 1] - va
            out *= (e - t[a]).astype(np.float64)[:, None]
            out /= (t[a + 1] - t[a]).astype(np.float64)[:, None]
            out += va
        for end, row in ((e >= t[-1], -1), (e <= t[0], 0)):  # the first pose wins a tie
            if end.any():
                out[end] = v[row]
                sent[end] = c[row]
    sent &= out != NO_VALUE_MARKER  # Webots skips a target equal to its 'no value' marker
    np.copyto(out, np.nan, where=~sent)
    return out, sent


def targets_at(motion: Motion, elapsed_ms: npt.NDArray[np.int64]) -> npt.NDArray[np.float64]:
    """Targets (S, J) at the given playback times, NaN where no command is sent.

    NaN also where the command itself is NaN: use :func:`commands_at` to tell them apart.
    """
    return commands_at(motion, elapsed_ms)[0]


def sample(
    motion: Motion,
    timestep_ms: int,
    *,
    reverse: bool = False,
    loops: int = 1,
    max_steps: int | None = None,
) -> CommandStream:
    """The command stream of ``motion`` played by a controller stepping every ``timestep_ms``,
    whole, in memory: (S, J) arrays. :func:`iter_commands` streams it in bounded chunks.

    Args:
        max_steps: keep only the first steps, at most this many (the stream of a motion that
            never ends included); None: every step.

    Raises:
        PlaybackNeverEndsError: the motion never stops at this time step (Webots' clock wraps)
            and ``max_steps`` is None.
    """
    import numpy as np

    if max_steps is None:
        elapsed = elapsed_steps(motion.duration_ms, timestep_ms, reverse=reverse, loops=loops)
    else:
        if max_steps < 1:
            raise ValueError(f"max_steps must be >= 1, got {max_steps}")
        chunks = iter_elapsed(
            motion.duration_ms,
            timestep_ms,
            reverse=reverse,
            loops=loops,
            chunk_steps=min(max_steps, 1 << 20),
            max_steps=max_steps,
        )
        elapsed = np.concatenate(list(chunks))
    targets, commanded = commands_at(motion, elapsed)
    return CommandStream(motion.joints, timestep_ms, elapsed, targets, commanded)


def iter_commands(
    motion: Motion,
    timestep_ms: int,
    *,
    reverse: bool = False,
    loops: int = 1,
    chunk_steps: int = CHUNK_STEPS,
    max_steps: int | None = None,
) -> Iterator[CommandStream]:
    """The command stream of :func:`sample`, in consecutive chunks of at most ``chunk_steps``
    steps: memory stays bounded whatever the duration, and the first chunk comes at once.

    Where the motion never stops at this time step (Webots' clock wraps:
    :func:`step_count` is None) the iterator is endless, as Webots' player is: bound it with
    ``max_steps`` (the first steps only, at most this many; None: every step).
    """
    for elapsed in iter_elapsed(
        motion.duration_ms,
        timestep_ms,
        reverse=reverse,
        loops=loops,
        chunk_steps=chunk_steps,
        max_steps=max_steps,
    ):
        targets, commanded = commands_at(motion, elapsed)
        yield CommandStream(motion.joints, timestep_ms, elapsed, targets, commanded)


class Held(NamedTuple):
    """The targets the motors hold, step by step (see :func:`hold_targets`).

    Attributes:
        targets: float64 (S, N): the target each motor holds at each step, rad (m for linear
            joints): the one sent at that step, else the previous one, else the initial one.
        sent: bool (S, N): whether a target is sent to the motor at that step.
        holding: bool (S, N): whether the motor holds a target sent at or before that step (or
            one it held before the first step: ``holding`` of :func:`hold_targets`).
    """

    targets: npt.NDArray[np.float64]
    sent: npt.NDArray[np.bool_]
    holding: npt.NDArray[np.bool_]


def _by_motor(
    targets: npt.NDArray[np.float64],
    commanded: npt.NDArray[np.bool_],
    joints: Sequence[str] | None,
    names: Sequence[str] | None,
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.bool_]]:
    """The targets (S, N) and whether each is sent, per motor of ``names``, of the columns
    ``joints`` (:func:`hold_targets`'s arguments): where two columns send to one motor at a
    step, the later column's target."""
    import numpy as np

    if names is None or (joints is not None and list(joints) == list(names)):
        return targets, commanded  # one column per motor, in order: nothing to merge
    if joints is None:
        raise ValueError("names needs joints: the column names to merge by")
    index = {name: k for k, name in enumerate(names)}
    out = np.full((targets.shape[0], len(names)), np.nan)
    sent = np.zeros(out.shape, dtype=np.bool_)
    for j, name in enumerate(joints):
        k = index.get(name)
        if k is None:
            continue
        column = commanded[:, j]
        out[column, k] = targets[column, j]  # a later column overwrites where it sends
        sent[:, k] |= column
    return out, sent


def hold_targets(
    targets: npt.NDArray[np.float64],
    commanded: npt.NDArray[np.bool_],
    joints: Sequence[str] | None = None,
    names: Sequence[str] | None = None,
    *,
    initial: npt.NDArray[np.float64] | None = None,
    holding: npt.NDArray[np.bool_] | None = None,
) -> Held:
    """What each motor holds while a command stream plays: the one forward-fill of motiontool.

    Webots' player calls ``wb_motor_set_position`` once per column that sends a target, in
    column order, and a motor keeps its last target until it gets another. So, of two columns
    with one name, the later one's target wins at a step where it sends one, and the earlier
    one's reaches the motor where the later sends none; a step where no column sends a target
    holds the previous one.

    Args:
        targets: float64 (S, C): the targets of C columns at S steps (or poses), rad.
        commanded: bool (S, C): whether each target is sent (a sent target may be NaN or
            infinite: Webots sends a ``nan`` or ``inf`` cell).
        joints: the C column names; with ``names``, columns are merged by name.
        names: the N motors to report, in order; a name no column has is never sent, a column
            whose name is not here is dropped. None: the C columns as they are (N = C).
        initial: float64 (N,): the target each motor holds before its first command, rad;
            NaN (none) when None.
        holding: bool (N,): whether each motor holds ``initial`` as a target (for ``holding``
            of the result); False when None.

    Returns:
        :class:`Held`, every array (S, N). To go on with a later stream, pass the last row of
        ``targets`` and ``holding`` as ``initial`` and ``holding``.
    """
    import numpy as np

    out, sent = _by_motor(targets, commanded, joints, names)
    steps, n = out.shape
    start = np.full(n, np.nan) if initial is None else np.asarray(initial, dtype=np.float64)
    held_before = np.zeros(n, dtype=np.bool_) if holding is None else holding
    held = np.array(out, dtype=np.float64)  # a motor sent a target at every step holds it
    holds = np.ones((steps, n), dtype=np.bool_)
    gaps = np.flatnonzero(~sent.all(axis=0))  # the motors that miss a target at some step
    if gaps.size:
        last = np.where(sent[:, gaps], np.arange(steps)[:, None], -1)  # the last step that sent
        np.maximum.accumulate(last, axis=0, out=last)
        before = last < 0
        held[:, gaps] = np.where(
            before, start[gaps][None, :], np.take_along_axis(out[:, gaps], np.maximum(last, 0), 0)
        )
        holds[:, gaps] = np.where(before, held_before[gaps][None, :], True)
    return Held(held, sent, holds)


class Holder:
    """:func:`hold_targets` of a stream given a chunk of steps (or poses) at a time, each chunk
    going on from what the one before left held: the one home of that carry.

    Args:
        names: the N motors to report, in order (``names`` of :func:`hold_targets`); None: the
            columns of each chunk as they are.
        initial, holding: what the motors hold before the first chunk (as in
            :func:`hold_targets`); after each chunk, the last row of its result.
    """

    def __init__(
        self,
        names: Sequence[str] | None = None,
        *,
        initial: npt.NDArray[np.float64] | None = None,
        holding: npt.NDArray[np.bool_] | None = None,
    ) -> None:
        self.names = names
        self.initial = initial
        self.holding = holding

    def hold(
        self,
        targets: npt.NDArray[np.float64],
        commanded: npt.NDArray[np.bool_],
        joints: Sequence[str] | None = None,
    ) -> Held:
        """What the motors hold at the chunk's steps: its targets (S, C) and whether each is
        sent (S, C), of the columns ``joints`` (merged by name as :func:`hold_targets` does)."""
        held = hold_targets(
            targets, commanded, joints, self.names, initial=self.initial, holding=self.holding
        )
        if held.targets.shape[0]:
            self.initial, self.holding = held.targets[-1], held.holding[-1]
        return held
