"""The package itself: its layout, its public names, and what start-up imports."""

from __future__ import annotations

import ast
import importlib
import importlib.metadata
import os
import re
import shutil
import subprocess
import sys
import tarfile
import tomllib
import zipfile
from pathlib import Path
from typing import Any

import pytest
from conftest import ROOT, missing_data

from motiontool.extras import EXTRAS

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
}


#: Folders of data only (no ``__init__.py``) that the wheel ships as packages of their own:
#: setuptools warns about a data folder that is not listed.
DATA_PACKAGES = {"motiontool.kinematics.models"}


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


def test_the_readme_extras_table_names_every_extra() -> None:
    """The Install section's table has a row for each extra of pyproject.toml
    (it lacked ``lsp``), and no row for an extra that does not exist."""
    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"][
        "optional-dependencies"
    ]
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    table = readme[readme.index("| extra | brings | for |") :].split("\n\n", 1)[0]
    rows = re.findall(r"^\| `([a-z-]+)` \|", table, flags=re.MULTILINE)
    assert sorted(rows) == sorted(extras)


#: Code folders left out of the wheel on purpose: build-time tools that run from a checkout.
NOT_SHIPPED = {
    # Writes kinematics/models from tests/data/robot_facts, which the wheel does not hold either.
    "motiontool.kinematics._modelgen",
}


def test_explicit_package_list_covers_every_code_folder() -> None:
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    listed = set(config["tool"]["setuptools"]["packages"])
    found = {"motiontool"} | {
        "motiontool." + ".".join(p.parent.relative_to(ROOT).parts)
        for p in ROOT.glob("*/**/__init__.py")
        if not {"tests", "benchmarks", ".venv", "build"} & set(p.relative_to(ROOT).parts)
    }
    assert found >= NOT_SHIPPED
    assert listed == (found - NOT_SHIPPED) | DATA_PACKAGES
    # A data folder is listed as a package of its own, with its files as its package data.
    assert set(config["tool"]["setuptools"]["package-data"]) >= DATA_PACKAGES


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


_BUILD = """
import sys
from setuptools import build_meta
print(getattr(build_meta, sys.argv[1])(sys.argv[2]))
"""


