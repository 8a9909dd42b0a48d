"""The physics options (``--physics-step``, ``--friction``, ``--profile``) reach the compiled
MuJoCo model, the report says what was used, and bad values are one-line errors."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.errors import MotionToolError
from motiontool.kinematics import load_robot
from motiontool.sim import PlayOptions, play
from motiontool.sim.batch import Perturbation, plan
from motiontool.sim.physics import (
    WEBOTS_PROFILE_NOTE,
    Physics,
    physics_run_options,
    read_back,
    resolve_physics,
)

runner = CliRunner()

NOD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,A,0,0\n00:00:100,B,0.2,-0.1\n"


@pytest.fixture
def nod(tmp_path: Path) -> Path:
    path = tmp_path / "nod.motion"
    path.write_bytes(NOD)
    return path


@pytest.mark.needs("sim")
@pytest.mark.parametrize(
    ("friction", "step_ms"), [(0.5, 4.0), (3.0, 1.0), (7.0, 20.0)], ids=["0.5@4", "3@1", "7@20"]
)
def test_friction_and_step_reach_the_compiled_model(friction: float, step_ms: float) -> None:
    from motiontool.sim import _mujoco

    physics = resolve_physics(20, friction=friction, physics_step_ms=step_ms)
    scene = _mujoco.build_scene(
        load_robot("nao"),
        20,
        physics_step_ms=physics.timestep_ms,
        floor_friction=physics.friction,
    )
    assert scene.model.opt.timestep == pytest.approx(step_ms / 1000.0, rel=1e-12)
    assert scene.model.geom("floor").friction[0] == friction
    assert scene.control_substeps == round(20 / step_ms)
    assert read_back(scene) == pytest.approx((step_ms, friction), rel=1e-12)


@pytest.mark.needs("sim")
def test_play_reports_the_physics_it_compiled(nod: Path) -> None:
    default = play([nod], robot="nao", options=PlayOptions(hold_s=0.0))
    assert default.physics == {"timestep_ms": 2.0, "friction": 1.0, "profile": "default"}
    assert default.to_json()["physics"] == default.physics
    assert default.options["floor_friction"] == 1.0
    options = PlayOptions(hold_s=0.0, floor_friction=2.0, friction_scale=1.5, physics_step_ms=4)
    report = play([nod], robot="nao", options=options)
    assert report.physics == {"timestep_ms": 4.0, "friction": 3.0, "profile": "default"}
    assert report.stamps["physics_step_ms"] == 4.0


@pytest.mark.needs("sim")
def test_the_webots_profile_uses_webots_numbers_and_says_it_is_not_what_matches(
    nod: Path,
) -> None:
    report = play([nod], robot="nao", options=PlayOptions(hold_s=0.0, profile="webots"))
    assert report.physics["timestep_ms"] == 20.0  # the Nao's control step
    assert report.physics["friction"] == 7.0
    assert report.physics["profile"] == "webots"
    assert "not what makes walks match" in report.physics["profile_note"]
    # Explicit values win over the profile; the note says what ran, not that walks fall.
    options = PlayOptions(hold_s=0.0, profile="webots", floor_friction=1.0, physics_step_ms=5)
    mixed = play([nod], robot="nao", options=options)
    assert (mixed.physics["timestep_ms"], mixed.physics["friction"]) == (5.0, 1.0)
    note = mixed.physics["profile_note"]
    assert "floor friction 1 (1 given; Webots' is 7)" in note
    assert "physics step 5 ms (given; Webots' is the control step, 20 ms)" in note
    assert "walks fall" not in note and "(7)" not in note


@pytest.mark.parametrize(
    ("kwargs", "says"),
    [
        ({}, WEBOTS_PROFILE_NOTE),
        ({"friction": 7.0, "physics_step_ms": 20.0}, WEBOTS_PROFILE_NOTE),  # Webots' own numbers
        (
            {"friction": 1.0},
            "profile webots, overridden: this run used floor friction 1 (1 given; Webots' is 7)"
            " and physics step 20 ms (= the control step, Webots'), so it is not a run with"
            " Webots' numbers; how friction and step change the walks: docs/play.md, Fidelity",
        ),
        ({"physics_step_ms": 2.0}, "floor friction 7 (Webots') and physics step 2 ms"),
        ({"friction_scale": 0.5}, "floor friction 3.5 (Webots' 7 x 0.5 by the friction pert"),
        ({"friction": 2.0, "friction_scale": 0.5}, "floor friction 1 (2 given x 0.5 by"),
    ],
)
def test_the_webots_note_describes_the_numbers_that_ran(
    kwargs: dict[str, float], says: str
) -> None:
    note = resolve_physics(20, profile="webots", **kwargs).note  # type: ignore[arg-type]
    assert note is not None and says in note
    assert (note == WEBOTS_PROFILE_NOTE) == ("walks fall" in note)
    assert resolve_physics(20, **kwargs).note is None  # type: ignore[arg-type]


def test_the_default_step_divides_any_control_step() -> None:
    assert resolve_physics(20) == Physics("default", 2.0, 1.0, 10)
    odd = resolve_physics(25)  # 2 ms does not divide 25 ms: the largest step below that does
    assert odd.substeps == 13 and odd.timestep_ms == pytest.approx(25 / 13)
    assert resolve_physics(8, profile="webots") == Physics(
        "webots", 8.0, 7.0, 1, WEBOTS_PROFILE_NOTE
    )


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"friction": 0.0}, "floor friction must be a number > 0, got 0"),
        ({"friction": float("nan")}, "floor friction must be a number > 0, got nan"),
        ({"friction_scale": -1.0}, "friction scale must be a number > 0, got -1"),
        ({"physics_step_ms": 0.0}, "physics step must be a number > 0 ms, got 0"),
        (
            {"physics_step_ms": 3.0},
            "physics step 3 ms does not divide the control step of 20 ms; choose one that does,"
            " e.g. 1, 2, 4, 5, 10, 20 ms",
        ),
        ({"physics_step_ms": 40.0}, "physics step 40 ms does not divide the control step"),
        ({"profile": "ode"}, "physics profile 'ode': choose default, webots"),
    ],
)
def test_bad_physics_values_are_one_line_errors(kwargs: dict[str, object], message: str) -> None:
    with pytest.raises(MotionToolError, match="^" + message.replace("(", r"\(")) as info:
        resolve_physics(20, **kwargs)  # type: ignore[arg-type]
    assert "\n" not in str(info.value)


def test_play_options_refuse_bad_physics_before_anything_runs(nod: Path) -> None:
    with pytest.raises(MotionToolError, match="floor friction must be a number > 0"):
        PlayOptions(floor_friction=-1.0).check()
    with pytest.raises(MotionToolError, match="does not divide the control step of 20 ms"):
        play([nod], robot="nao", options=PlayOptions(physics_step_ms=3.0))


@pytest.mark.needs("sim")
def test_cli_play_physics_options_text_and_json(nod: Path, tmp_path: Path) -> None:
    out = tmp_path / "run.json"
    result = runner.invoke(
        app,
        ["play", "--headless", "--hold", "0", "--profile", "webots", "--json", str(out), str(nod)],
    )
    assert result.exit_code in (0, 1), result.output
    assert "physics step 20 ms, floor friction 7)" in result.stdout
    assert f"note: {WEBOTS_PROFILE_NOTE}\n" in result.stdout
    doc = json.loads(out.read_text())
    assert doc["physics"]["profile_note"] == WEBOTS_PROFILE_NOTE
    result = runner.invoke(
        app,
        [
            *("play", "--headless", "--hold", "0", "--friction", "0.5"),
            *("--physics-step", "4", "--json", str(out), str(nod)),
        ],
    )
    assert result.exit_code == 0, result.output
    assert "physics step 4 ms, floor friction 0.5)" in result.stdout
    assert "note:" not in result.stdout
    assert json.loads(out.read_text())["physics"] == {
        "timestep_ms": 4.0,
        "friction": 0.5,
        "profile": "default",
    }
    result = runner.invoke(
        app,
        [
            *("play", "--headless", "--hold", "0", "--profile", "webots", "--friction", "1"),
            *("--json", str(out), str(nod)),
        ],
    )
    assert result.exit_code in (0, 1), result.output
    doc = json.loads(out.read_text())
    assert (doc["physics"]["friction"], doc["physics"]["timestep_ms"]) == (1.0, 20.0)
    assert "floor friction 1 (1 given; Webots' is 7)" in doc["physics"]["profile_note"]
    assert f"note: {doc['physics']['profile_note']}\n" in result.stdout


@pytest.mark.needs("sim")
@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--friction", "0"], "floor friction must be a number > 0, got 0"),
        (["--physics-step", "3"], "physics step 3 ms does not divide the control step of 20 ms"),
        (["--physics-step", "4", "-t", "10"], "physics step 4 ms does not divide the control step"),
    ],
)
@pytest.mark.parametrize("command", ["play", "batch"])
def test_cli_bad_physics_values_exit_2_with_one_line(
    nod: Path, tmp_path: Path, command: str, args: list[str], message: str
) -> None:
    extra = ["--headless"] if command == "play" else ["--no-cache", "--cache-dir", str(tmp_path)]
    result = runner.invoke(app, [command, *extra, *args, str(nod)])
    assert result.exit_code == 2, result.output
    lines = result.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"motiontool: error: {message}"), lines


@pytest.mark.needs("sim")
def test_batch_friction_perturbation_multiplies_the_given_friction(nod: Path) -> None:
    from motiontool.sim.runs import run_spec

    options = {"timestep_ms": None, **physics_run_options("default", 4.0, 2.0)}
    assert options == {"timestep_ms": None, "physics_step_ms": 4.0, "floor_friction": 2.0}
    [spec] = plan(
        [nod], ["nao"], perturbations=[Perturbation("friction", 1.5, 1.5)], options=options
    )
    doc = run_spec(spec)
    assert doc["physics"] == {"timestep_ms": 4.0, "friction": 3.0, "profile": "default"}
    assert physics_run_options() == {}  # the defaults leave the cache key as it was


@pytest.mark.needs("sim")
def test_cli_batch_prints_the_webots_note(nod: Path, tmp_path: Path) -> None:
    result = runner.invoke(
        app,
        ["batch", "--no-cache", "--jobs", "1", "--profile", "webots", str(nod)],
    )
    assert result.exit_code in (0, 1), result.output
    assert f"note: {WEBOTS_PROFILE_NOTE}\n" in result.stdout
