"""Inverse kinematics (kinematics/ik.py) and the UR5e motions generated with it."""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Iterable
from pathlib import Path

import numpy as np
import pytest
from conftest import ROOT
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.errors import MotionToolError
from motiontool.kinematics import ik, ur5e_tasks
from motiontool.kinematics.ik import Pose, forward_pose, frame_jacobian, solve_ik
from motiontool.kinematics.robots import load_robot
from motiontool.kinematics.ur5e_tasks import (
    BINS_XY_M,
    FLANGE_FRAME,
    GRASP_Z_M,
    PICK_XY_M,
    PLACE_Z_M,
    TABLE_TOP_Z_M,
    TRAVEL_Z_M,
    Task,
    flange_pose,
    generate,
    jog_motion,
    segment_ms,
    sorting_motion,
    sorting_plan,
    sorting_spots,
)
from motiontool.motionfmt import format_motion, read_motion, sample, validate_paths
from motiontool.motionfmt.motion import Motion

UR5E = load_robot("ur5e")
NAMES = UR5E.joint_names
MOTIONS = ROOT / "motions" / "ur5e"
#: Waypoint accuracy the generated files must keep (the brief's 1 mm / 1 degree).
WAYPOINT_POSITION_TOLERANCE_M = 1e-3
WAYPOINT_ORIENTATION_TOLERANCE_RAD = math.radians(1.0)
#: Below travel height the flange must be straight above the pick-up point or a bin, within
#: this horizontal distance (m). Webots interpolates joints, not the flange, between keyframes:
#: the flange drifts 6.8 mm sideways in the 0.15 m descent to the belt and 18.5 mm in the
#: 0.25 m descent into a bin.
PICK_DESCENT_RADIUS_M = 0.01
BIN_DESCENT_RADIUS_M = 0.025


def q_of(values: Iterable[float]) -> dict[str, float]:
    """Motor name -> rad, from six values in model order."""
    return dict(zip(NAMES, (float(v) for v in values), strict=True))


def random_configurations(n: int, seed: int) -> np.ndarray:
    """Random UR5e configurations, rad, shape (n, 6), away from the elbow's ±π stops."""
    rng = np.random.default_rng(seed)
    q = rng.uniform(-math.pi, math.pi, size=(n, 6))
    q[:, 2] = rng.uniform(-2.8, 2.8, size=n)
    return q


# --------------------------------------------------------------------------- IK


@pytest.mark.needs("kinematics")
def test_flange_frame_is_the_tool_slot_0_1_m_along_wrist_3_y() -> None:
    q = q_of(random_configurations(1, 3)[0])
    wrist = forward_pose(UR5E, q, "wrist_3_link")
    flange = forward_pose(UR5E, q, FLANGE_FRAME)
    np.testing.assert_allclose(flange.position, wrist.position + 0.1 * wrist.rotation[:, 1])
    np.testing.assert_allclose(flange.rotation, wrist.rotation, atol=1e-12)
    # ur5e.json derived_checks: tool_slot at (0.817, 0.234, 0.063) m at q = 0
    zero = forward_pose(UR5E, q_of([0] * 6), FLANGE_FRAME)
    np.testing.assert_allclose(zero.position, [0.817, 0.234, 0.063], atol=1e-6)


@pytest.mark.needs("kinematics")
@pytest.mark.parametrize("index", range(24))
def test_ik_round_trips_forward_kinematics(index: int) -> None:
    q_true = random_configurations(24, 2024)[index]
    target = forward_pose(UR5E, q_of(q_true), FLANGE_FRAME)
    rng = np.random.default_rng(index)
    seed = q_true + rng.uniform(-0.3, 0.3, size=6)
    solution = solve_ik(UR5E, target, q_of(seed), frame=FLANGE_FRAME)
    reached = forward_pose(UR5E, solution.q_by_joint, FLANGE_FRAME)
    position, angle = reached.errors_to(target)
    assert position <= ik.DEFAULT_POSITION_TOLERANCE_M
    assert angle <= ik.DEFAULT_ORIENTATION_TOLERANCE_RAD
    assert (position, angle) == pytest.approx(
        (solution.position_error_m, solution.orientation_error_rad), abs=1e-12
    )
    for joint in UR5E.joints:
        assert joint.lower <= solution.q_by_joint[joint.name] <= joint.upper


