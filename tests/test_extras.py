"""A light core, heavy parts as extras: what the real CLI does when an extra is missing.

Each test runs the real command line in a subprocess. A missing extra is simulated by putting a
folder first on the path whose stub packages (``mujoco/__init__.py``: ``raise ImportError``)
shadow the installed ones, so the tests run in the normal test environment; the last test runs
the CLI in a core-only environment (the built wheel and the core's dependencies, no
site-packages), as ``pip install motiontool`` leaves it.
"""

from __future__ import annotations

import importlib
import json
import os
import subprocess
import sys
import tomllib
import zipfile
from importlib import metadata
from pathlib import Path

import jsonschema
import pytest
from conftest import ROOT

from motiontool.cli.schemas import load as load_schema
from motiontool.errors import MissingExtraError, MotionToolError
from motiontool.extras import EXTRAS, install_hint, require

#: Joints of the Nao; HeadYaw 3.0 rad is past its limit (2.0857 rad) and 0 -> 3 rad in 100 ms is
#: faster than its maxVelocity: limits and velocity need no extra.
NAO_BAD = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,P0,0,0\n00:00:100,P1,3.0,0\n"
NAO_OK = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,P0,0,0\n00:01:000,P1,0.2,0.1\n"

_RUN = "import sys; from motiontool.cli.__main__ import main; sys.argv[0] = 'motiontool'; main()"


def _stubs(root: Path, modules: tuple[str, ...]) -> Path:
    """A folder of packages that fail to import as a missing one does."""
    folder = root / "-".join(("stubs", *modules))
    for module in modules:
        (folder / module).mkdir(parents=True, exist_ok=True)
        (folder / module / "__init__.py").write_text(f"raise ImportError('{module} stubbed out')\n")
    return folder


def _cli(
    args: list[str], tmp_path: Path, missing: tuple[str, ...] = ()
) -> subprocess.CompletedProcess[str]:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "NO_COLOR")}
    env["PYTHONPATH"] = str(_stubs(tmp_path, missing))
    return subprocess.run(
        [sys.executable, "-c", _RUN, *args],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        env=env,
        check=False,
    )


def _write(tmp_path: Path, name: str, data: bytes) -> Path:
    path = tmp_path / name
    path.write_bytes(data)
    return path


# --------------------------------------------------------------------------- commands


@pytest.mark.parametrize(
    ("missing", "args", "message"),
    [
        (
            ("mujoco",),
            ["play", "nao.motion", "--headless"],
            "motiontool play needs MuJoCo: pip install 'motiontool[sim]'",
        ),
        pytest.param(
            ("rerun",),
            ["play", "nao.motion", "--headless", "--rrd", "run.rrd"],
            "motiontool play --rrd needs Rerun (rerun-sdk): pip install 'motiontool[rerun]'",
            marks=pytest.mark.needs("sim"),
        ),
        (
            ("mujoco",),
            ["batch", "nao.motion"],
            "motiontool batch needs MuJoCo: pip install 'motiontool[sim]'",
        ),
        pytest.param(
            ("junitparser",),
            ["batch", "nao.motion", "--junit", "r.xml"],
            "motiontool batch --junit needs junitparser: pip install 'motiontool[sim]'",
            marks=pytest.mark.needs("sim"),
        ),
        pytest.param(
            ("ray",),
            ["batch", "nao.motion", "--executor", "ray"],
            "motiontool batch --executor ray needs Ray: pip install 'motiontool[ray]'",
            marks=pytest.mark.needs("sim"),
        ),
        (
            ("matplotlib",),
            ["plot", "nao.motion", "-o", "nao.png"],
            "motiontool plot needs matplotlib: pip install 'motiontool[plot]'",
        ),
        (
            ("matplotlib",),
            ["diff", "nao.motion", "nao.motion", "--plot", "d.png"],
            "motiontool diff --plot needs matplotlib: pip install 'motiontool[plot]'",
        ),
        pytest.param(
            ("pinocchio",),
            ["validate", "--robot", "erd:ur5", "nao.motion"],
            "robot 'erd:ur5' (a URDF model) needs Pinocchio: pip install 'motiontool[kinematics]'",
            marks=pytest.mark.needs("erd"),
        ),
        (
            ("pinocchio",),
            ["validate", "--robot", "arm.urdf", "nao.motion"],
            "robot 'arm' (a URDF model) needs Pinocchio: pip install 'motiontool[kinematics]'",
        ),
        (
            ("pinocchio",),
            ["generate", "ur5e-sorting", "-o", "s.motion"],
            "inverse kinematics (motiontool generate) needs Pinocchio: "
            "pip install 'motiontool[kinematics]'",
        ),
        (
            ("pinocchio",),
            ["robots", "export", "ur5e", "--urdf", "ur5e.urdf"],
            "motiontool robots export --urdf needs Pinocchio: pip install 'motiontool[kinematics]'",
        ),
        (
            ("rosbags",),
            ["convert", "nao.motion", "nao.mcap"],
            "a ROS 2 bag needs rosbags: pip install 'motiontool[ros]'",
        ),
        pytest.param(
            ("mcap_ros2",),
            ["convert", "nao.motion", "nao.mcap"],
            "a ROS 2 bag needs mcap-ros2-support: pip install 'motiontool[ros]'",
            marks=pytest.mark.needs("ros"),
        ),
        (
            ("rosbags",),
            ["convert", "rec.mcap", "back.motion"],
            "reading a ROS 2 bag needs rosbags: pip install 'motiontool[ros]'",
        ),
        pytest.param(
            ("rosbags",),
            ["play", "nao.motion", "--headless", "--bag", "run.mcap"],
            "motiontool play --bag needs rosbags: pip install 'motiontool[ros]'",
            marks=pytest.mark.needs("sim"),
        ),
    ],
)
def test_a_command_whose_extra_is_missing_names_the_pip_install(
    tmp_path: Path, missing: tuple[str, ...], args: list[str], message: str
) -> None:
    _write(tmp_path, "nao.motion", NAO_OK)
    _write(tmp_path, "arm.urdf", b'<robot name="arm"><link name="base"/></robot>\n')
    _write(tmp_path, "rec.mcap", b"")  # a bag, read only where an import needs it
    proc = _cli(args, tmp_path, missing)
    assert proc.returncode == 2, proc.stderr
    assert proc.stderr == f"motiontool: error: {message}\n"  # one line, no traceback
    assert not any(
        p.suffix in (".rrd", ".xml", ".png", ".urdf", ".mcap")
        and p.name not in ("arm.urdf", "rec.mcap")
        for p in tmp_path.iterdir()
    ), "nothing is written"
    assert not (tmp_path / "s.motion").exists()
    assert not (tmp_path / "back.motion").exists()


