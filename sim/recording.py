"""Rerun recordings of ``play`` runs: one ``.rrd`` per run, written without a viewer.

The module that imports :mod:`rerun` (lazily; :mod:`motiontool.sim.recording_shapes` draws the
collision primitives). It logs to an explicit :class:`rerun.RecordingStream` (never the global
one) whose sink is a temporary file, logged a chunk of the run at a time and copied to the
output at the end (:class:`RunRecorder`). Layout of a recording:

- timeline ``sim_time`` (simulated seconds, a duration);
- ``/joints/<limb>/<joint>/commanded`` (the target as sent, clipped to the limits, at the time
  it is sent), ``.../measured`` (the joint position at every frame), ``.../lower`` and
  ``.../upper`` (the motor limits, two points each): scalar series, logged with one
  ``send_columns`` call a chunk of the run;
- ``/world/robot/<body>``: the body's pose at every frame (``Transform3D`` columns), its
  collision primitives as static ``Boxes3D`` / ``Capsules3D`` / ``Cylinders3D`` /
  ``Ellipsoids3D`` children; ``/world/scene/<body>``: the floor, the box;
- ``/world/base_trail``: the root body's path (``LineStrips3D``, at most
  :data:`BASE_TRAIL_POINTS` frames of it), ``/world/base``: its position at every frame
  (``Points3D``);
- an arm's end effector (the report's ``end_effector``): ``/world/tool`` its position at every
  frame (``Points3D``), ``/world/tool/trail`` its path so far, a growing ``LineStrips3D`` logged
  at the report's trail samples (the last one is the report's ``trail_position_m``),
  ``/world/tool/keyframes`` the commanded position of every keyframe, labelled with its name
  (static ``Points3D``);
- ``/events``: falls, collisions, limit hits, motion starts and simulator warnings
  (``TextLog``, level INFO / WARN / ERROR);
- a run in a Webots world: ``/webots_world``, what was applied of it and what was not
  (:mod:`motiontool.sim.recording_world`);
- a blueprint: the 3D view, the event log (and the world) and one tab of joint plots per limb;
- recording properties ``stamps`` (tool and library versions, model hash, time steps, seed).

Read one back with ``rerun.chunk.RrdReader(path).stream().collect()`` (see the tests).
"""

from __future__ import annotations

import contextlib
import math
import tempfile
import uuid
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from motiontool.errors import OutputError
from motiontool.extras import require
from motiontool.motionfmt.fileio import atomic_write, open_output, temporary_folder
from motiontool.sim.live import LiveView, attach
from motiontool.sim.recording_paths import Thinned, thin
from motiontool.sim.recording_shapes import log_shapes
from motiontool.sim.recording_world import WORLD_ENTITY, log_world

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt
    import rerun
    import rerun.blueprint

    from motiontool.sim.motor import MotorLimits
    from motiontool.sim.play import Marker
    from motiontool.sim.report import EndEffectorStats
    from motiontool.sim.trace import BodyShapes, Trace

__all__ = ["APPLICATION_ID", "BASE_TRAIL_POINTS", "TIMELINE", "RunRecorder", "write_failure"]

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

TOOL_TRAIL_ROWS = 400
"""At most this many rows of the growing tool trail (a longer run logs every n-th sample; the
last row is always the whole path)."""

TOOL_TRAIL_POINTS = 1000
"""At most this many points in a row of the tool trail (a longer path keeps every n-th sample
and its last one): the trail of a long run holds 400 x 1000 points, not 400 x its samples."""