@pytest.mark.needs("kinematics")
def test_ik_stays_on_the_seed_branch() -> None:
    """Seeded next to a configuration, IK returns that configuration, not another branch."""
    for q_true in random_configurations(8, 7):
        target = forward_pose(UR5E, q_of(q_true), FLANGE_FRAME)
        solution = solve_ik(UR5E, target, q_of(q_true + 0.05), frame=FLANGE_FRAME)
        np.testing.assert_allclose(solution.values(NAMES), q_true, atol=1e-4)


@pytest.mark.needs("kinematics")
def test_ik_fails_cleanly_on_an_unreachable_pose() -> None:
    far = Pose([1.5, 0.0, 0.5], np.eye(3))  # the arm reaches about 1 m
    with pytest.raises(MotionToolError) as info:
        solve_ik(UR5E, far, q_of([0, -1.2, 1.8, -2.2, -1.57, 0]), frame=FLANGE_FRAME)
    message = str(info.value)
    assert "did not converge" in message and "tool_slot" in message
    assert " mm and " in message and " deg away" in message
    assert "\n" not in message
    # the remaining error is honest: at least the distance beyond the arm's reach
    assert float(message.split("still ")[1].split(" mm")[0]) > 300


@pytest.mark.needs("kinematics")
def test_ik_respects_joint_limits() -> None:
    """An elbow limited to [0.5, 1.0] rad: the solver stays inside, and a target that needs
    the elbow at 1.5 rad is out of reach."""
    limited = dataclasses.replace(
        UR5E,
        joints=tuple(
            dataclasses.replace(j, lower=0.5, upper=1.0) if j.name == "elbow_joint" else j
            for j in UR5E.joints
        ),
    )
    q_true = np.array([0.3, -1.4, 0.8, -1.0, 1.2, 0.4])
    target = forward_pose(UR5E, q_of(q_true), FLANGE_FRAME)
    seed = q_true.copy()
    seed[2] = 2.0  # outside the limits: clamped before the first step
    solution = solve_ik(limited, target, q_of(seed), frame=FLANGE_FRAME)
    assert 0.5 <= solution.q_by_joint["elbow_joint"] <= 1.0
    assert forward_pose(UR5E, solution.q_by_joint, FLANGE_FRAME).errors_to(target)[0] < 1e-6
    q_true[2] = 1.5
    beyond = forward_pose(UR5E, q_of(q_true), FLANGE_FRAME)
    with pytest.raises(MotionToolError, match="did not converge"):
        solve_ik(limited, beyond, q_of(q_true), frame=FLANGE_FRAME)
    assert solve_ik(UR5E, beyond, q_of(q_true), frame=FLANGE_FRAME).iterations == 0


@pytest.mark.needs("kinematics")
def test_ik_solves_with_a_joint_resting_on_its_limit() -> None:
    """The target needs wrist_3 exactly at its (narrowed) upper limit; the seed's other motors
    are off, so steps keep pushing wrist_3 outward: it must stay on the limit, not block."""
    limited = dataclasses.replace(
        UR5E,
        joints=tuple(
            dataclasses.replace(j, lower=-0.5, upper=0.4) if j.name == "wrist_3_joint" else j
            for j in UR5E.joints
        ),
    )
    q_true = np.array([0.3, -1.4, 1.1, -1.0, 1.2, 0.4])
    target = forward_pose(UR5E, q_of(q_true), FLANGE_FRAME)
    seed = q_true + np.array([0.15, -0.1, 0.1, 0.2, -0.15, 0.0])
    solution = solve_ik(limited, target, q_of(seed), frame=FLANGE_FRAME)
    assert solution.q_by_joint["wrist_3_joint"] <= 0.4
    np.testing.assert_allclose(solution.values(NAMES), q_true, atol=1e-4)


@pytest.mark.needs("kinematics")
def test_ik_moves_only_the_chosen_joints() -> None:
    q_true = np.array([0.2, -1.0, 1.2, -1.5, -1.2, 0.3])
    target = forward_pose(UR5E, q_of(q_true), FLANGE_FRAME)
    arm = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint"]
    seed = q_true.copy()
    seed[:3] += 0.1
    solution = solve_ik(UR5E, target, q_of(seed), frame=FLANGE_FRAME, joints=arm)
    assert solution.values(NAMES)[3:] == seed[3:].tolist()  # the wrist kept its seed
    np.testing.assert_allclose(solution.values(NAMES), q_true, atol=1e-4)
    seed[3:] += 0.2  # a wrong, frozen wrist: the orientation cannot follow
    with pytest.raises(MotionToolError, match="did not converge"):
        solve_ik(UR5E, target, q_of(seed), frame=FLANGE_FRAME, joints=arm)


