"""One fact, one home (issue #16 item 2): the start states, the unit conversions, the substep rule
and its slack, the motor gain. Each test looks for the stray spellings a second home would
bring back (string and number constants in the code, not in docstrings or comments)."""

from __future__ import annotations

import ast
import inspect
from collections.abc import Iterator

import pytest
from conftest import ROOT

PACKAGES = ("motionfmt", "kinematics", "sim", "cli")


def sources() -> Iterator[tuple[str, ast.Module]]:
    for package in PACKAGES:
        for path in sorted((ROOT / package).rglob("*.py")):
            rel = path.relative_to(ROOT).as_posix()
            yield rel, ast.parse(path.read_text(encoding="utf-8"), rel)


def constants(tree: ast.Module) -> Iterator[ast.Constant]:
    """Every constant of ``tree`` but docstrings."""
    docs = {
        id(node.body[0].value)
        for node in ast.walk(tree)
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef)
        and node.body
        and isinstance(node.body[0], ast.Expr)
        and isinstance(node.body[0].value, ast.Constant)
    }
    for node in ast.walk(tree):
        if isinstance(node, ast.Constant) and id(node) not in docs:
            yield node


def test_the_start_states_are_spelt_in_one_place() -> None:
    names = {"standing", "lying-front", "lying-back"}
    stray = [
        f"{rel}:{c.lineno}: {c.value!r}"
        for rel, tree in sources()
        if rel != "sim/start.py"
        for c in constants(tree)
        if c.value in names
    ]
    assert not stray, "use motiontool.sim.start.StartState:\n" + "\n".join(stray)


def _scaled_by_1000(tree: ast.Module) -> Iterator[int]:
    """Lines where 1000 multiplies or divides something: a unit conversion spelt by hand."""
    for node in ast.walk(tree):
        if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Mult | ast.Div):
            for side in (node.left, node.right):
                if isinstance(side, ast.Constant) and side.value in (1000, 1000.0):
                    yield node.lineno


def test_unit_conversions_come_from_the_units_module() -> None:
    stray = [f"{rel}:{line}" for rel, tree in sources() for line in _scaled_by_1000(tree)]
    assert not stray, "use motiontool.motionfmt.units (MS_PER_S, MM_PER_M):\n" + "\n".join(stray)
    homes = [
        rel
        for rel, tree in sources()
        for node in ast.walk(tree)
        if isinstance(node, ast.Assign)
        for target in node.targets
        if isinstance(target, ast.Name) and target.id in ("MS_PER_S", "MM_PER_M")
    ]
    assert homes == ["motionfmt/units.py", "motionfmt/units.py"]


def test_the_time_fields_have_one_home() -> None:
    """What a pose time's m:s:ms fields are worth is spelt once (the reader's three paths,
    the writer and the command line read it from the units module)."""
    stray = [
        f"{rel}:{c.lineno}: {c.value!r}"
        for rel, tree in sources()
        if rel != "motionfmt/units.py"
        for c in constants(tree)
        if type(c.value) is int and c.value == 60_000
    ]
    assert not stray, "use motiontool.motionfmt.units.TIME_FIELD_MS:\n" + "\n".join(stray)


def _spelt_exit_code(node: ast.AST) -> bool:
    """``Exit(1)``, ``sys.exit(2)``, ``os._exit(0)`` or ``128 + signal...``."""
    if isinstance(node, ast.BinOp):
        return isinstance(node.left, ast.Constant) and node.left.value == 128
    if not isinstance(node, ast.Call):
        return False
    name = getattr(node.func, "attr", getattr(node.func, "id", None))
    return name in ("Exit", "exit", "_exit") and any(isinstance(a, ast.Constant) for a in node.args)


def test_exit_codes_come_from_their_module() -> None:
    """Every exit status a command ends with is named in ``motiontool.exit_codes``: no
    ``typer.Exit(1)``, ``sys.exit(2)`` or ``128 + signal.SIGINT`` spelt by hand."""
    stray = [
        f"{rel}:{node.lineno}"
        for rel, tree in sources()
        for node in ast.walk(tree)
        if _spelt_exit_code(node)
    ]
    assert not stray, "use motiontool.exit_codes:\n" + "\n".join(stray)
    from typer.testing import CliRunner

    from motiontool import exit_codes
    from motiontool.cli.app import app

    assert exit_codes.SUMMARY in " ".join(CliRunner().invoke(app, ["--help"]).output.split())


def test_the_substep_slack_has_one_home() -> None:
    slack = [
        f"{rel}:{c.lineno}"
        for rel, tree in sources()
        if rel.startswith("sim/")
        for c in constants(tree)
        if c.value == 1e-9
    ]
    assert len(slack) == 1 and slack[0].startswith("sim/physics.py:"), slack


@pytest.mark.needs("sim")
@pytest.mark.parametrize("control_ms", [8, 20, 25, 32, 40, 7])
def test_the_scene_and_the_report_count_the_same_substeps(control_ms: int) -> None:
    """The physics profile and the MuJoCo scene split a control step by one rule."""
    from motiontool.kinematics.robots import load_robot
    from motiontool.sim import _mujoco
    from motiontool.sim.physics import DEFAULT_PHYSICS_STEP_MS, resolve_physics

    physics = resolve_physics(control_ms)
    scene = _mujoco.build_scene(load_robot("ur5e"), control_ms)
    assert scene.control_substeps == physics.substeps
    assert scene.physics_step_s * 1e3 <= DEFAULT_PHYSICS_STEP_MS + 1e-12


