"""``--chain``, ``--loop N|NAME=N`` and ``--start-pose FILE[:POSE]``: how ``play`` plays its
motions as the elements of a chain and where the run starts (one spelling and help text each;
:mod:`motiontool.sim.chain` says what they do)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path, PurePath
from typing import TYPE_CHECKING, Annotated, Any

import typer

from motiontool.cli.options import MAX_COUNT
from motiontool.errors import MotionToolError

if TYPE_CHECKING:
    from motiontool.sim.session import PlayPlan

__all__ = [
    "AfterOption",
    "ChainOption",
    "LoopOption",
    "StartPoseOption",
    "chain_options",
    "loop_counts",
    "start_pose_options",
]

LoopOption = Annotated[
    list[str] | None,
    typer.Option(
        "--loop",
        metavar="N|NAME=N",
        help="Play each motion N times; with --chain, NAME=N plays the element NAME (its path,"
        " file name or stem) N times (repeat the option; the others play once, or N).",
        show_default=False,
    ),
]
ChainOption = Annotated[
    bool,
    typer.Option(
        "--chain",
        help="The motions are one chain, as a controller plays them: each from the state the one"
        " before left (the joints, the base and its velocities; as without --chain), an element"
        " looped on its own (--loop NAME=N), and the report lists each element with its time in"
        " the run, displacement and turn. A motions.toml 'after' makes a chain too.",
    ),
]
AfterOption = Annotated[
    Path | None,
    typer.Option(
        "--after",
        metavar="FILE",
        help="Play every motion after the motion FILE, in one run (a chain, as a motions.toml"
        " 'after': FILE's own 'after' is followed too); a motion whose motions.toml has an"
        " 'after' keeps it. The reports name every element.",
        show_default=False,
    ),
]
StartPoseOption = Annotated[
    str | None,
    typer.Option(
        "--start-pose",
        metavar="FILE[:POSE]",
        help="Start from the pose POSE of the motion FILE (without :POSE its last pose: where"
        " FILE leaves the robot) instead of the zero stance; with --start lying-*, the robot"
        " lies with these joints.",
        show_default=False,
    ),
]


def _is_element(name: str, path: str) -> bool:
    """Whether ``name`` names the element played from ``path``: the path as given, its file
    name or its stem."""
    pure = PurePath(path)
    return name in (path, pure.name, pure.stem)


def loop_counts(
    specs: Sequence[str], names: Sequence[str], *, chain: bool
) -> tuple[int, tuple[int, ...]]:
    """The cycles of each motion from ``--loop`` values: ``N`` (every motion) or ``NAME=N``
    (the elements ``NAME`` names, in a chain only; the others keep ``N``, else 1).

    Returns:
        (the count of every motion, the counts of each one in order; empty: no ``NAME=N``).

    Raises:
        MotionToolError: a count that is no whole number in 1..MAX_COUNT, two plain counts,
            ``NAME=N`` without ``chain`` or naming no element.
    """
    every, named = 1, {}
    plain = [s for s in specs if "=" not in s]
    if len(plain) > 1:
        raise MotionToolError(f"--loop {plain[0]} and --loop {plain[1]}: give one count")
    for spec in specs:
        name, equals, text = spec.rpartition("=")
        if not text.isdigit() or not 1 <= int(text) <= MAX_COUNT:
            raise MotionToolError(f"--loop {spec}: not in the range 1<=x<={MAX_COUNT}")
        if not equals:
            every = int(text)
            continue
        if not chain:
            raise MotionToolError(f"--loop {spec} loops one element of a chain: pass --chain")
        if not any(_is_element(name, n) for n in names):
            raise MotionToolError(
                f"--loop {spec}: no element {name!r} in the chain ({', '.join(names)})"
            )
        named[name] = int(text)
    if not named:
        return every, ()
    counts = [next((n for k, n in named.items() if _is_element(k, p)), every) for p in names]
    return every, tuple(counts)


def chain_options(
    loop: Sequence[str] | None, start_pose: str | None, planned: PlayPlan, *, chain: bool
) -> dict[str, Any]:
    """The :class:`~motiontool.sim.play.PlayOptions` of the run ``planned``: ``loops``,
    ``chain`` (``--chain``, or a sidecar's ``after``), ``chain_loops``, ``start_pose`` and its
    joints (:func:`start_pose_options`)."""
    chain = chain or bool(planned.motion.before)
    names = [str(f) for f in planned.files]
    loops, chain_loops = loop_counts(loop or [], names, chain=chain)
    return {
        "loops": loops,
        "chain": chain,
        "chain_loops": chain_loops,
        **start_pose_options(start_pose),
    }


def start_pose_options(start_pose: str | None) -> dict[str, Any]:
    """The :class:`~motiontool.sim.play.PlayOptions` of ``--start-pose``: ``start_pose`` and
    its joints (read here: a bad pose fails before the run, ``--start-pose X: ...``)."""
    from motiontool.sim.chain import start_pose as read_start_pose

    try:
        joints = () if start_pose is None else read_start_pose(start_pose)
    except MotionToolError as exc:
        raise MotionToolError(str(exc).replace("start pose ", "--start-pose ", 1)) from None
    return {"start_pose": start_pose, "start_pose_joints": joints}
