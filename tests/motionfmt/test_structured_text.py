"""Structured files nested deeper than their parsers' recursion, or values built of YAML
aliases: one line at the file, never a ``RecursionError`` or a message of millions of items.
TOML and YAML (``motionfmt/structured_text.py``: the configuration, ``motions.toml``, joint
maps, a JointTrajectory), a ``--world`` file and ``--ray-runtime-env``'s JSON."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from motiontool.errors import MotionSyntaxError
from motiontool.motionfmt.structured_text import load_toml, load_yaml, shown

DEEP = 5000
DEEP_TOML = "x = " + "[" * DEEP + "1" + "]" * DEEP + "\n"
DEEP_YAML = "x: " + "[" * DEEP + "]" * DEEP + "\n"
MOTION = b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,P1,0\n00:00:160,P2,0.2\n"


def _cli(*args: str, cwd: Path) -> tuple[int, str]:
    done = subprocess.run(
        [sys.executable, "-c", "from motiontool.cli.__main__ import main; main()", *args],
        cwd=cwd,
        capture_output=True,
        text=True,
    )
    return done.returncode, done.stderr


def test_deep_toml_is_nested_too_deeply_at_its_file() -> None:
    with pytest.raises(MotionSyntaxError, match="nested too deeply to read: expected a map"):
        load_toml(DEEP_TOML, "m.toml", "a map")


def test_toml_errors_keep_tomllib_s_line_and_column() -> None:
    with pytest.raises(MotionSyntaxError) as bad:
        load_toml("a = 1\nb = = 2\n", "m.toml", "a map")
    assert (bad.value.line, bad.value.column, bad.value.path) == (2, 5, "m.toml")
    assert "(at line" not in bad.value.message


@pytest.mark.needs("ros")
def test_deep_yaml_is_nested_too_deeply_at_its_file() -> None:
    with pytest.raises(MotionSyntaxError, match="nested too deeply to read: expected a map"):
        load_yaml(DEEP_YAML, "m.yaml", "a map")


@pytest.mark.needs("ros")
def test_a_value_of_aliases_is_shown_short() -> None:
    text = "a: &a [x, x, x, x, x, x, x, x, x]\n" + "".join(
        f"{n}: &{n} [{', '.join([f'*{p}'] * 9)}]\n"
        for p, n in zip("abcdefg", "bcdefgh", strict=True)
    )
    (doc,) = load_yaml(text, "m.yaml", "a map")
    assert len(shown(doc["h"])) < 80


@pytest.mark.parametrize("name", ["pyproject.toml", "motiontool.toml"])
def test_a_deep_configuration_is_one_line(tmp_path: Path, name: str) -> None:
    (tmp_path / "m.motion").write_bytes(MOTION)
    text = DEEP_TOML if name != "pyproject.toml" else "[tool.motiontool]\n" + DEEP_TOML
    (tmp_path / name).write_text(text)
    code, err = _cli("validate", "m.motion", cwd=tmp_path)
    assert code == 2 and err.count("\n") == 1, err
    assert "nested too deeply to read" in err and name in err


def test_a_deep_motions_toml_is_one_line(tmp_path: Path) -> None:
    (tmp_path / "m.motion").write_bytes(MOTION)
    (tmp_path / "motions.toml").write_text(DEEP_TOML)
    code, err = _cli("validate", "--robot", "none", "m.motion", cwd=tmp_path)
    assert code == 0, err  # validate does not read motions.toml
    code, err = _cli("batch", "m.motion", cwd=tmp_path)
    assert code == 2 and err.count("\n") == 1, err
    assert "motions.toml:1:1: nested too deeply to read" in err


@pytest.mark.needs("ros")
@pytest.mark.parametrize(("name", "text"), [("map.toml", DEEP_TOML), ("map.yaml", DEEP_YAML)])
def test_a_deep_joint_map_is_one_line(tmp_path: Path, name: str, text: str) -> None:
    (tmp_path / "m.motion").write_bytes(MOTION)
    (tmp_path / name).write_text(text)
    code, err = _cli("convert", "m.motion", "m.trajectory.yaml", "--joint-map", name, cwd=tmp_path)
    assert code == 2 and err.count("\n") == 1, err
    assert f"{name}:1:1: nested too deeply to read: expected a joint map" in err
    assert not (tmp_path / "m.trajectory.yaml").exists()


def test_a_deep_world_is_one_line(tmp_path: Path) -> None:
    """``--world``: the .wbt parser descends once per level of nested nodes."""
    from motiontool.sim.wbt import parse_wbt

    text = "#VRML_SIM R2023b utf8\n" + "Group { children [ " * 3000 + " ] }" * 3000 + "\n"
    with pytest.raises(MotionSyntaxError, match="nodes nested too deeply to read"):
        parse_wbt(text, "deep.wbt")


def test_a_deep_ray_runtime_env_is_one_line(tmp_path: Path) -> None:
    (tmp_path / "m.motion").write_bytes(MOTION)
    (tmp_path / "env.json").write_text('{"pip": ' + "[" * DEEP + "]" * DEEP + "}")
    code, err = _cli(
        "batch", "m.motion", "--executor", "ray", "--ray-runtime-env", "env.json", cwd=tmp_path
    )
    assert code == 2 and "Traceback" not in err, err
    assert "'env.json': nested too deeply to read as JSON" in err