def _build(source: Path, hook: str, out: Path) -> tuple[Path, str]:
    """Run setuptools' PEP 517 ``hook`` (as ``python -m build`` or pip would) in ``source``;
    the file it wrote and everything it printed (warnings shown, whatever the environment)."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    proc = subprocess.run(
        [sys.executable, "-W", "always", "-c", _BUILD, hook, str(out)],
        cwd=source,
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return out / proc.stdout.splitlines()[-1], proc.stdout + proc.stderr


def _checkout_files() -> list[str]:
    """What a clone has: the tracked files (and new ones not yet committed, not ignored)."""
    listed = subprocess.run(
        ["git", "ls-files", "-z", "--cached", "--others", "--exclude-standard"],
        cwd=ROOT,
        capture_output=True,
        check=True,
    ).stdout.decode()
    return sorted(n for n in set(listed.split("\0")) if n and (ROOT / n).is_file())


@pytest.fixture(scope="module")
def built(tmp_path_factory: pytest.TempPathFactory) -> dict[str, Any]:
    """An sdist built from a copy of the checkout, and the wheel built from that sdist (what
    ``pip install motiontool-*.tar.gz`` does), with what each build printed."""
    tmp = tmp_path_factory.mktemp("build")
    source = tmp / "checkout"
    files = _checkout_files()
    for name in files:
        (source / name).parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(ROOT / name, source / name)
    sdist, sdist_log = _build(source, "build_sdist", tmp / "dist")
    with tarfile.open(sdist) as tar:
        tar.extractall(tmp / "unpacked", filter="data")
    (unpacked,) = (tmp / "unpacked").iterdir()
    wheel, wheel_log = _build(unpacked, "build_wheel", tmp / "dist")
    return {"files": files, "sdist": sdist, "wheel": wheel, "log": sdist_log + wheel_log}


def test_the_build_prints_no_setuptools_warning(built: dict[str, Any]) -> None:
    warnings = [line for line in built["log"].splitlines() if re.search(r"(?i)warning|^!!$", line)]
    assert warnings == [], "\n".join(warnings)


@pytest.mark.needs("rerun")
def test_the_sdist_holds_every_file_of_a_checkout(built: dict[str, Any]) -> None:
    with tarfile.open(built["sdist"]) as tar:
        names = {n.split("/", 1)[1] for n in tar.getnames() if "/" in n}
    missing = sorted(set(built["files"]) - names - {".gitignore"})
    assert missing == [], f"MANIFEST.in (or, for code, [tool.setuptools] packages): {missing}"
    for must in ("LICENSE", ".pre-commit-hooks.yaml", "docs/ci.md", "tests/conftest.py"):
        assert must in names
    assert not any("__pycache__" in n or n.endswith(".pyc") for n in names)


def test_metadata_license_classifiers_and_no_url_that_does_not_exist(
    built: dict[str, Any],
) -> None:
    with zipfile.ZipFile(built["wheel"]) as zf:
        (meta_name,) = [n for n in zf.namelist() if n.endswith(".dist-info/METADATA")]
        meta = zf.read(meta_name).decode()
        assert any(n.endswith(".dist-info/licenses/LICENSE") for n in zf.namelist())
    assert "License-Expression: Apache-2.0" in meta.splitlines()
    assert (ROOT / "LICENSE").read_text().lstrip().startswith("Apache License\n")
    assert "END OF TERMS AND CONDITIONS" in (ROOT / "LICENSE").read_text()
    classifiers = {
        line.split(": ", 1)[1] for line in meta.splitlines() if line.startswith("Classifier:")
    }
    assert "Topic :: Scientific/Engineering :: Robotics" in classifiers
    assert "Programming Language :: Python :: 3.11" in classifiers
    # The repository is not hosted yet: a Project-URL would point nowhere.
    assert not [line for line in meta.splitlines() if line.startswith("Project-URL:")]
    version = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    assert f"Version: {version}" in meta.splitlines()


def test_the_version_has_one_home() -> None:
    import motiontool

    version = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["version"]
    assert motiontool.__version__ == version
    import ast

    literal = [
        f"{path.relative_to(ROOT)}:{node.lineno}"
        for package in ("", "cli", "motionfmt", "kinematics", "sim")
        for path in sorted((ROOT / package).glob("*.py" if not package else "**/*.py"))
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8")))
        if isinstance(node, ast.Constant) and node.value == version
    ]
    assert literal == [], "read it from pyproject.toml / the package metadata"


@pytest.mark.needs("rerun")
def test_rerun_sdk_is_bounded_to_the_minor_the_recordings_are_tested_with() -> None:
    from importlib import metadata

    from packaging.requirements import Requirement
    from packaging.version import Version

    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"][
        "optional-dependencies"
    ]
    (rerun,) = [Requirement(r) for r in extras["rerun"] if r.startswith("rerun-sdk")]
    installed = Version(metadata.version("rerun-sdk"))
    assert installed in rerun.specifier
    upper = [s for s in rerun.specifier if s.operator == "<"]
    assert [s.version for s in upper] == [f"0.{installed.minor + 1}"], rerun


def test_built_wheel_contains_every_subpackage(built: dict[str, Any], tmp_path: Path) -> None:
    wheel = built["wheel"]
    names = set(zipfile.ZipFile(wheel).namelist())
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    for package in set(config["tool"]["setuptools"]["packages"]) - DATA_PACKAGES:
        assert package.replace(".", "/") + "/__init__.py" in names
    for tool in NOT_SHIPPED:
        assert not any(n.startswith(tool.replace(".", "/") + "/") for n in names)
    schema_files = sorted((ROOT / "cli" / "schemas").glob("*.schema.json"))
    assert schema_files
    for schema in schema_files:  # package data: the JSON Schemas of the reports
        assert f"motiontool/cli/schemas/{schema.name}" in names
    for model in sorted((ROOT / "kinematics" / "models").iterdir()):  # the robots
        assert f"motiontool/kinematics/models/{model.name}" in names
    assert not any(
        n.startswith(("motiontool/tests/", "motiontool/benchmarks/", "motiontool/docs/", "tests/"))
        for n in names
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
    assert provided == {*EXTRAS, "all", "test"}  # the extras helper is the one list
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


#: What each library package must not import (docs/architecture.md: motionfmt <- kinematics, sim <- cli;
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


def _may_import(init: Path) -> str:
    """The paragraph of ``init``'s docstring that says what its folder may import ("" if none)."""
    doc = ast.get_docstring(ast.parse(init.read_text(encoding="utf-8"))) or ""
    return next((p for p in doc.split("\n\n") if p.startswith("May import ")), "")