def test_validate_without_pinocchio_checks_limits_and_velocity_and_notes_the_skipped_collision(
    tmp_path: Path,
) -> None:
    bad = _write(tmp_path, "bad.motion", NAO_BAD)
    ok = _write(tmp_path, "ok.motion", NAO_OK)
    proc = _cli(["validate", bad.name, ok.name], tmp_path, ("pinocchio",))
    assert proc.returncode == 1, proc.stderr  # the limit error fails the run, not the note
    out = proc.stdout
    assert "error MT302" in out and "warning MT303" in out  # limits and velocity still checked
    assert out.count("MT902") == 1  # one note a run, about the run: no file, no line
    assert (
        "\ninfo MT902: collision check skipped: Pinocchio is not installed; every "
        "file of this run is checked without it\n   = hint: pip install 'motiontool[kinematics]'"
    ) in out
    assert "bad.motion:1:1" not in out
    assert "checks: limits, velocity, collision (skipped: Pinocchio is not installed)" in out
    assert out.splitlines()[-1].endswith(
        "1 note; collision check skipped: pip install 'motiontool[kinematics]';"
        " 2 fixable with --fix --unsafe-fixes"
    )


def test_a_note_is_not_a_failure_even_with_strict(tmp_path: Path) -> None:
    ok = _write(tmp_path, "ok.motion", NAO_OK)
    proc = _cli(["validate", "--strict", ok.name], tmp_path, ("pinocchio",))
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "info MT902: collision check skipped" in proc.stdout
    # --checks limits,velocity asks for nothing that needs Pinocchio: nothing is skipped.
    proc = _cli(["validate", "--checks", "limits,velocity", ok.name], tmp_path, ("pinocchio",))
    assert proc.returncode == 0 and "MT902" not in proc.stdout, proc.stdout


@pytest.mark.parametrize("checks", ["limits,balance", "collision", "all"])
def test_a_check_named_with_checks_fails_the_run_without_its_library(
    tmp_path: Path, checks: str
) -> None:
    """Only default checks may be skipped with a note: one the user asked for by name that
    cannot run is an error (exit 2), not a silent pass."""
    ok = _write(tmp_path, "ok.motion", NAO_OK)
    proc = _cli(["validate", "--checks", checks, ok.name], tmp_path, ("pinocchio",))
    assert (proc.returncode, proc.stdout) == (2, ""), proc.stdout
    name = "balance" if "balance" in checks else "collision"
    assert proc.stderr == (
        f"motiontool: error: the {name} check needs Pinocchio: "
        "pip install 'motiontool[kinematics]'\n"
    )


