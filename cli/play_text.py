"""The text report of a ``play`` run, for people: the outcome, the robot, the feet, contacts,
the end effector, then one row per commanded joint."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from motiontool.cli.text import file_name, plural
from motiontool.motionfmt.units import MM_PER_M

if TYPE_CHECKING:
    from motiontool.sim.report import ContactSummary, PlayReport

__all__ = ["render_text"]


def _num(value: float | None, fmt: str, unit: str) -> str:
    return "n/a" if value is None or not math.isfinite(value) else f"{value:{fmt}} {unit}"


def _contacts(title: str, rows: list[ContactSummary], limit: int = 8) -> list[str]:
    if not rows:
        return [f"{title}: none"]
    lines = [f"{title}: {len(rows)}"]
    for c in rows[:limit]:
        lines.append(
            f"  {c.body_a} / {c.body_b}: from {c.first_s:.2f} s, {c.duration_s:.2f} s in all, "
            f"max depth {c.max_depth_m * MM_PER_M:.1f} mm"
        )
    if len(rows) > limit:
        lines.append(f"  ... and {len(rows) - limit} more (see --json)")
    return lines


def _end_effector(report: PlayReport, limit: int = 32) -> list[str]:
    """An arm's tool: the largest deviation, then a table of keyframes (time, position error,
    lag); past ``limit`` keyframes, the ``limit // 2`` worst, in the order first played."""
    ee = report.end_effector
    if ee is None:
        return []
    lines = [
        f"end effector {ee.frame}: largest deviation from the commanded path "
        f"{ee.max_deviation_mm:.1f} mm at {ee.max_deviation_at_s:.2f} s; lag: time to come "
        f"within {ee.reach_tolerance_mm:g} mm of a keyframe (- : not before the next one)"
    ]
    rows = list(enumerate(ee.keyframes))
    if len(rows) > limit:
        worst = sorted(rows, key=lambda r: -r[1].position_error_mm)[: limit // 2]
        rows = sorted(worst, key=lambda r: r[0])
    if not rows:
        return lines
    folded = any(k.visits > 1 for k in ee.keyframes)
    if folded:
        lines[0] += "; a keyframe reached several times: its worst visit, its longest lag"
    wn = max(8, *(len(k.name) for _i, k in rows))
    visits = f" {'visits':>6}" if folded else ""
    lines.append(f"  {'keyframe':<{wn}} {'time':>9} {'error':>10} {'lag':>8}{visits}")
    for _i, k in rows:
        lag = "-" if k.lag_ms is None else f"{k.lag_ms:.0f} ms"
        row = f"  {k.name:<{wn}} {k.time_s:>7.3f} s {k.position_error_mm:>7.1f} mm {lag:>8}"
        lines.append(row + (f" {k.visits:>6}" if folded else ""))
    if len(rows) < len(ee.keyframes):
        lines.append(
            f"  ... {len(ee.keyframes) - len(rows)} more keyframes with smaller errors (see --json)"
        )
    return lines


def _joint_table(report: PlayReport) -> list[str]:
    """One row per commanded joint: tracking errors and time at the caps; none without one."""
    rows = [j for j in report.joints if j.commanded]
    if not rows:
        return []
    wj = max(5, *(len(j.name) for j in rows))
    wl = max(4, *(len(j.limb) for j in rows))
    lines = [
        f"{'joint':<{wj}} {'limb':<{wl}} {'rms error':>11} {'max error':>11} "
        f"{'at vel cap':>10} {'at torque cap':>13} {'clipped':>8}"
    ]
    for j in rows:
        lines.append(
            f"{j.name:<{wj}} {j.limb:<{wl}} {j.rms_error:>7.4f} {j.unit:<3} "
            f"{j.max_error:>7.4f} {j.unit:<3} {j.velocity_cap_s:>8.2f} s "
            f"{j.torque_cap_s:>11.2f} s {j.target_clipped_s:>6.2f} s"
        )
    return lines


def _world(report: PlayReport) -> list[str]:
    """What ``--world`` applied and what it did not, one line each."""
    world = report.world
    if world is None:
        return []
    node = world["robot_node"]
    lines = [
        f"world: {world['path']}, robot node {node['name']!r}"
        + (f" (DEF {node['def']})" if node["def"] else "")
    ]
    for entry in world["applied"]:
        unit = f" {entry['unit']}" if entry["unit"] else ""
        lines.append(f"  applied: {entry['field']} {_value(entry['value'])}{unit}: "
                     f"{entry['applied_as']}")  # fmt: skip
    for entry in world["not_applied"]:
        unit = f" {entry['unit']}" if entry["unit"] else ""
        lines.append(f"  not applied: {entry['field']} {_value(entry['value'])}{unit}: "
                     f"{entry['reason']}")  # fmt: skip
    lines += [f"  skipped: {line}" for line in world["skipped_nodes"]]
    return lines


def _self_collision(report: PlayReport) -> list[str]:
    """Whether the robot's parts collided with each other, why, how many pairs touched (not
    said of a run as the robot's model has it, without self-collision physics)."""
    doc = report.self_collision
    if doc is None or (doc["source"] == "robot model" and not doc["physics"]):
        return []
    why = doc["why"]
    if doc["source"] == "option":  # the library's words; the flag is the command line's
        why = "--self-collision" if doc["physics"] else "--no-self-collision"
    if not doc["physics"]:
        return [f"self-collision physics: off ({why})"]
    return [
        f"self-collision physics: on ({why}); {doc['touching_pairs']} pairs of bodies "
        f"touched, {doc['touching_s']:.2f} s in all"
    ]


def _chain(report: PlayReport) -> list[str]:
    """A chain's elements, one line each: cycles, time in the run, what the base did."""
    if not report.options.get("chain"):
        return []
    lines = [f"chain: {plural(len(report.files), 'element')}"]
    for k, f in enumerate(report.files, 1):
        cycles = f" x{f.loops}" if f.loops > 1 else ""
        line = (
            f"  {k}. {file_name(f.path)}{cycles}: {f.start_s:.2f}-{f.start_s + f.duration_s:.2f} s"
        )
        if f.dx_m is not None and f.dy_m is not None and f.yaw_change_deg is not None:
            line += f", dx {f.dx_m:+.3f} m, dy {f.dy_m:+.3f} m, turn {f.yaw_change_deg:+.1f} deg"
        lines.append(line)
    return lines


def _value(value: object) -> str:
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if isinstance(value, list):
        return " ".join(f"{v:g}" for v in value)
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


def render_text(report: PlayReport) -> str:
    """The summary for people: the outcome, the robot, the feet, contacts, then one row per
    commanded joint."""
    stamps_ = report.stamps
    names = " + ".join(file_name(f.path) for f in report.files)
    lines = [
        f"{names} on {report.robot}: {report.simulated_s:.2f} s simulated "
        f"({report.control_steps} control steps of {stamps_.get('control_step_ms')} ms, "
        f"physics step {stamps_.get('physics_step_ms'):g} ms"
        + (f", floor friction {report.physics['friction']:g}" if report.physics else "")
        + ")",
        *([f"note: {report.physics['profile_note']}"] if "profile_note" in report.physics else []),
        *_world(report),
        *_self_collision(report),
        *_chain(report),
        "result: " + ("clean" if report.clean else "; ".join(report.problems)),
    ]
    if report.expectations:
        lines.append(f"expectations: {sum(r.passed for r in report.expectations)} of "
                     f"{len(report.expectations)} met")  # fmt: skip
        lines += [f"  {r.summary()}" for r in report.expectations]
    base = report.base
    if base is not None:
        lines.append(
            f"base: dx {base.dx_m:+.3f} m, dy {base.dy_m:+.3f} m, "
            f"yaw {_num(base.yaw_change_deg, '+.1f', 'deg')}, "
            f"max tilt {base.max_tilt_deg:.1f} deg, final tilt {base.final_tilt_deg:.1f} deg, "
            f"height {base.final_height_m:.3f} m (min {base.min_height_m:.3f} m)"
            + (f", fell at {base.fell_at_s:.2f} s" if base.fell_at_s is not None else "")
        )
    for foot in report.feet:
        lines.append(
            f"foot {foot.name}: on the floor {foot.contact_s:.2f} s, "
            f"slip {foot.slip_m * MM_PER_M:.1f} mm, "
            f"moved {foot.max_displacement_m * MM_PER_M:.1f} mm at most, "
            f"{foot.final_displacement_m * MM_PER_M:.1f} mm at the end"
        )
    lines += _end_effector(report)
    lines += _contacts("self-collisions", report.self_collisions)
    lines += _contacts("contacts with anything but the floor", report.scene_contacts)
    if report.ground_contacts:
        lines += _contacts("other body parts on the floor", report.ground_contacts, limit=4)
    raised = {k: v for k, v in report.warnings.items() if v}
    lines.append(
        "MuJoCo warnings: " + (", ".join(f"{k} x{v}" for k, v in raised.items()) or "none")
    )
    if report.ignored_joints:
        lines.append("ignored (not motors of the robot): " + ", ".join(report.ignored_joints))
    lines += _joint_table(report)
    if report.error:
        lines.append(f"error: {report.error}")
    return "\n".join(lines) + "\n"