def _stream(
    name: str, properties: Mapping[str, str], file: Path | None = None, live: LiveView | None = None
) -> tuple[rerun.RecordingStream, rerun.MemoryRecording | None]:
    """A recording stream into memory (None: into ``file``, as it is logged, and to ``live``'s
    viewer), with its name and stamps.

    Every recording starts here, so this is where a missing rerun is one line naming
    ``motiontool[rerun]``; rerun ships its own types (``py.typed``), so the helpers below import
    it directly and mypy checks every call against them."""
    require("rerun", "rerun", "a Rerun recording")
    import rerun as rr

    run = name + repr(sorted(properties.items()))  # one id a run; live, one a take (a new one)
    recording_id = uuid.uuid4() if live else uuid.uuid5(uuid.NAMESPACE_URL, run)
    rec = rr.RecordingStream(APPLICATION_ID, recording_id=recording_id, send_properties=False)
    memory = None
    if file is None:
        memory = rec.memory_recording()
    elif live is not None:
        attach(rec, live, file)
    else:
        rec.save(file)
    rec.send_recording_name(name)
    if properties:
        rec.send_property("stamps", rr.AnyValues(drop_untyped_nones=True, **properties))
    return rec, memory


def _finish(rec: rerun.RecordingStream, memory: rerun.MemoryRecording | None, path: Path) -> None:
    rec.flush()
    assert memory is not None
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


class RunRecorder:
    """The recording of one run, logged a chunk of the run at a time (:meth:`add` each chunk
    of :func:`motiontool.sim._mujoco.run_chunks` in order, then :meth:`finish`).

    What is logged goes to a temporary file as it is logged, so memory stays flat whatever the
    run's duration; :meth:`finish` copies that file to ``path`` as every output is written
    (:func:`motiontool.motionfmt.fileio.open_output`: a regular file whole or not at all, a
    FIFO or a device straight through). :meth:`close` (also on leaving a ``with`` block)
    removes the temporary file. With ``live``, what is logged is also shown live
    (:mod:`motiontool.sim.live`; no ``path``: only there). The root body's whole path keeps at most
    :data:`BASE_TRAIL_POINTS` of its frames (every other one, then every fourth, ..., as the
    run goes on); its position at every frame is logged in full.
    """

    def __init__(
        self,
        path: Path | None,
        shapes: Sequence[BodyShapes],
        *,
        limits: MotorLimits,
        joints: Sequence[str],
        joint_limbs: Sequence[str],
        properties: Mapping[str, str],
        name: str,
        live: LiveView | None = None,
    ) -> None:
        import rerun as rr

        self.path, self.limits, self.joint_limbs, self.shapes = path, limits, joint_limbs, shapes
        try:
            self._folder = temporary_folder("motiontool-rrd-")  # SIGTERM-safe
        except OSError as exc:
            raise OutputError(
                f"cannot write the recording '{path}': no temporary folder: {exc.strerror or exc}"
            ) from exc
        try:  # stopped here (an error, SIGTERM): no temporary folder left behind
            self.rec, _ = _stream(name, properties, Path(self._folder.name) / "run.rrd", live)
            self.rec.log("/world", rr.ViewCoordinates.RIGHT_HAND_Z_UP, static=True)
            self._entities = _joint_entities(joints, joint_limbs)
            colors = _limb_color(shapes)
            for body in shapes:
                log_shapes(self.rec, _body_entity(body), body, colors.get(body.limb, _SCENE))
            if live is not None:  # the layout from the start (again at the end, with the world)
                self.rec.send_blueprint(_blueprint(self._limbs(), world=False))
        except BaseException:
            self.close()
            raise
        self._trail = Thinned(BASE_TRAIL_POINTS)
        self._start_s: float | None = None  # the run's first frame's time
        self._last: Trace | None = None

    def __enter__(self) -> RunRecorder:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _limbs(self) -> dict[str, list[str]]:
        """Each limb's joint entities."""
        limbs: dict[str, list[str]] = {}
        for limb, base in zip(self.joint_limbs, self._entities, strict=True):
            limbs.setdefault(limb, []).append(base)
        return limbs

    def close(self) -> None:
        """Stop logging and remove the temporary file (the recording is lost unless
        :meth:`finish` wrote it)."""
        if hasattr(self, "rec"):
            with contextlib.suppress(RuntimeError):  # a sink that failed: finish said so
                self.rec.disconnect()
        self._folder.cleanup()

    def add(self, chunk: Trace) -> None:
        """Log the next chunk of the run: its frames (but the first, the last of the chunk
        before) and its steps."""
        new = 0 if self._last is None else 1
        _log_joints(self.rec, chunk, new, self.limits, self._entities)
        _log_bodies(self.rec, chunk, new, self.shapes)
        _log_base(self.rec, chunk, new)
        if chunk.tool_pos is not None:
            _log_points(self.rec, "/world/tool", chunk.time_s[new:], chunk.tool_pos[new:])
        self._trail.add(chunk.first_frame + new, chunk.base_pos[new:])
        if self._start_s is None:
            self._start_s = float(chunk.time_s[0])
        self._last = chunk

    def finish(
        self,
        markers: Sequence[Marker],
        end_effector: EndEffectorStats | None,
        world: Mapping[str, object] | None = None,
    ) -> None:
        """Log what is known at the end of the run (the limits over its time, the root body's
        path, the tool's keyframes and path, the events, the report's ``world``, the
        blueprint) and write the recording to ``path``."""
        import rerun as rr

        assert self._start_s is not None and self._last is not None, "a run has a chunk at least"
        rec = self.rec
        span = (self._start_s, float(self._last.time_s[-1]))
        for j, base in enumerate(self._entities):
            _log_limits(rec, base, span, self.limits.lower[j], self.limits.upper[j])
        trail = self._trail.points(self._last.last_frame, self._last.base_pos[-1])
        rec.log(
            "/world/base_trail",
            rr.LineStrips3D([trail], colors=[_BASE_TRAIL], radii=[BASE_TRAIL_RADIUS_M]),
            static=True,
        )
        if end_effector is not None:
            _log_tool(rec, end_effector)
        if markers:
            _log_events(rec, markers)
        if world is not None:
            log_world(rec, world)
        rec.send_blueprint(_blueprint(self._limbs(), world=world is not None))
        try:
            rec.flush()
        except RuntimeError as exc:  # the file sink stopped: a full or unwritable disk
            raise OutputError(
                f"cannot write the recording '{self.path}': its temporary file under "
                f"{tempfile.gettempdir()} could not be written ({exc}); is that disk full?"
            ) from exc
        rec.disconnect()
        if self.path is None:
            return
        with open_output(self.path) as sink, open(Path(self._folder.name) / "run.rrd", "rb") as f:
            while block := f.read(1 << 20):
                sink.write(block)