def test_a_run_note_is_not_pinned_to_a_file_in_sarif_or_github(tmp_path: Path) -> None:
    ok = _write(tmp_path, "ok.motion", NAO_OK)
    proc = _cli(["validate", "--format", "sarif", ok.name], tmp_path, ("pinocchio",))
    assert proc.returncode == 0, proc.stderr
    run = json.loads(proc.stdout)["runs"][0]
    assert run["results"] == []
    (note,) = run["invocations"][0]["toolExecutionNotifications"]
    assert note["level"] == "note" and note["descriptor"]["id"] == "MT902"
    assert note["message"]["text"].startswith("collision check skipped: Pinocchio")
    proc = _cli(["validate", "--format", "github", ok.name], tmp_path, ("pinocchio",))
    first = proc.stdout.splitlines()[0]
    assert first.startswith("::notice title=MT902 check skipped%3A a library it needs")
    assert "file=" not in first and "line=" not in first


@pytest.mark.needs("kinematics")
def test_the_json_report_lists_the_skipped_checks(tmp_path: Path) -> None:
    ok = _write(tmp_path, "ok.motion", NAO_OK)
    proc = _cli(["validate", "--format", "json", ok.name], tmp_path, ("pinocchio",))
    assert proc.returncode == 0, proc.stderr
    doc = json.loads(proc.stdout)
    jsonschema.validate(doc, load_schema("validate"))
    assert doc["robot"]["skipped_checks"] == [
        {
            "check": "collision",
            "library": "Pinocchio",
            "extra": "kinematics",
            "install": "pip install 'motiontool[kinematics]'",
        }
    ]
    assert doc["summary"]["notes"] == 1
    assert doc["files"][0]["diagnostics"] == []
    (note,) = doc["notes"]
    assert (note["code"], note["severity"]) == ("MT902", "info")
    assert note["hint"] == "pip install 'motiontool[kinematics]'"
    # With Pinocchio, nothing is skipped.
    proc = _cli(["validate", "--format", "json", ok.name], tmp_path)
    assert json.loads(proc.stdout)["robot"]["skipped_checks"] == []


# --------------------------------------------------------------------------- the helper


def test_require_imports_or_names_the_extra() -> None:
    assert require("json", "sim", "x").__name__ == "json"
    with pytest.raises(MissingExtraError) as info:
        require("motiontool_no_such_module.sub", "plot", "motiontool plot")
    err = info.value
    assert isinstance(err, MotionToolError)
    assert (err.module, err.extra, err.what) == (
        "motiontool_no_such_module",
        "plot",
        "motiontool plot",
    )
    assert str(err) == (
        "motiontool plot needs motiontool_no_such_module: pip install 'motiontool[plot]'"
    )
    assert install_hint("sim") == "pip install 'motiontool[sim]'"


