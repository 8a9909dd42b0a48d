"""Rerun recordings of ``play`` runs: one ``.rrd`` per run, written without a viewer.

The only module that imports :mod:`rerun` (lazily). It logs to an explicit
:class:`rerun.RecordingStream` (never the global one) whose sink is a memory buffer, written to
the file atomically at the end. Layout of a recording:

- timeline ``sim_time`` (simulated seconds, a duration);
- ``/joints/<limb>/<joint>/commanded`` (the target as sent, clipped to the limits, at the time
  it is sent), ``.../measured`` (the joint position at every frame), ``.../lower`` and
  ``.../upper`` (the motor limits, two points each): scalar series, each logged with one
  ``send_columns`` call;
- ``/world/robot/<body>``: the body's pose at every frame (``Transform3D`` columns), its
  collision primitives as static ``Boxes3D`` / ``Capsules3D`` / ``Cylinders3D`` /
  ``Ellipsoids3D`` children; ``/world/scene/<body>``: the floor, the box;
- ``/world/base_trail``: the root body's path (``LineStrips3D``), ``/world/base``: its position
  at every frame (``Points3D``);
- an arm's end effector (the report's ``end_effector``): ``/world/tool`` its position at every
  frame (``Points3D``), ``/world/tool/trail`` its path so far, a growing ``LineStrips3D`` logged
  at the report's trail samples (the last one is the report's ``trail_position_m``),
  ``/world/tool/keyframes`` the commanded position of every keyframe, labelled with its name
  (static ``Points3D``);
- ``/events``: falls, collisions, limit hits, motion starts and simulator warnings
  (``TextLog``, level INFO / WARN / ERROR);
- a blueprint: the 3D view, the event log and one tab of joint plots per limb;
- recording properties ``stamps`` (tool and library versions, model hash, time steps, seed).

Read one back with ``rerun.chunk.RrdReader(path).stream().collect()`` (see the tests).
"""

from __future__ import annotations

import math
import uuid
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from motiontool.extras import require
from motiontool.motionfmt.fileio import atomic_write

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt
    import rerun
    import rerun.blueprint

    from motiontool.sim.motor import MotorLimits
    from motiontool.sim.play import Marker
    from motiontool.sim.report import EndEffectorStats
    from motiontool.sim.trace import BodyShapes, Shape, Trace

__all__ = ["APPLICATION_ID", "TIMELINE", "write_failure", "write_recording"]

APPLICATION_ID = "motiontool"
TIMELINE = "sim_time"

_LIMB_COLORS = (
    (230, 126, 34),
    (52, 152, 219),
    (46, 204, 113),
    (155, 89, 182),
    (241, 196, 15),
    (231, 76, 60),
    (26, 188, 156),
    (149, 165, 166),
)
_COMMANDED = (230, 80, 60)
_MEASURED = (40, 120, 230)
_LIMIT = (150, 150, 150)
_SCENE = (170, 170, 170)
_BASE_TRAIL = (255, 200, 0)
_TOOL = (0, 200, 255)
_KEYFRAME = (230, 80, 60)

LIMIT_WIDTH = 0.5
"""Width of a joint limit's line in the plots, UI points (the series' own are 1)."""

POINT_RADIUS_M = 0.01
"""Radius of the base's and the tool's moving point, m."""

BASE_TRAIL_RADIUS_M = 0.003
"""Radius of the base's path, m."""

TOOL_TRAIL_RADIUS_M = 0.002
"""Radius of the tool's path, m."""

KEYFRAME_RADIUS_M = 0.006
"""Radius of a keyframe's commanded tool position, m."""

PLANE_HALF_SIZE_M = 2.0
"""Half the side of an infinite plane as drawn (a 4 m x 4 m floor), m."""

PLANE_THICKNESS_M = 1e-4
"""Half the thickness of a plane as drawn (a thin box just below its surface), m."""

TOOL_TRAIL_ROWS = 400
"""At most this many rows of the growing tool trail (a longer run logs every n-th sample; the
last row is always the whole path)."""