def test_every_folder_says_what_it_holds_and_what_it_may_import() -> None:
    # Each folder's __init__ docstring: what it holds, then a "May import ..." paragraph; a
    # layer's names what it never imports, as _FORBIDDEN has it.
    wrong = []
    for package in ("motionfmt", "kinematics", "sim", "cli"):
        for init in sorted((ROOT / package).rglob("__init__.py")):
            rel = init.relative_to(ROOT).as_posix()
            doc = ast.get_docstring(ast.parse(init.read_text(encoding="utf-8"))) or ""
            paragraph = _may_import(init)
            if not paragraph or doc.startswith("May import "):
                wrong.append(f"{rel}: what the folder holds, then 'May import ...'")
            never = re.split(r"\bnever\s+", paragraph, maxsplit=1)[1:]
            for banned in _FORBIDDEN.get(package, ()) if init.parent.name == package else ():
                if f"``{banned.rsplit('.', 1)[1]}``" not in "".join(never):
                    wrong.append(f"{rel}: 'never ...' names {banned}")
    assert not wrong, "\n".join(wrong)


def test_no_library_module_imports_a_build_time_tool() -> None:
    # The wheel lacks them: an import from the library would fail only once installed.
    tools = tuple(NOT_SHIPPED)
    wrong = [
        f"{path.relative_to(ROOT)}:{line}: {name}"
        for package in ("cli", "motionfmt", "kinematics", "sim")
        for path in sorted((ROOT / package).rglob("*.py"))
        if not any(path.is_relative_to(ROOT.joinpath(*t.split(".")[1:])) for t in tools)
        for line, name in _imports(path)
        if name.startswith(tools)
    ]
    assert wrong == []


