"""The package itself: its layout, its public names, and what start-up imports."""

from __future__ import annotations

import importlib
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import pytest
from conftest import ROOT

HEAVY = ("mujoco", "pinocchio", "rerun", "coal", "example_robot_data", "ray")


def test_explicit_package_list_covers_every_code_folder() -> None:
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    listed = set(config["tool"]["setuptools"]["packages"])
    found = {"motiontool"} | {
        "motiontool." + ".".join(p.parent.relative_to(ROOT).parts)
        for p in ROOT.glob("*/**/__init__.py")
        if not {"tests", "benchmarks", ".venv", "build"} & set(p.relative_to(ROOT).parts)
    }
    assert listed == found


@pytest.mark.parametrize(
    "module", ["motiontool.motionfmt", "motiontool.kinematics", "motiontool.sim"]
)
def test_all_is_honest(module: str) -> None:
    mod = importlib.import_module(module)
    names = getattr(mod, "__all__", [])
    for name in names:
        assert hasattr(mod, name), f"{module}.__all__ names missing {name}"
    public = {
        n
        for n, v in vars(mod).items()
        if not n.startswith("_") and getattr(v, "__module__", "").startswith(module)
    }
    assert public <= set(names) | {n for n in public if isinstance(vars(mod)[n], type(mod))}


def _imported_after(code: str) -> set[str]:
    out = subprocess.run(
        [sys.executable, "-c", code + "\nimport sys; print(' '.join(sorted(sys.modules)))"],
        capture_output=True,
        text=True,
        check=True,
        cwd=ROOT,
    ).stdout
    return set(out.split())


def test_help_and_syntax_validation_import_no_heavy_library(tmp_path: Path) -> None:
    # A joint no built-in robot has: validate stays at syntax level (MT901).
    motion = tmp_path / "small.motion"
    motion.write_bytes(b"#WEBOTS_MOTION,V1.0,NoSuchMotor\n0,P,0\n")
    for argv in (["--help"], ["validate", str(motion)], ["robots"], ["robots", "show", "nao"]):
        code = (
            "import sys\nfrom motiontool.cli.app import app\n"
            f"try:\n    app({argv!r}, prog_name='motiontool')\nexcept SystemExit:\n    pass"
        )
        loaded = _imported_after(code)
        assert not loaded & set(HEAVY), f"{argv} imported {sorted(loaded & set(HEAVY))}"


def test_limits_and_velocity_checks_import_no_heavy_library(tmp_path: Path) -> None:
    # A Nao file: auto-detection loads the Nao's joint table, but limits and velocities come
    # from it alone; only the collision and balance checks load Pinocchio.
    motion = tmp_path / "nao.motion"
    motion.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n0,P,0,0\n100,Q,3,0.7\n")
    argv = ["validate", "--checks", "limits,velocity", str(motion)]
    code = (
        "import sys\nfrom motiontool.cli.app import app\n"
        f"try:\n    app({argv!r}, prog_name='motiontool')\nexcept SystemExit:\n    pass\n"
        "assert 'motiontool.kinematics.checks' in sys.modules"
    )
    loaded = _imported_after(code)
    assert not loaded & set(HEAVY), f"{argv} imported {sorted(loaded & set(HEAVY))}"


def test_built_wheel_contains_every_subpackage(tmp_path: Path) -> None:
    subprocess.run(
        [
            sys.executable,
            "-m",
            "pip",
            "wheel",
            "--no-deps",
            "--no-build-isolation",
            "-q",
            "-w",
            str(tmp_path),
            str(ROOT),
        ],
        check=True,
        capture_output=True,
    )
    (wheel,) = tmp_path.glob("motiontool-*.whl")
    names = set(zipfile.ZipFile(wheel).namelist())
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    for package in config["tool"]["setuptools"]["packages"]:
        assert package.replace(".", "/") + "/__init__.py" in names
    schema_files = sorted((ROOT / "cli" / "schemas").glob("*.schema.json"))
    assert schema_files
    for schema in schema_files:  # package data: the JSON Schemas of the reports
        assert f"motiontool/cli/schemas/{schema.name}" in names
    assert not any(
        n.startswith(("motiontool/tests/", "motiontool/benchmarks/", "tests/")) for n in names
    )
    # The wheel alone, first on the path, imports and runs.
    target = tmp_path / "site"
    with zipfile.ZipFile(wheel) as zf:
        zf.extractall(target)
    proc = subprocess.run(
        [
            sys.executable,
            "-c",
            "import motiontool.cli.app as a, motiontool; print(motiontool.__file__); a.app(['--version'])",
        ],
        capture_output=True,
        text=True,
        env={"PYTHONPATH": str(target), "PATH": "/usr/bin:/bin"},
        check=False,
    )
    assert proc.stdout.splitlines()[0].startswith(str(target)), proc.stderr
    assert proc.stdout.splitlines()[1].startswith("motiontool ")