def _stream(
    name: str, properties: Mapping[str, str]
) -> tuple[rerun.RecordingStream, rerun.MemoryRecording]:
    """A recording stream into memory, with its name and stamps.

    Every recording starts here, so this is where a missing rerun is one line naming
    ``motiontool[rerun]``; rerun ships its own types (``py.typed``), so the helpers below import
    it directly and mypy checks every call against them."""
    require("rerun", "rerun", "a Rerun recording")
    import rerun as rr

    recording_id = uuid.uuid5(uuid.NAMESPACE_URL, name + repr(sorted(properties.items())))
    rec = rr.RecordingStream(APPLICATION_ID, recording_id=recording_id, send_properties=False)
    memory = rec.memory_recording()
    rec.send_recording_name(name)
    if properties:
        rec.send_property("stamps", rr.AnyValues(drop_untyped_nones=True, **properties))
    return rec, memory


def _finish(rec: rerun.RecordingStream, memory: rerun.MemoryRecording, path: Path) -> None:
    rec.flush()
    data = memory.drain_as_bytes()
    rec.disconnect()
    atomic_write(path, data)


def write_failure(path: Path, message: str, properties: Mapping[str, str], name: str) -> None:
    """A recording holding only the stamps and ``message`` as an ERROR event (at 0 s): written
    when a run could not even start, so that ``--rrd`` always leaves a file."""
    rec, memory = _stream(name, properties)
    import rerun as rr

    rec.send_columns(
        "/events",
        indexes=[rr.TimeColumn(TIMELINE, duration=[0.0])],
        columns=rr.TextLog.columns(text=[message], level=["ERROR"]),
    )
    _finish(rec, memory, path)


def write_recording(
    path: Path,
    trace: Trace,
    shapes: Sequence[BodyShapes],
    *,
    limits: MotorLimits,
    joint_limbs: Sequence[str],
    markers: Sequence[Marker],
    properties: Mapping[str, str],
    name: str,
    end_effector: EndEffectorStats | None = None,
) -> None:
    """Write the recording of one run to ``path`` (atomically)."""
    rec, memory = _stream(name, properties)
    limbs = _log_joints(rec, trace, limits, joint_limbs)
    _log_bodies(rec, trace, shapes)
    _log_base(rec, trace)
    if end_effector is not None and trace.tool_pos is not None:
        _log_tool(rec, trace, end_effector)
    if markers:
        _log_events(rec, markers)
    rec.send_blueprint(_blueprint(limbs))
    _finish(rec, memory, path)


def _log_joints(
    rec: rerun.RecordingStream, trace: Trace, limits: MotorLimits, joint_limbs: Sequence[str]
) -> dict[str, list[str]]:
    """Joint series: commanded (clipped, as the motor sees it), measured, limits. Returns the
    entity of each joint, by limb."""
    import numpy as np
    import rerun as rr

    times = trace.time_s
    frames = rr.TimeColumn(TIMELINE, duration=times)
    steps = rr.TimeColumn(TIMELINE, duration=times[:-1])
    clipped = np.clip(trace.targets, limits.lower, limits.upper)
    limbs: dict[str, list[str]] = {}
    for j, joint in enumerate(trace.joints):
        base = f"/joints/{rr.escape_entity_path_part(joint_limbs[j])}/"
        base += rr.escape_entity_path_part(joint)
        limbs.setdefault(joint_limbs[j], []).append(base)
        _log_series(rec, f"{base}/commanded", steps, clipped[:, j], _COMMANDED, "commanded")
        _log_series(rec, f"{base}/measured", frames, trace.position[:, j], _MEASURED, "measured")
        _log_limits(rec, base, times, limits.lower[j], limits.upper[j])
    return limbs


def _log_series(
    rec: rerun.RecordingStream,
    entity: str,
    index: rerun.TimeColumn,
    values: npt.NDArray[np.float64],
    color: tuple[int, int, int],
    name: str,
) -> None:
    """One scalar series (one ``send_columns``; none when empty) and its static line style."""
    import rerun as rr

    if len(values):
        rec.send_columns(entity, indexes=[index], columns=rr.Scalars.columns(scalars=values))
    rec.log(entity, rr.SeriesLines(colors=[color], names=[name]), static=True)


def _log_limits(
    rec: rerun.RecordingStream,
    base: str,
    times: npt.NDArray[np.float64],
    lower: float,
    upper: float,
) -> None:
    """A joint's finite limits: a flat line each, from the first frame to the last."""
    import rerun as rr

    ends = rr.TimeColumn(TIMELINE, duration=[float(times[0]), float(times[-1])])
    for side, value in (("lower", lower), ("upper", upper)):
        if math.isfinite(value):
            rec.send_columns(
                f"{base}/{side}",
                indexes=[ends],
                columns=rr.Scalars.columns(scalars=[float(value), float(value)]),
            )
            rec.log(
                f"{base}/{side}",
                rr.SeriesLines(colors=[_LIMIT], names=[f"{side} limit"], widths=[LIMIT_WIDTH]),
                static=True,
            )