BASE_TRAIL_POINTS = 20_000
"""At most this many frames in the root body's whole path (400 s at the Nao's 20 ms)."""


def _joint_entities(joints: Sequence[str], joint_limbs: Sequence[str]) -> list[str]:
    """Each joint's entity: ``/joints/<limb>/<joint>``."""
    import rerun as rr

    esc = rr.escape_entity_path_part
    return [f"/joints/{esc(limb)}/{esc(j)}" for j, limb in zip(joints, joint_limbs, strict=True)]


def _log_joints(
    rec: rerun.RecordingStream, trace: Trace, new: int, limits: MotorLimits, entities: Sequence[str]
) -> None:
    """Joint series of a chunk: commanded (clipped, as the motor sees it) at its steps,
    measured at its frames from ``new`` on."""
    import numpy as np
    import rerun as rr

    frames = rr.TimeColumn(TIMELINE, duration=trace.time_s[new:])
    steps = rr.TimeColumn(TIMELINE, duration=trace.time_s[:-1])
    clipped = np.clip(trace.targets, limits.lower, limits.upper)
    first = new == 0  # the run's first chunk: the series' styles are logged once
    for j, base in enumerate(entities):
        _log_series(rec, f"{base}/commanded", steps, clipped[:, j], _COMMANDED, "commanded", first)
        _log_series(
            rec, f"{base}/measured", frames, trace.position[new:, j], _MEASURED, "measured", first
        )