@pytest.mark.needs("kinematics")
def test_ik_errors_name_the_choices() -> None:
    target = Pose([0.4, 0.1, 0.4], np.eye(3))
    with pytest.raises(MotionToolError, match=r"no frame 'flange'; choose one of .*tool_slot"):
        solve_ik(UR5E, target, {}, frame="flange")
    with pytest.raises(MotionToolError, match="did you mean 'elbow_joint'"):
        solve_ik(UR5E, target, {}, frame=FLANGE_FRAME, joints=["elbow_jiont"])
    with pytest.raises(MotionToolError, match="orthonormal"):
        Pose([0, 0, 0], 2 * np.eye(3))


def _rotation_vector(rotation: np.ndarray) -> np.ndarray:
    """Axis × angle (rad) of a rotation matrix (angle < π)."""
    angle = math.acos(max(-1.0, min(1.0, (np.trace(rotation) - 1) / 2)))
    if angle < 1e-12:
        return np.zeros(3)
    skew = (rotation - rotation.T) / (2 * math.sin(angle))
    return angle * np.array([skew[2, 1], skew[0, 2], skew[1, 0]])


@pytest.mark.needs("kinematics")
@pytest.mark.parametrize("index", range(4))
def test_frame_jacobian_matches_finite_differences(index: int) -> None:
    q = random_configurations(4, 11)[index]
    jac = frame_jacobian(UR5E, q_of(q), FLANGE_FRAME)
    h = 1e-6
    numeric = np.empty((6, 6))
    for k in range(6):
        dq = np.zeros(6)
        dq[k] = h
        plus = forward_pose(UR5E, q_of(q + dq), FLANGE_FRAME)
        minus = forward_pose(UR5E, q_of(q - dq), FLANGE_FRAME)
        numeric[:3, k] = (plus.position - minus.position) / (2 * h)
        numeric[3:, k] = _rotation_vector(plus.rotation @ minus.rotation.T) / (2 * h)
    np.testing.assert_allclose(jac, numeric, atol=1e-7)


@pytest.mark.needs("kinematics")
def test_residual_jacobian_matches_finite_differences() -> None:
    """The Jacobian the solver steps with is the derivative of its log6 residual."""
    import pinocchio as pin

    from motiontool.kinematics._pinocchio import build_model

    model, _geoms = build_model(UR5E)
    data = model.createData()
    fid = model.getFrameId(FLANGE_FRAME)
    chain = ik._Chain(model, UR5E, None)
    q0, q1 = random_configurations(2, 5)
    goal = pin.SE3(
        np.array(forward_pose(UR5E, q_of(q1), FLANGE_FRAME).rotation),
        np.array(forward_pose(UR5E, q_of(q1), FLANGE_FRAME).position),
    )
    q0 = q1 + 0.2 * (q0 - q1) / np.linalg.norm(q0 - q1)  # near the goal: log6 is smooth there
    _error, jac = ik._residual(model, data, q0.copy(), fid, goal, chain)
    h = 1e-6
    numeric = np.empty((6, 6))
    for k in range(6):
        dq = np.zeros(6)
        dq[k] = h
        plus, _ = ik._residual(model, data, q0 + dq, fid, goal, chain)
        minus, _ = ik._residual(model, data, q0 - dq, fid, goal, chain)
        numeric[:, k] = (plus - minus) / (2 * h)
    np.testing.assert_allclose(jac, numeric, atol=1e-7)


# --------------------------------------------------------------------------- the UR5e motions


@pytest.fixture(scope="module")
def sorting() -> Motion:
    return sorting_motion()


@pytest.fixture(scope="module")
def jog() -> Motion:
    return jog_motion()


def test_segment_ms_is_the_shortest_step_multiple_within_the_margin() -> None:
    # 0.785 rad at 0.5 × 3.14 rad/s needs 500 ms: the next multiple of 8 ms is 504 ms
    assert segment_ms([0, 0], [0.785, 0.1], [3.14, 3.14], min_ms=0) == 504
    assert 0.785 / 0.496 > 0.5 * 3.14
    assert segment_ms([0, 0], [0.01, 0], [3.14, 3.14]) == ur5e_tasks.MIN_SEGMENT_MS
    assert segment_ms([0], [1.0], [6.28], margin=1.0, min_ms=0, step_ms=1) == 160