def _log_bodies(rec: rerun.RecordingStream, trace: Trace, shapes: Sequence[BodyShapes]) -> None:
    """Bodies: static primitives in the body frame, a robot body posed every frame."""
    import rerun as rr

    esc = rr.escape_entity_path_part
    frames = rr.TimeColumn(TIMELINE, duration=trace.time_s)
    limb_color = {
        limb: _LIMB_COLORS[i % len(_LIMB_COLORS)]
        for i, limb in enumerate(dict.fromkeys(s.limb for s in shapes if s.robot))
    }
    body_index = {b: i for i, b in enumerate(trace.bodies)}
    rec.log("/world", rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
    for body in shapes:
        root = f"/world/robot/{esc(body.name)}" if body.robot else f"/world/scene/{esc(body.name)}"
        _log_shapes(rec, root, body, limb_color.get(body.limb, _SCENE))
        if body.robot and body.name in body_index and len(trace.body_pos):
            b = body_index[body.name]
            rec.send_columns(
                root,
                indexes=[frames],
                columns=rr.Transform3D.columns(
                    translation=trace.body_pos[:, b],
                    quaternion=trace.body_quat[:, b][:, [1, 2, 3, 0]],  # xyzw
                ),
            )


def _log_base(rec: rerun.RecordingStream, trace: Trace) -> None:
    """The root body: its whole path (static), its position at every frame."""
    import numpy as np
    import rerun as rr

    rec.log(
        "/world/base_trail",
        rr.LineStrips3D([trace.base_pos], colors=[_BASE_TRAIL], radii=[BASE_TRAIL_RADIUS_M]),
        static=True,
    )
    rec.send_columns(
        "/world/base",
        indexes=[rr.TimeColumn(TIMELINE, duration=trace.time_s)],
        columns=rr.Points3D.columns(
            positions=trace.base_pos, radii=np.full(len(trace.time_s), POINT_RADIUS_M)
        ),
    )


def _log_events(rec: rerun.RecordingStream, markers: Sequence[Marker]) -> None:
    """The event log: one ``TextLog`` row per marker."""
    import rerun as rr

    rec.send_columns(
        "/events",
        indexes=[rr.TimeColumn(TIMELINE, duration=[m.time_s for m in markers])],
        columns=rr.TextLog.columns(
            text=[f"[{m.entity}] {m.text}" for m in markers],
            level=[m.level for m in markers],
        ),
    )


def _blueprint(limbs: Mapping[str, Sequence[str]]) -> rerun.blueprint.Blueprint:
    """The 3D view and the event log beside one tab of joint plots per limb."""
    import rerun.blueprint as rrb

    plots = [
        rrb.Grid(
            *[rrb.TimeSeriesView(origin=base, name=base.rsplit("/", 1)[1]) for base in bases],
            name=limb,
        )
        for limb, bases in limbs.items()
    ]
    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Vertical(
                rrb.Spatial3DView(origin="/world", name="robot"),
                rrb.TextLogView(origin="/events", name="events"),
                row_shares=[3, 1],
            ),
            rrb.Tabs(*plots) if plots else rrb.TextLogView(origin="/events"),
            column_shares=[1, 1],
        ),
        collapse_panels=True,
    )


