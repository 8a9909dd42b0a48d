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
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from motiontool.motionfmt.extras import require
from motiontool.motionfmt.fileio import atomic_write

if TYPE_CHECKING:
    from motiontool.sim.motor import MotorLimits
    from motiontool.sim.play import Marker
    from motiontool.sim.report import EndEffectorStats
    from motiontool.sim.trace import BodyShapes, Trace

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
_TOOL = (0, 200, 255)
_KEYFRAME = (230, 80, 60)

TOOL_TRAIL_ROWS = 400
"""At most this many rows of the growing tool trail (a longer run logs every n-th sample; the
last row is always the whole path)."""


def _rerun(module: str) -> Any:
    """``rerun`` (or a submodule), or a one-line error naming ``motiontool[rerun]``."""
    return require(module, "rerun", "a Rerun recording (--rrd, --rrd-dir)")


def _stream(name: str, properties: Mapping[str, str]) -> tuple[Any, Any]:
    rr = _rerun("rerun")

    recording_id = uuid.uuid5(uuid.NAMESPACE_URL, name + repr(sorted(properties.items())))
    rec = rr.RecordingStream(APPLICATION_ID, recording_id=recording_id, send_properties=False)
    memory = rec.memory_recording()
    rec.send_recording_name(name)
    if properties:
        values: dict[str, Any] = dict(properties)
        rec.send_property("stamps", rr.AnyValues(**values))
    return rec, memory


def _finish(rec: Any, memory: Any, path: Path) -> None:
    rec.flush()
    data = memory.drain_as_bytes()
    rec.disconnect()
    atomic_write(path, data)


