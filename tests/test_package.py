"""The package itself: its layout, its public names, and what start-up imports."""

from __future__ import annotations

import importlib
import re
import subprocess
import sys
import tomllib
import zipfile
from pathlib import Path

import pytest
from conftest import ROOT

HEAVY = ("mujoco", "pinocchio", "rerun", "coal", "example_robot_data", "ray")
#: The distributions behind the heavy parts: each belongs to an extra, never to the core.
HEAVY_DISTS = {
    "pin": "kinematics",
    "mujoco": "sim",
    "junitparser": "sim",
    "rerun-sdk": "rerun",
    "matplotlib": "plot",
    "example-robot-data": "erd",
    "ray": "ray",
    "pyarrow": "fast",
}


def _dist_name(requirement: str) -> str:
    return re.split(r"[\s\[<>=!~;(]", requirement.strip(), maxsplit=1)[0].lower()


def test_core_is_light_and_each_heavy_library_is_an_extra() -> None:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert {_dist_name(r) for r in project["dependencies"]} == {"numpy", "typer"}
    extras = project["optional-dependencies"]
    for dist, extra in HEAVY_DISTS.items():
        assert dist in {_dist_name(r) for r in extras[extra]}, (dist, extra)
    # [all] is every extra but test; [test] is [all] plus the test tools.
    (everything,) = extras["all"]
    assert everything.startswith("motiontool[")
    assert set(everything.removeprefix("motiontool[").rstrip("]").split(",")) == (
        set(extras) - {"all", "test"}
    )
    assert "motiontool[all]" in extras["test"]


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
    "module",
    [
        "motiontool.motionfmt",
        "motiontool.kinematics",
        "motiontool.kinematics.checks",
        "motiontool.sim",
    ],
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
    # The core's metadata: numpy and typer; every heavy library only behind an extra.
    (meta_name,) = [n for n in names if n.endswith(".dist-info/METADATA")]
    meta = zipfile.ZipFile(wheel).read(meta_name).decode()
    requires = [
        line.split(":", 1)[1].strip()
        for line in meta.splitlines()
        if line.startswith("Requires-Dist:")
    ]
    core = {_dist_name(r) for r in requires if "extra ==" not in r}
    assert core == {"numpy", "typer"}, core
    assert not core & set(HEAVY_DISTS)
    provided = {
        line.split(":", 1)[1].strip()
        for line in meta.splitlines()
        if line.startswith("Provides-Extra:")
    }
    assert provided == {"kinematics", "sim", "rerun", "plot", "erd", "ray", "fast", "all", "test"}
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


#: What each library package must not import (STYLE.md: motionfmt <- kinematics, sim <- cli;
#: nothing imports cli), counting imports inside functions too.
_FORBIDDEN = {
    "motionfmt": ("motiontool.cli", "motiontool.kinematics", "motiontool.sim"),
    "kinematics": ("motiontool.cli", "motiontool.sim"),
    "sim": ("motiontool.cli",),
}


def _imports(path: Path) -> list[tuple[int, str]]:
    import ast

    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if isinstance(node, ast.Import):
            found += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            found.append((node.lineno, node.module))
            found += [(node.lineno, f"{node.module}.{alias.name}") for alias in node.names]
    return found


def test_imports_follow_the_layers() -> None:
    wrong = [
        f"{path.relative_to(ROOT)}:{line}: {name}"
        for package, banned in _FORBIDDEN.items()
        for path in sorted((ROOT / package).rglob("*.py"))
        for line, name in _imports(path)
        if any(name == b or name.startswith(b + ".") for b in banned)
    ]
    assert not wrong, "\n".join(wrong)


#: String literals of the library packages that may name a CLI flag: a script's own argparse
#: option, and text the CLI's option help owns or writes into a generated file.
_FLAGS_ALLOWED = {
    ("kinematics/_modelgen.py", "--check"),  # the model generator script's own option
    ("sim/batch.py", "--friction"),  # a perturbation's help: what 1 means
    ("sim/infer.py", "--infer"),  # the header of the motions.toml that 'expect --infer' writes
}


def _flags_in_strings(path: Path) -> list[tuple[int, str]]:
    """(line, flag) of every ``--flag`` in a string literal of ``path`` that is no docstring."""
    import ast

    tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    docs = {
        id(node.value)
        for node in ast.walk(tree)
        if isinstance(node, ast.Expr) and isinstance(node.value, ast.Constant)
    }
    return [
        (node.lineno, flag)
        for node in ast.walk(tree)
        if isinstance(node, ast.Constant) and isinstance(node.value, str) and id(node) not in docs
        for flag in re.findall(r"(?<![\w-])--[a-z][a-z-]*", node.value)
    ]


def test_library_messages_name_no_cli_flag() -> None:
    # The library says what to do; the CLI, which owns its flags, adds them (cli/options.py
    # error_line, or a hint parameter such as robot_option).
    wrong = [
        f"{rel}:{line}: {flag}"
        for package in ("motionfmt", "kinematics", "sim")
        for path in sorted((ROOT / package).rglob("*.py"))
        for rel in [path.relative_to(ROOT).as_posix()]
        for line, flag in _flags_in_strings(path)
        if (rel, flag) not in _FLAGS_ALLOWED
    ]
    assert not wrong, "\n".join(wrong)


def _function_bodies(path: Path) -> list[tuple[str, str]]:
    """(``path:line name``, the body's AST without its docstring, with the arguments) of every
    function of ``path``."""
    import ast

    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if not isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            continue
        body = node.body
        if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
            body = body[1:]
        where = f"{path.relative_to(ROOT).as_posix()}:{node.lineno} {node.name}"
        out.append((where, ast.dump(node.args) + "".join(ast.dump(b) for b in body)))
    return out


@pytest.mark.parametrize("package", ["cli", "motionfmt", "kinematics", "sim"])
def test_no_function_is_written_twice_in_a_package(package: str) -> None:
    # One helper serves every module of a package (issue #11): a second copy of a function,
    # word for word, is a shared helper waiting to be imported.
    seen: dict[str, list[str]] = {}
    for path in sorted((ROOT / package).rglob("*.py")):
        for where, body in _function_bodies(path):
            seen.setdefault(body, []).append(where)
    twice = [" = ".join(places) for places in seen.values() if len(places) > 1]
    assert not twice, "\n".join(twice)