def test_ctrl_c_in_an_import_is_an_interrupt_not_a_missing_extra(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    # pybind11 turns an exception in a module's initialisation into ImportError, caused by it:
    # Ctrl-C while MuJoCo loads said "needs MuJoCo: pip install ..." and exited 2, not 130.
    def interrupted(name: str) -> None:
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as exc:
            raise ImportError("initialization failed") from exc

    monkeypatch.setattr(importlib, "import_module", interrupted)
    with pytest.raises(KeyboardInterrupt):
        require("mujoco", "sim", "motiontool batch")

    def missing(name: str) -> None:
        try:
            raise OSError("libGL.so.1: cannot open shared object file")
        except OSError as exc:
            raise ImportError("initialization failed") from exc

    monkeypatch.setattr(importlib, "import_module", missing)
    with pytest.raises(MissingExtraError):
        require("mujoco", "sim", "motiontool batch")


def test_every_extra_of_the_helper_is_an_extra_of_the_package() -> None:
    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    extras = config["project"]["optional-dependencies"]
    assert set(EXTRAS) <= set(extras)
    assert set(extras) - set(EXTRAS) == {"all", "test"}


# --------------------------------------------------------------------------- core only


def _core_closure() -> set[str]:
    """The distributions ``pip install motiontool`` brings: the core's requirements, and theirs."""
    from packaging.requirements import Requirement

    config = tomllib.loads((ROOT / "pyproject.toml").read_text())
    todo = [Requirement(r) for r in config["project"]["dependencies"]]
    seen: set[str] = set()
    while todo:
        req = todo.pop()
        if req.marker is not None and not req.marker.evaluate({"extra": ""}):
            continue
        if req.name.lower() in seen:
            continue
        seen.add(req.name.lower())
        todo.extend(Requirement(r) for r in metadata.distribution(req.name).requires or [])
    return seen


def test_the_core_alone_validates_and_names_the_extras(tmp_path: Path) -> None:
    """``pip install motiontool`` without network: the built wheel and the core's dependencies
    linked into one folder, run with ``python -S`` (no site-packages), so nothing else exists."""
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q",
         "-w", str(tmp_path / "wheel"), str(ROOT)],
        check=True,
        capture_output=True,
    )  # fmt: skip
    (wheel,) = (tmp_path / "wheel").glob("motiontool-*.whl")
    site = tmp_path / "site"
    with zipfile.ZipFile(wheel) as zf:
        zf.extractall(site)
    for name in sorted(_core_closure()):
        dist = metadata.distribution(name)
        for top in {Path(str(f)).parts[0] for f in dist.files or []} - {".."}:
            source = Path(str(dist.locate_file(top)))
            if source.exists() and not (site / top).exists():
                (site / top).symlink_to(source)
    _write(tmp_path, "ok.motion", NAO_OK)

    def run(*args: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [sys.executable, "-S", "-c", _RUN, *args],
            capture_output=True,
            text=True,
            cwd=tmp_path,
            env={"PYTHONPATH": str(site), "PATH": "/usr/bin:/bin"},
            check=False,
        )

    probe = run("--version")
    assert probe.returncode == 0 and probe.stdout.startswith("motiontool "), probe.stderr
    heavy = subprocess.run(
        [sys.executable, "-S", "-c", "import importlib.util as u; print([m for m in "
         "('mujoco', 'pinocchio', 'rerun', 'matplotlib', 'ray', 'pyarrow', 'junitparser') "
         "if u.find_spec(m)])"],
        capture_output=True, text=True, env={"PYTHONPATH": str(site)}, check=True,
    ).stdout  # fmt: skip
    assert heavy.strip() == "[]"
    proc = run("validate", "ok.motion")
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "collision check skipped: pip install 'motiontool[kinematics]'" in proc.stdout
    proc = run("play", "ok.motion", "--headless")
    assert (proc.returncode, proc.stderr) == (
        2,
        "motiontool: error: motiontool play needs MuJoCo: pip install 'motiontool[sim]'\n",
    )
    proc = run("plot", "ok.motion", "-o", "ok.png")
    assert proc.stderr.endswith("pip install 'motiontool[plot]'\n") and proc.returncode == 2
    proc = run("validate", "--robot", "erd:ur5", "ok.motion")
    assert (proc.returncode, proc.stderr) == (
        2,
        "motiontool: error: robot 'erd:ur5' needs example-robot-data: "
        "pip install 'motiontool[erd]'\n",
    )


# --------------------------------------------------------------------------- the tests' own marker

NEEDS_SIM = """
import pytest

@pytest.mark.needs("sim")
def test_plays():
    import mujoco

def test_reads():
    pass
"""


def _pytest_without_mujoco(tmp_path: Path, ci: bool) -> subprocess.CompletedProcess[str]:
    """pytest on a test marked ``needs("sim")`` beside tests/conftest.py, MuJoCo stubbed out."""
    (tmp_path / "conftest.py").write_bytes((ROOT / "tests" / "conftest.py").read_bytes())
    (tmp_path / "test_needs.py").write_text(NEEDS_SIM)
    env = {k: v for k, v in os.environ.items() if k not in ("CI", "PYTHONPATH")}
    env["PYTHONPATH"] = str(_stubs(tmp_path, ("mujoco",)))
    if ci:
        env["CI"] = "true"
    return subprocess.run(
        [sys.executable, "-m", "pytest", "-p", "no:cacheprovider", "-rs", "-q", "test_needs.py"],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        check=False,
    )


def test_a_test_that_needs_a_missing_extra_skips_with_the_extras_name(tmp_path: Path) -> None:
    """With the core alone, a test of MuJoCo skips and says what to install."""
    proc = _pytest_without_mujoco(tmp_path, ci=False)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "1 passed, 1 skipped" in proc.stdout
    reason = "needs motiontool[sim]: pip install 'motiontool[sim]' (mujoco: mujoco stubbed out)"
    assert reason in proc.stdout


def test_a_test_that_needs_a_missing_extra_fails_under_ci(tmp_path: Path) -> None:
    proc = _pytest_without_mujoco(tmp_path, ci=True)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert "1 passed, 1 error" in proc.stdout and "skipped" not in proc.stdout  # at setup
    assert "CI=true: tests do not skip for a missing extra" in proc.stdout