def write_failure(path: Path, message: str, properties: Mapping[str, str], name: str) -> None:
    """A recording holding only the stamps and ``message`` as an ERROR event (at 0 s): written
    when a run could not even start, so that ``--rrd`` always leaves a file."""
    rr = _rerun("rerun")

    rec, memory = _stream(name, properties)
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
    import numpy as np

    rr = _rerun("rerun")
    rrb = _rerun("rerun.blueprint")

    rec, memory = _stream(name, properties)
    esc = rr.escape_entity_path_part
    times = trace.time_s
    frames = rr.TimeColumn(TIMELINE, duration=times)
    steps = rr.TimeColumn(TIMELINE, duration=times[:-1])
    ends = rr.TimeColumn(TIMELINE, duration=[float(times[0]), float(times[-1])])

    # Joint series: commanded (clipped, as the motor sees it), measured, limits.
    clipped = np.clip(trace.targets, limits.lower, limits.upper)
    limbs: dict[str, list[str]] = {}
    for j, joint in enumerate(trace.joints):
        base = f"/joints/{esc(joint_limbs[j])}/{esc(joint)}"
        limbs.setdefault(joint_limbs[j], []).append(base)
        if len(clipped):
            rec.send_columns(
                f"{base}/commanded",
                indexes=[steps],
                columns=rr.Scalars.columns(scalars=clipped[:, j]),
            )
        rec.send_columns(
            f"{base}/measured",
            indexes=[frames],
            columns=rr.Scalars.columns(scalars=trace.position[:, j]),
        )
        rec.log(
            f"{base}/commanded",
            rr.SeriesLines(colors=[_COMMANDED], names=["commanded"]),
            static=True,
        )
        rec.log(
            f"{base}/measured", rr.SeriesLines(colors=[_MEASURED], names=["measured"]), static=True
        )
        for side, value in (("lower", limits.lower[j]), ("upper", limits.upper[j])):
            if math.isfinite(value):
                rec.send_columns(
                    f"{base}/{side}",
                    indexes=[ends],
                    columns=rr.Scalars.columns(scalars=[float(value), float(value)]),
                )
                rec.log(
                    f"{base}/{side}",
                    rr.SeriesLines(colors=[_LIMIT], names=[f"{side} limit"], widths=[0.5]),
                    static=True,
                )

    # Bodies: static primitives in the body frame, the body posed every frame.
    limb_color = {
        limb: _LIMB_COLORS[i % len(_LIMB_COLORS)]
        for i, limb in enumerate(dict.fromkeys(s.limb for s in shapes if s.robot))
    }
    body_index = {b: i for i, b in enumerate(trace.bodies)}
    rec.log("/world", rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
    for body in shapes:
        root = f"/world/robot/{esc(body.name)}" if body.robot else f"/world/scene/{esc(body.name)}"
        color = limb_color.get(body.limb, (170, 170, 170))
        _log_shapes(rec, root, body, color)
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
    rec.log(
        "/world/base_trail",
        rr.LineStrips3D([trace.base_pos], colors=[(255, 200, 0)], radii=[0.003]),
        static=True,
    )
    rec.send_columns(
        "/world/base",
        indexes=[frames],
        columns=rr.Points3D.columns(positions=trace.base_pos, radii=np.full(len(times), 0.01)),
    )

    if end_effector is not None and trace.tool_pos is not None:
        _log_tool(rec, trace, end_effector)

    if markers:
        rec.send_columns(
            "/events",
            indexes=[rr.TimeColumn(TIMELINE, duration=[m.time_s for m in markers])],
            columns=rr.TextLog.columns(
                text=[f"[{m.entity}] {m.text}" for m in markers],
                level=[m.level for m in markers],
            ),
        )

    plots = [
        rrb.Grid(
            *[rrb.TimeSeriesView(origin=base, name=base.rsplit("/", 1)[1]) for base in bases],
            name=limb,
        )
        for limb, bases in limbs.items()
    ]
    blueprint = rrb.Blueprint(
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
    rec.send_blueprint(blueprint)
    _finish(rec, memory, path)


def _log_tool(rec: Any, trace: Trace, ee: EndEffectorStats) -> None:
    """The tool: its position every frame, its growing path, the keyframes' targets."""
    import numpy as np

    rr = _rerun("rerun")

    assert trace.tool_pos is not None
    rec.send_columns(
        "/world/tool",
        indexes=[rr.TimeColumn(TIMELINE, duration=trace.time_s)],
        columns=rr.Points3D.columns(
            positions=trace.tool_pos, radii=np.full(len(trace.time_s), 0.01)
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
            rr.LineStrips3D.from_fields(colors=[_TOOL], radii=[0.002]),
            static=True,
        )
    if ee.keyframes:
        rec.log(
            "/world/tool/keyframes",
            rr.Points3D(
                [k.commanded_position_m for k in ee.keyframes],
                labels=[k.name for k in ee.keyframes],
                colors=[_KEYFRAME],
                radii=[0.006],
            ),
            static=True,
        )


def _log_shapes(rec: Any, root: str, body: BodyShapes, color: tuple[int, int, int]) -> None:
    """Log ``body``'s primitives under ``root``, in the body frame, one entity per kind."""
    import numpy as np

    rr = _rerun("rerun")

    by_kind: dict[str, list[Any]] = {}
    for shape in body.shapes:
        by_kind.setdefault(shape.kind, []).append(shape)
    for kind, group in by_kind.items():
        pos = np.array([s.pos for s in group], dtype=np.float64)
        quat = np.array([s.quat for s in group], dtype=np.float64)
        xyzw = quat[:, [1, 2, 3, 0]]
        size = np.array([s.size for s in group], dtype=np.float64)
        colors = [color] * len(group)
        if kind == "box":
            rec.log(
                f"{root}/boxes",
                rr.Boxes3D(half_sizes=size, centers=pos, quaternions=xyzw, colors=colors),
                static=True,
            )
        elif kind == "capsule":
            # Rerun's capsule starts at its origin and runs along +z; MuJoCo's is centred.
            start = pos - np.array(
                [_rotate(q, (0.0, 0.0, s[1])) for q, s in zip(quat, size, strict=True)]
            )
            rec.log(
                f"{root}/capsules",
                rr.Capsules3D(
                    lengths=2 * size[:, 1],
                    radii=size[:, 0],
                    translations=start,
                    quaternions=xyzw,
                    colors=colors,
                ),
                static=True,
            )
        elif kind == "cylinder":
            rec.log(
                f"{root}/cylinders",
                rr.Cylinders3D(
                    lengths=2 * size[:, 1],
                    radii=size[:, 0],
                    centers=pos,
                    quaternions=xyzw,
                    colors=colors,
                ),
                static=True,
            )
        elif kind in ("sphere", "ellipsoid"):
            half = np.repeat(size[:, :1], 3, axis=1) if kind == "sphere" else size
            rec.log(
                f"{root}/{kind}s",
                rr.Ellipsoids3D(
                    half_sizes=half, centers=pos, quaternions=xyzw, colors=colors, fill_mode="solid"
                ),
                static=True,
            )
        elif kind == "plane":
            half = np.where(size[:, :2] > 0, size[:, :2], 2.0)  # an infinite plane: 4 m x 4 m
            rec.log(
                f"{root}/planes",
                rr.Boxes3D(
                    half_sizes=np.column_stack([half, np.full(len(group), 1e-4)]),
                    centers=pos - [0.0, 0.0, 1e-4],
                    quaternions=xyzw,
                    colors=colors,
                    fill_mode="solid",
                ),
                static=True,
            )


def _rotate(quat: Any, v: tuple[float, float, float]) -> tuple[float, float, float]:
    """Rotate ``v`` by the unit quaternion ``quat`` (w, x, y, z)."""
    w, x, y, z = (float(c) for c in quat)
    vx, vy, vz = v
    # v + 2 w (q x v) + 2 q x (q x v)
    cx, cy, cz = y * vz - z * vy, z * vx - x * vz, x * vy - y * vx
    ddx, ddy, ddz = y * cz - z * cy, z * cx - x * cz, x * cy - y * cx
    return (vx + 2 * (w * cx + ddx), vy + 2 * (w * cy + ddy), vz + 2 * (w * cz + ddz))