@pytest.mark.needs("kinematics")
def test_sorting_waypoints_reach_their_cartesian_targets(sorting: Motion) -> None:
    plan = sorting_plan()
    spots = sorting_spots()
    assert sorting.joints == NAMES
    assert sorting.pose_names == ("start", *(w.name for w in plan))
    np.testing.assert_array_equal(sorting.values[0], 0.0)  # the UR5e's start pose
    for waypoint, row in zip(plan, sorting.values[1:], strict=True):
        position, angle = flange_pose(UR5E, q_of(row)).errors_to(spots[waypoint.spot])
        assert position <= WAYPOINT_POSITION_TOLERANCE_M, waypoint.name
        assert angle <= WAYPOINT_ORIENTATION_TOLERANCE_RAD, waypoint.name
    # the flange points down at every waypoint
    for row in sorting.values[1:]:
        assert flange_pose(UR5E, q_of(row)).rotation[:, 1] == pytest.approx([0, 0, -1], abs=1e-5)


@pytest.mark.needs("kinematics")
def test_sorting_sorts_rusty_left_and_galvanized_right(sorting: Motion) -> None:
    places = [i for i, n in enumerate(sorting.pose_names) if n.startswith("place_")]
    ys = [flange_pose(UR5E, q_of(sorting.values[i])).position[1] for i in places]
    assert [y > 0 for y in ys] == [True, False, True]  # rusty, galvanized, rusty
    assert sorting.pose_names[1] == sorting.pose_names[-1] == "home"
    np.testing.assert_array_equal(sorting.values[1], sorting.values[-1])
    grasps = [i for i, n in enumerate(sorting.pose_names) if n.startswith("grasp_")]
    for i in grasps:  # a grasp is a pause at the pick pose
        np.testing.assert_array_equal(sorting.values[i], sorting.values[i - 1])
        assert sorting.times_ms[i] - sorting.times_ms[i - 1] == ur5e_tasks.GRASP_MS


@pytest.mark.needs("kinematics")
@pytest.mark.parametrize("name", ["sorting", "jog"])
def test_segments_within_the_speed_margin_and_the_limits(
    name: str, request: pytest.FixtureRequest
) -> None:
    motion: Motion = request.getfixturevalue(name)
    assert not np.isnan(motion.values).any()
    assert motion.times_ms[0] == 0
    assert all(t % UR5E.default_timestep_ms == 0 for t in motion.times_ms.tolist())
    dt_s = np.diff(motion.times_ms)[:, None] / 1000.0
    speeds = np.abs(np.diff(motion.values, axis=0)) / dt_s
    limits = np.array([UR5E.joint(n).max_velocity for n in motion.joints])
    assert (speeds <= ur5e_tasks.SPEED_MARGIN * limits).all()
    lower = np.array([j.lower for j in UR5E.joints])
    upper = np.array([j.upper for j in UR5E.joints])
    assert ((motion.values >= lower) & (motion.values <= upper)).all()


@pytest.mark.needs("kinematics")
def test_sorting_moves_are_as_short_as_the_margin_allows(sorting: Motion) -> None:
    limits = [UR5E.joint(n).max_velocity for n in NAMES]
    plan = [None, *sorting_plan()]  # pose 0 is the start pose, before the plan's home
    for k in range(1, sorting.n_poses):
        dt = int(sorting.times_ms[k] - sorting.times_ms[k - 1])
        step = plan[k]
        if step is not None and step.pause_ms is not None:
            assert dt == step.pause_ms
            continue
        assert dt >= ur5e_tasks.MIN_SEGMENT_MS
        shorter = (dt - UR5E.default_timestep_ms) / 1000.0
        if dt > ur5e_tasks.MIN_SEGMENT_MS:  # one step less would be too fast for some joint
            delta = np.abs(sorting.values[k] - sorting.values[k - 1])
            assert (delta / shorter > ur5e_tasks.SPEED_MARGIN * np.array(limits)).any()


@pytest.mark.needs("kinematics")
def test_tool_stays_above_the_table_except_at_pick_and_place(sorting: Motion) -> None:
    """The 8 ms command stream: the flange never goes below the grasp/release heights, and
    below travel height only straight above the pick-up point or a bin."""
    stream = sample(sorting, UR5E.default_timestep_ms)
    centres = np.array([PICK_XY_M, *BINS_XY_M.values()])
    radii = np.array([PICK_DESCENT_RADIUS_M] + [BIN_DESCENT_RADIUS_M] * len(BINS_XY_M))
    lowest_allowed = min(GRASP_Z_M, PLACE_Z_M) - 1e-3
    assert lowest_allowed > TABLE_TOP_Z_M + 0.05 and lowest_allowed > ur5e_tasks.BIN_RIM_Z_M
    assert len(stream.targets) > sorting.duration_ms // 8
    lowest = math.inf
    start_z = flange_pose(UR5E, q_of(sorting.values[0])).position[2]
    for t, row in zip(stream.elapsed_ms, stream.targets, strict=True):
        position = flange_pose(UR5E, q_of(row)).position
        if t <= sorting.times_ms[1]:  # from the start pose up to home: never below the start
            assert position[2] >= start_z - 1e-3
            continue
        lowest = min(lowest, position[2])
        assert position[2] >= lowest_allowed
        if position[2] < TRAVEL_Z_M - 5e-3:
            distances = np.linalg.norm(centres - position[:2], axis=1)
            assert (distances <= radii).any(), position
    assert lowest == pytest.approx(PLACE_Z_M, abs=1e-5)  # it does go down to the bins