def _log_series(
    rec: rerun.RecordingStream,
    entity: str,
    index: rerun.TimeColumn,
    values: npt.NDArray[np.float64],
    color: tuple[int, int, int],
    name: str,
    style: bool,
) -> None:
    """Part of a scalar series (one ``send_columns``; none when empty), and with ``style`` its
    static line style."""
    import rerun as rr

    if len(values):
        rec.send_columns(entity, indexes=[index], columns=rr.Scalars.columns(scalars=values))
    if style:
        rec.log(entity, rr.SeriesLines(colors=[color], names=[name]), static=True)


def _log_limits(
    rec: rerun.RecordingStream, base: str, span: tuple[float, float], lower: float, upper: float
) -> None:
    """A joint's finite limits: a flat line each, over ``span`` (the first and last frame's
    times, s)."""
    import rerun as rr

    ends = rr.TimeColumn(TIMELINE, duration=list(span))
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


def _body_entity(body: BodyShapes) -> str:
    """``/world/robot/<body>`` or ``/world/scene/<body>``."""
    import rerun as rr

    group = "robot" if body.robot else "scene"
    return f"/world/{group}/{rr.escape_entity_path_part(body.name)}"


def _limb_color(shapes: Sequence[BodyShapes]) -> dict[str, tuple[int, int, int]]:
    """The colour of each limb of the robot, in the order its bodies come."""
    limbs = dict.fromkeys(s.limb for s in shapes if s.robot)
    return {limb: _LIMB_COLORS[i % len(_LIMB_COLORS)] for i, limb in enumerate(limbs)}


def _log_bodies(
    rec: rerun.RecordingStream, trace: Trace, new: int, shapes: Sequence[BodyShapes]
) -> None:
    """Each robot body's pose at the chunk's frames from ``new`` on."""
    import rerun as rr

    if not len(trace.body_pos):
        return
    frames = rr.TimeColumn(TIMELINE, duration=trace.time_s[new:])
    body_index = {b: i for i, b in enumerate(trace.bodies)}
    for body in shapes:
        if body.robot and body.name in body_index:
            b = body_index[body.name]
            rec.send_columns(
                _body_entity(body),
                indexes=[frames],
                columns=rr.Transform3D.columns(
                    translation=trace.body_pos[new:, b],
                    quaternion=trace.body_quat[new:, b][:, [1, 2, 3, 0]],  # xyzw
                ),
            )


def _log_base(rec: rerun.RecordingStream, trace: Trace, new: int) -> None:
    """The root body's position at the chunk's frames from ``new`` on."""
    _log_points(rec, "/world/base", trace.time_s[new:], trace.base_pos[new:])


def _log_points(
    rec: rerun.RecordingStream,
    entity: str,
    times: npt.NDArray[np.float64],
    positions: npt.NDArray[np.float64],
) -> None:
    """A moving point: its position (m) at each of ``times`` (s)."""
    import numpy as np
    import rerun as rr

    rec.send_columns(
        entity,
        indexes=[rr.TimeColumn(TIMELINE, duration=times)],
        columns=rr.Points3D.columns(positions=positions, radii=np.full(len(times), POINT_RADIUS_M)),
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


def _blueprint(limbs: Mapping[str, Sequence[str]], *, world: bool) -> rerun.blueprint.Blueprint:
    """The 3D view and the event log (in a tab beside the ``world`` document) beside one tab
    of joint plots per limb."""
    import rerun.blueprint as rrb

    events: rrb.View | rrb.Tabs = rrb.TextLogView(origin="/events", name="events")
    if world:
        events = rrb.Tabs(events, rrb.TextDocumentView(origin=WORLD_ENTITY, name="world"))

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
                events,
                row_shares=[3, 1],
            ),
            rrb.Tabs(*plots) if plots else rrb.TextLogView(origin="/events"),
            column_shares=[1, 1],
        ),
        collapse_panels=True,
    )


def _log_tool(rec: rerun.RecordingStream, ee: EndEffectorStats) -> None:
    """The tool (its position every frame is logged with each chunk): its growing path, the
    keyframes' targets."""
    import numpy as np
    import rerun as rr

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
            columns=rr.LineStrips3D.columns(
                strips=[thin(trail[: r + 1], TOOL_TRAIL_POINTS) for r in rows]
            ),
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