#: String literals of the library packages that may name a CLI flag: a script's own argparse
#: option, and text the CLI's option help owns or writes into a generated file.
_FLAGS_ALLOWED = {
    ("kinematics/_modelgen/main.py", "--check"),  # the model generator script's own option
    ("sim/batch.py", "--friction"),  # a perturbation's help: what 1 means
    ("sim/infer.py", "--infer"),  # the header of the motions.toml that 'expect --infer' writes
    ("motionfmt/convert/naoqi_script.py", "--ip"),  # the generated NAOqi script's options
    ("motionfmt/convert/naoqi_script.py", "--port"),
    ("motionfmt/convert/naoqi_script.py", "--json"),
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
        if all(isinstance(b, ast.Expr) and getattr(b.value, "value", None) is ... for b in body):
            continue  # declared, not written: a Protocol's or an overload's `...`
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


#: Sizes are guidance: a module of the four packages over 800 lines, or a function over 80
#: (counted from its ``def`` to its last line, docstring included), is named in the "Sizes" list
#: of docs/architecture.md with its size and the reason it is kept whole. Below them, a module
#: or function is as long as its idea.
MAX_MODULE_LINES = 800
MAX_FUNCTION_LINES = 80
#: One entry of the "Sizes" list: ``- `path` or `path::function`, N lines: reason``.
_SIZE_ENTRY = re.compile(r"^- `([^`]+)`, (\d+) lines: \S.*$", flags=re.MULTILINE)


def _sizes_named() -> dict[str, int]:
    """The "Sizes" list of docs/architecture.md: each entry's ``path`` or ``path::function``
    and the size in lines it states."""
    text = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    section = text.split("\n## Sizes\n", 1)[1].split("\n## ", 1)[0]
    return {name: int(size) for name, size in _SIZE_ENTRY.findall(section)}


def _oversized(path: Path, rel: str) -> dict[str, int]:
    """``rel`` if the module at ``path`` is over :data:`MAX_MODULE_LINES`, and ``rel::name`` of
    each function over :data:`MAX_FUNCTION_LINES`, each with its length in lines."""
    import ast

    text = path.read_text(encoding="utf-8")
    found = {}
    if len(text.splitlines()) > MAX_MODULE_LINES:
        found[rel] = len(text.splitlines())
    for node in ast.walk(ast.parse(text, str(path))):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            length = (node.end_lineno or node.lineno) - node.lineno + 1
            if length > MAX_FUNCTION_LINES:
                found[f"{rel}::{node.name}"] = length
    return found


def test_every_module_or_function_over_its_size_is_named_with_its_reason() -> None:
    over = {
        name: size
        for package in ("motionfmt", "kinematics", "sim", "cli")
        for path in sorted((ROOT / package).rglob("*.py"))
        for name, size in _oversized(path, path.relative_to(ROOT).as_posix()).items()
    }
    # Each is named with its size as it is now; an entry that is gone or back under goes too.
    assert over == _sizes_named(), (
        "docs/architecture.md, Sizes: name each module over "
        f"{MAX_MODULE_LINES} lines or function over {MAX_FUNCTION_LINES} with its size and why "
        "it stays whole (or split it by idea), and drop an entry that is no longer over"
    )


def test_sizes_are_counted_from_def_to_last_line(tmp_path: Path) -> None:
    body = "".join(f"    x{i} = {i}\n" for i in range(MAX_FUNCTION_LINES - 2))
    fits = 'def fits():\n    """At the limit."""\n' + body
    over = "def over():\n" + body + "    y = 1\n    return y\n"  # one line over
    source = tmp_path / "m.py"
    source.write_text(fits + "\n\n" + over)
    assert _oversized(source, "m.py") == {"m.py::over": MAX_FUNCTION_LINES + 1}
    source.write_text("x = 1\n" * (MAX_MODULE_LINES + 1))
    assert _oversized(source, "m.py") == {"m.py": MAX_MODULE_LINES + 1}


def test_the_sizes_list_reads_its_entries() -> None:
    # The list is parsed, not skipped: an entry in the documented form is found.
    sample = "- `cli/x.py::long`, 95 lines: one table, read top to bottom\n"
    assert _SIZE_ENTRY.findall(sample) == [("cli/x.py::long", "95")]


#: The Python versions the package's classifiers name (``3.11`` ...): each one is tested.
CLASSIFIED_PYTHONS = sorted(
    int(c.rsplit(".", 1)[1])
    for c in tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["classifiers"]
    if re.fullmatch(r"Programming Language :: Python :: 3\.\d+", c)
)


def _python(minor: int) -> str | None:
    """A working interpreter of Python 3.``minor`` on this machine: on PATH, else pyenv's."""
    found = [shutil.which(f"python3.{minor}")]
    found += sorted(
        str(p) for p in Path.home().glob(f".pyenv/versions/3.{minor}.*/bin/python3.{minor}")
    )
    for python in found:
        if python and subprocess.run([python, "-c", "pass"], capture_output=True).returncode == 0:
            return python
    return None


def test_the_classifiers_start_at_requires_python() -> None:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert project["requires-python"] == f">=3.{CLASSIFIED_PYTHONS[0]}"
    assert list(range(CLASSIFIED_PYTHONS[0], CLASSIFIED_PYTHONS[-1] + 1)) == CLASSIFIED_PYTHONS
    assert [a["name"] for a in project["authors"]] == ["The motiontool maintainers"]


@pytest.mark.slow
@pytest.mark.parametrize("minor", CLASSIFIED_PYTHONS, ids=lambda m: f"3.{m}")
def test_the_core_installs_and_runs_on_every_python_the_classifiers_name(
    built: dict[str, Any], minor: int, tmp_path: Path
) -> None:
    """A classifier is a promise. The whole suite runs on the Python of this
    venv; on each other version named, the built wheel installs in a fresh venv (the core:
    numpy, typer and their dependencies from the package index) and lints, transforms and
    reads back the project's motions."""
    if minor == sys.version_info.minor:
        pytest.skip("this interpreter: the whole suite runs on it")
    python = _python(minor)
    if python is None:
        missing_data(f"no python3.{minor} on this machine")
    assert python is not None
    venv = tmp_path / "venv"
    subprocess.run([python, "-m", "venv", str(venv)], check=True, capture_output=True)
    install = subprocess.run(
        [
            str(venv / "bin/pip"),
            "install",
            "-q",
            "--disable-pip-version-check",
            str(built["wheel"]),
        ],
        capture_output=True,
        text=True,
        check=False,
    )
    assert install.returncode == 0, install.stderr[-2000:]
    tool = str(venv / "bin/motiontool")

    def run(*args: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [tool, *args], cwd=ROOT, capture_output=True, text=True, check=False, timeout=300
        )

    lint = run("validate", "motions/", "--strict", "--checks", "limits,velocity")
    assert lint.returncode == 0, lint.stdout + lint.stderr
    assert re.search(r"^checked \d+ files: 0 errors, 0 warnings", lint.stdout, re.MULTILINE)
    out = tmp_path / "walk20.motion"
    resampled = run("resample", "motions/nao/wave_right.motion", "--step", "20", "-o", str(out))
    assert resampled.returncode == 0, resampled.stderr
    back = run("diff", "motions/nao/wave_right.motion", str(out))
    assert back.returncode == 0, back.stdout + back.stderr


def _test_tool_modules() -> set[str]:
    """The top-level modules of the core's and ``[test]``'s own distributions (not its extras)."""
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    wanted = {
        _dist_name(r).replace("_", "-")
        for r in project["dependencies"] + project["optional-dependencies"]["test"]
        if not r.startswith("motiontool[")
    }
    return {
        module
        for module, dists in importlib.metadata.packages_distributions().items()
        if any(d.lower().replace("_", "-") in wanted for d in dists)
    }


def _needs(nodes: list[ast.expr]) -> set[str]:
    """The extras named by ``pytest.mark.needs(...)`` calls among ``nodes`` (decorators, or
    what a ``pytestmark`` holds)."""
    return {
        arg.value
        for node in nodes
        for call in ast.walk(node)
        if isinstance(call, ast.Call) and getattr(call.func, "attr", None) == "needs"
        for arg in call.args
        if isinstance(arg, ast.Constant) and isinstance(arg.value, str)
    }


def test_every_test_that_imports_an_extra_says_it_needs_it() -> None:
    """With the core and [test]'s tools alone, a test that needs an extra
    skips with the extra's name (tests/conftest.py). So no test module imports an extra's
    library (nor one no extra declares, nor a helper of tests/ that does) at its top, except
    through ``import_extra``; a test that imports one in its body is marked ``needs`` that
    extra, or its module is; and none calls ``pytest.importorskip``, which skips under CI."""
    extra_of = {module: extra for extra, (modules, _) in EXTRAS.items() for module in modules}
    allowed = set(sys.stdlib_module_names) | _test_tool_modules() | {"motiontool"}
    allowed |= {p.stem for p in (ROOT / "tests").iterdir() if p.suffix == ".py" or p.is_dir()}
    trees = {  # tests/data holds files as others wrote them (Python 2 exports), no tests
        path.relative_to(ROOT).as_posix(): ast.parse(path.read_text(encoding="utf-8"))
        for path in sorted((ROOT / "tests").rglob("*.py"))
        if path.relative_to(ROOT / "tests").parts[0] != "data"
    }
    heavy_helpers = {
        rel.removeprefix("tests/").removesuffix(".py")
        for rel, tree in trees.items()
        if "/" not in rel.removeprefix("tests/")
        for _, name in _imports_of(*tree.body, top=True)
        if name.partition(".")[0] not in allowed
    }
    wrong = []
    for rel, tree in trees.items():
        if not rel.rpartition("/")[2].startswith("test_"):
            continue
        for line, name in _imports_of(*tree.body, top=True):
            if name.partition(".")[0] not in allowed - heavy_helpers:
                wrong.append(f"{rel}:{line}: {name} at the top (import_extra, or in a test)")
        wrong += [
            f"{rel}:{node.lineno}: pytest.importorskip skips under CI too (mark needs)"
            for node in ast.walk(tree)
            if isinstance(node, ast.Call) and getattr(node.func, "attr", None) == "importorskip"
        ]
        marked = _needs([n.value for n in tree.body if isinstance(n, ast.Assign)])
        for node in tree.body:
            if isinstance(node, ast.FunctionDef) and node.name.startswith("test_"):
                needed = marked | _needs(node.decorator_list)
                for line, name in _imports_of(*node.body):
                    extra = extra_of.get(name.partition(".")[0])
                    if extra and extra not in needed:
                        wrong.append(f"{rel}:{line}: {name} in {node.name}, not marked needs")
    assert not wrong, "\n".join(wrong)


def _imports_of(*nodes: ast.stmt, top: bool = False) -> list[tuple[int, str]]:
    """The modules ``nodes`` import (with ``top``, not those in a function or class body)."""
    found, todo = [], list(nodes)
    while todo:
        node = todo.pop()
        if isinstance(node, ast.Import):
            found += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            found.append((node.lineno, node.module))
        if not (top and isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef)):
            todo += ast.iter_child_nodes(node)
    return sorted(found)