@pytest.mark.needs("kinematics")
def test_sorting_waypoints_are_free_of_self_collision(sorting: Motion) -> None:
    from motiontool.kinematics._pinocchio import self_collisions

    for row in np.unique(sorting.values, axis=0):
        assert self_collisions(UR5E, q_of(row)) == []


@pytest.mark.needs("kinematics")
def test_jog_follows_the_keyboard_rule(jog: Motion) -> None:
    steps = ur5e_tasks.JOG_STEPS
    assert jog.pose_names[0] == "start"
    np.testing.assert_array_equal(jog.values[0], 0.0)  # the UR5e's start pose
    home = jog.values[1]
    np.testing.assert_array_equal(jog.values[-1], home)
    assert jog.pose_names[1] == jog.pose_names[-1] == "home"
    np.testing.assert_array_equal(np.diff(jog.times_ms[1:]), ur5e_tasks.JOG_STEP_MS)
    assert jog.n_poses == 2 + 6 * 2 * steps
    # home is the sorting task's IK home
    spot = sorting_spots()["home"]
    assert flange_pose(UR5E, q_of(home)).errors_to(spot)[0] < WAYPOINT_POSITION_TOLERANCE_M
    offsets = jog.values[1:] - home
    moving = np.abs(offsets) > 1e-9
    assert (moving.sum(axis=1) <= 1).all()  # one joint at a time, the others held
    ladder = [*range(1, steps + 1), *range(steps - 1, -1, -1)]
    for j in range(6):
        block = offsets[1 + j * 2 * steps : 1 + (j + 1) * 2 * steps, j]
        np.testing.assert_allclose(block, np.array(ladder) * 0.01, atol=1e-9)
        assert block.max() == pytest.approx(steps * 0.01)


@pytest.mark.needs("kinematics")
@pytest.mark.parametrize("task", list(Task))
def test_committed_motions_are_what_the_generators_write(task: Task) -> None:
    path = MOTIONS / f"{task.value.removeprefix('ur5e-')}.motion"
    assert path.read_bytes() == format_motion(generate(task)).encode()
    assert read_motion(str(path)) == generate(task)


def test_committed_motions_validate_clean() -> None:
    report = validate_paths([str(MOTIONS)], timestep_ms=UR5E.default_timestep_ms)
    assert len(report.files) == len(Task)
    assert [d for f in report.files for d in f.diagnostics] == []


@pytest.mark.needs("kinematics")
def test_generate_command_writes_the_file_and_reports(tmp_path: Path) -> None:
    runner = CliRunner()
    out = tmp_path / "jog.motion"
    result = runner.invoke(app, ["generate", "ur5e-jog", "-o", str(out)])
    assert result.exit_code == 0, result.stderr
    assert out.read_bytes() == (MOTIONS / "jog.motion").read_bytes()
    assert "122 poses, 8.952 s" in result.stdout
    assert (
        "max joint speed 1.562 rad/s (elbow_joint" in result.stdout
        and "limit 3.14 rad/s" in result.stdout
    )
    assert f"sha256 {UR5E.model_hash}" in result.stdout
    bad = runner.invoke(app, ["generate", "ur5e-dance"])
    assert bad.exit_code == 2 and "ur5e-sorting" in bad.stderr


@pytest.mark.needs("kinematics")
def test_generate_rejects_unknown_tasks_and_items() -> None:
    with pytest.raises(MotionToolError, match="choose one of ur5e-sorting, ur5e-jog"):
        generate("dance")
    with pytest.raises(MotionToolError, match="choose one of rusty, galvanized"):
        sorting_plan(["copper"])
    with pytest.raises(MotionToolError, match="outside"):
        jog_motion(steps=400)  # 4 rad past home: beyond the elbow's ±π