def test_the_motor_gain_default_is_the_motor_module_s() -> None:
    from motiontool.sim import _mujoco
    from motiontool.sim.motor import DEFAULT_P_GAIN, MotorLimits
    from motiontool.sim.play import PlayOptions

    defaults = {
        "PlayOptions.p_gain": PlayOptions().p_gain,
        "build_scene(p_gain)": inspect.signature(_mujoco.build_scene).parameters["p_gain"].default,
        "MotorLimits.p_gain": inspect.signature(MotorLimits).parameters["p_gain"].default,
    }
    assert all(v is DEFAULT_P_GAIN for v in defaults.values()), defaults


def test_the_cli_words_reach_the_library_as_one_object() -> None:
    """No library function takes a CLI flag or command as its own parameter (``robot_option``,
    ``mirror_command``, ...): the front end's words travel as one ``Wording``."""
    stray = [
        f"{rel}:{node.lineno} {node.name}({arg.arg})"
        for rel, tree in sources()
        if not rel.startswith("cli/")
        for node in ast.walk(tree)
        if isinstance(node, ast.FunctionDef)
        for arg in [*node.args.args, *node.args.kwonlyargs]
        if arg.arg.endswith(("_option", "_command", "_flag"))
    ]
    assert not stray, "\n".join(stray)


def test_errors_and_extras_live_at_the_top_level() -> None:
    """Every layer raises motiontool's errors and needs its extras helper: they live in
    ``motiontool.errors`` and ``motiontool.extras`` alone (``motionfmt``'s shims of those names,
    kept for a 0.1 that was never released, are gone)."""
    assert not (ROOT / "motionfmt" / "errors.py").exists()
    assert not (ROOT / "motionfmt" / "extras.py").exists()
    stray = [
        f"{rel}:{node.lineno}"
        for rel, tree in sources()
        for node in ast.walk(tree)
        if isinstance(node, ast.ImportFrom)
        and node.module in ("motiontool.motionfmt.errors", "motiontool.motionfmt.extras")
    ]
    assert not stray, "import from motiontool.errors / motiontool.extras:\n" + "\n".join(stray)


def test_the_held_target_carry_has_one_home() -> None:
    """What a chunk of a stream leaves held is carried into the next by ``player.Holder``
    alone: no other call of ``hold_targets`` passes ``initial`` or ``holding`` on."""
    stray = [
        f"{rel}:{node.lineno}"
        for rel, tree in sources()
        if rel != "motionfmt/player.py"
        for node in ast.walk(tree)
        if isinstance(node, ast.Call)
        and getattr(node.func, "id", getattr(node.func, "attr", None)) == "hold_targets"
        and {k.arg for k in node.keywords} & {"initial", "holding"}
    ]
    assert not stray, "use motiontool.motionfmt.player.Holder:\n" + "\n".join(stray)


def test_the_step_without_a_robot_has_one_home() -> None:
    """Sampling, plotting and exporting without a robot, and a robot whose model
    names no Webots world, all step at Webots' default ``basicTimeStep``: one constant."""
    import inspect

    from motiontool.cli.plot import plot_command
    from motiontool.cli.sample import sample_command
    from motiontool.kinematics.builtin_robots import DEFAULT_TIMESTEP_MS
    from motiontool.motionfmt.convert.base import ExportOptions
    from motiontool.motionfmt.player import WEBOTS_DEFAULT_TIMESTEP_MS

    assert WEBOTS_DEFAULT_TIMESTEP_MS == 32  # Webots' WorldInfo default
    assert DEFAULT_TIMESTEP_MS == ExportOptions().timestep_ms == WEBOTS_DEFAULT_TIMESTEP_MS
    assert inspect.signature(sample_command).parameters["timestep"].default == 32
    assert "WEBOTS_DEFAULT_TIMESTEP_MS)" in inspect.getsource(plot_command)
    spelt = [
        f"{rel}:{node.lineno}"
        for rel, tree in sources()
        for node in ast.walk(tree)
        if isinstance(node, ast.Assign)
        for target in node.targets
        if isinstance(target, ast.Name) and "TIMESTEP_MS" in target.id
        if isinstance(node.value, ast.Constant)
    ]
    assert [s.split(":")[0] for s in spelt] == ["motionfmt/clock.py"], spelt


def test_the_output_options_are_listed_once() -> None:
    """Dev/hostile.py and the special-output tests point every output option
    at devices and FIFOs from one list, dev/writers.py (they had drifted apart)."""
    for rel in ("dev/hostile.py", "tests/cli/test_special_outputs.py"):
        tree = ast.parse((ROOT / rel).read_text(encoding="utf-8"))
        spelt = [
            node.lineno
            for node in ast.walk(tree)
            if isinstance(node, ast.Assign | ast.AnnAssign)
            and isinstance(node.value, ast.List)
            and "OUT" in ast.unparse(node.value)
        ]
        assert not spelt, f"{rel}:{spelt}: use dev/writers.py's WRITERS"