def _log_tool(rec: rerun.RecordingStream, trace: Trace, ee: EndEffectorStats) -> None:
    """The tool: its position every frame, its growing path, the keyframes' targets."""
    import numpy as np
    import rerun as rr

    assert trace.tool_pos is not None
    rec.send_columns(
        "/world/tool",
        indexes=[rr.TimeColumn(TIMELINE, duration=trace.time_s)],
        columns=rr.Points3D.columns(
            positions=trace.tool_pos, radii=np.full(len(trace.time_s), POINT_RADIUS_M)
        ),
    )
    trail = np.array(ee.trail_position_m, dtype=np.float64).reshape(-1, 3)
    n = len(trail)
    if n:
        every = max(1, math.ceil(n / TOOL_TRAIL_ROWS))
        rows = list(range(every - 1, n, every))
        if rows[-1] != n - 1:
            rows.append(n - 1)
        rec.send_columns(
            "/world/tool/trail",
            indexes=[rr.TimeColumn(TIMELINE, duration=[ee.trail_time_s[r] for r in rows])],
            columns=rr.LineStrips3D.columns(strips=[trail[: r + 1] for r in rows]),
        )
        rec.log(
            "/world/tool/trail",
            rr.LineStrips3D.from_fields(colors=[_TOOL], radii=[TOOL_TRAIL_RADIUS_M]),
            static=True,
        )
    if ee.keyframes:
        rec.log(
            "/world/tool/keyframes",
            rr.Points3D(
                [k.commanded_position_m for k in ee.keyframes],
                labels=[k.name for k in ee.keyframes],
                colors=[_KEYFRAME],
                radii=[KEYFRAME_RADIUS_M],
            ),
            static=True,
        )


def _log_shapes(
    rec: rerun.RecordingStream, root: str, body: BodyShapes, color: tuple[int, int, int]
) -> None:
    """Log ``body``'s primitives under ``root``, in the body frame, one entity per kind."""
    by_kind: dict[str, list[Shape]] = {}
    for shape in body.shapes:
        by_kind.setdefault(shape.kind, []).append(shape)
    for kind, group in by_kind.items():
        drawn = _primitives(kind, group, color)
        if drawn is not None:
            rec.log(f"{root}/{drawn[0]}", drawn[1], static=True)


def _primitives(
    kind: str, group: Sequence[Shape], color: tuple[int, int, int]
) -> tuple[str, rerun.AsComponents] | None:
    """(entity name, archetype) of the primitives ``group`` of one ``kind``, or None for a kind
    that is not drawn."""
    import numpy as np
    import rerun as rr

    pos = np.array([s.pos for s in group], dtype=np.float64)
    quat = np.array([s.quat for s in group], dtype=np.float64)
    xyzw = quat[:, [1, 2, 3, 0]]
    size = np.array([s.size for s in group], dtype=np.float64)
    colors = [color] * len(group)
    if kind == "box":
        return "boxes", rr.Boxes3D(half_sizes=size, centers=pos, quaternions=xyzw, colors=colors)
    if kind == "capsule":  # Rerun's starts at its origin along +z; MuJoCo's is centred
        start = [_rotate(q, (0.0, 0.0, s[1])) for q, s in zip(quat, size, strict=True)]
        return "capsules", rr.Capsules3D(
            lengths=2 * size[:, 1],
            radii=size[:, 0],
            translations=pos - np.array(start),
            quaternions=xyzw,
            colors=colors,
        )
    if kind == "cylinder":
        return "cylinders", rr.Cylinders3D(
            lengths=2 * size[:, 1], radii=size[:, 0], centers=pos, quaternions=xyzw, colors=colors
        )
    if kind in ("sphere", "ellipsoid"):
        half = np.repeat(size[:, :1], 3, axis=1) if kind == "sphere" else size
        return f"{kind}s", rr.Ellipsoids3D(
            half_sizes=half, centers=pos, quaternions=xyzw, colors=colors, fill_mode="solid"
        )
    if kind == "plane":
        half = np.where(size[:, :2] > 0, size[:, :2], PLANE_HALF_SIZE_M)  # 0: infinite
        return "planes", rr.Boxes3D(
            half_sizes=np.column_stack([half, np.full(len(group), PLANE_THICKNESS_M)]),
            centers=pos - [0.0, 0.0, PLANE_THICKNESS_M],
            quaternions=xyzw,
            colors=colors,
            fill_mode="solid",
        )
    return None


def _rotate(quat: Iterable[float], v: tuple[float, float, float]) -> tuple[float, float, float]:
    """Rotate ``v`` by the unit quaternion ``quat`` (w, x, y, z)."""
    w, x, y, z = (float(c) for c in quat)
    vx, vy, vz = v
    # v + 2 w (q x v) + 2 q x (q x v)
    cx, cy, cz = y * vz - z * vy, z * vx - x * vz, x * vy - y * vx
    ddx, ddy, ddz = y * cz - z * cy, z * cx - x * cz, x * cy - y * cx
    return (vx + 2 * (w * cx + ddx), vy + 2 * (w * cy + ddy), vz + 2 * (w * cz + ddz))
