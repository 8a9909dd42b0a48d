"""The simulation adapters' typed surface: no ``Any`` in sim/_mujoco/,
sim/recording.py and sim/_ray.py; the Protocols of ``sim/_mujoco/api.py`` say only what the real
MuJoCo has; Rerun and Ray are typed by their own annotations (``py.typed``)."""

from __future__ import annotations

import importlib.util
import tomllib
from pathlib import Path

import pytest
from conftest import ROOT
from typed_surface import any_count, imports_of, members, missing

from motiontool.kinematics.robots import load_robot
from motiontool.sim._mujoco import api, build_scene
from motiontool.sim._mujoco.build import _load_spec

#: The modules whose types mypy checks without an explicit ``Any`` (pyproject's override).
ADAPTERS = ("sim/_mujoco/*.py", "sim/recording.py", "sim/_ray.py")


def _adapter_files() -> list[Path]:
    return sorted(path for pattern in ADAPTERS for path in ROOT.glob(pattern))


def test_no_any_in_the_simulation_adapters() -> None:
    files = _adapter_files()
    assert len(files) > 3, files
    counts = {path.relative_to(ROOT).as_posix(): n for path in files if (n := any_count(path))}
    assert counts == {}


def test_mypy_rejects_any_in_the_simulation_adapters() -> None:
    overrides = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["mypy"]["overrides"]
    (strict,) = [o for o in overrides if "motiontool.sim._mujoco.*" in o["module"]]
    assert strict["disallow_any_unimported"] is True
    assert strict["disallow_any_explicit"] is True
    modules = set(strict["module"])
    for path in _adapter_files():
        dotted = "motiontool." + path.relative_to(ROOT).with_suffix("").as_posix().replace("/", ".")
        package = dotted.rsplit(".", 1)[0]
        assert dotted.removesuffix(".__init__") in modules or f"{package}.*" in modules, dotted
    exempt = {m for o in overrides if o.get("disallow_any_explicit") is False for m in o["module"]}
    assert not {
        m for m in exempt if m.startswith(("motiontool.sim._mujoco", "motiontool.sim._ray"))
    }
    assert "motiontool.sim.recording" not in exempt


def test_only_the_api_module_meets_the_untyped_mujoco() -> None:
    # Not even under TYPE_CHECKING: without stubs, `mujoco.MjModel` is Any to mypy. The module
    # object enters through api.mj(), typed as api.MuJoCo.
    assert imports_of(ROOT / "sim", ("mujoco",), ROOT) == []


@pytest.mark.needs("sim")
@pytest.mark.parametrize("robot", ["nao", "ur5e"])
def test_the_protocols_match_the_real_mujoco(robot: str) -> None:
    import mujoco

    mj = api.mj()
    assert mj is mujoco  # the module itself: no wrapper between the stepping loop and mj_step
    spec = _load_spec(load_robot(robot), 0.002)
    scene = build_scene(load_robot(robot), 20)
    model, data = scene.model, scene.data
    assert type(model) is mujoco.MjModel and type(data) is mujoco.MjData
    mujoco.mj_forward(model, data)
    body = spec.worldbody.add_body(name="probe_body", mass=1.0)
    enums = {
        mujoco.mjtGeom: api._Geoms,
        mujoco.mjtJoint: api._Joints,
        mujoco.mjtLimited: api._Limited,
        mujoco.mjtJacobian: api._Jacobians,
        mujoco.mjtCone: api._Cones,
    }
    found = {
        "MuJoCo": missing(mj, api.MuJoCo),
        "MjSpec class": missing(mujoco.MjSpec, api._SpecClass),
        "mjtWarning": missing(mujoco.mjtWarning, api._Enum),
        **{enum.__name__: missing(enum, protocol) for enum, protocol in enums.items()},
        "MjModel": missing(model, api.MjModel),
        "MjModel.opt": missing(model.opt, api._Option),
        "MjModel.body()": missing(model.body(1), api._NamedView),
        "MjModel.joint()": missing(model.joint(scene.joints[0]), api._NamedView),
        "MjModel.geom()": missing(model.geom("floor"), api._GeomView),
        "MjData": missing(data, api.MjData),
        "MjData.contact": missing(data.contact, api._Contacts),
        "MjData.warning[0]": missing(data.warning[0], api._WarningStat),
        "MjSpec": missing(spec, api.MjSpec),
        "MjSpec.option": missing(spec.option, api._SpecOption),
        "MjSpec.compiler": missing(spec.compiler, api._Compiler),
        "MjsBody": missing(body, api.MjsBody),
        "MjsJoint": missing(spec.joints[0], api.MjsJoint),
        "MjsGeom": missing(spec.geoms[0], api.MjsGeom),
        "MjsTendon": missing(spec.add_tendon(name="probe_tendon"), api.MjsTendon),
        "MjsMesh": missing(spec.add_mesh(name="probe_mesh"), api.MjsMesh),
        "MjsPair": missing(spec.add_pair(geomname1="a", geomname2="b"), api.MjsPair),
    }
    assert found == {name: [] for name in found}
    if scene.tool is not None and scene.tool[1] == "site":  # the UR5e's tool_slot
        assert not missing(model.site(scene.tool[2]), api._NamedView)
    # An enum member hashes and compares as its int value (EnumValue): the code compares and
    # looks up MuJoCo's int tables (geom_type) with them.
    for enum, protocol in enums.items():
        for name in members(protocol):
            value = getattr(enum, name)
            assert value == int(value) and hash(value) == hash(int(value)), name


def test_the_protocol_check_sees_a_missing_member() -> None:
    class Partial:
        nbody = 2

    assert "ngeom" in missing(Partial(), api.MjModel)
    assert "nbody" not in missing(Partial(), api.MjModel)


@pytest.mark.needs("rerun")
def test_rerun_is_typed_by_its_own_annotations(tmp_path: Path) -> None:
    import rerun as rr

    from motiontool.sim import recording

    spec = importlib.util.find_spec("rerun")
    assert spec is not None and spec.origin is not None
    assert (Path(spec.origin).parent / "py.typed").is_file()
    # What recording.py's annotations say its stream is, the real one is.
    rec, memory = recording._stream("typed", {"tool": "motiontool"})
    assert isinstance(rec, rr.RecordingStream)
    assert isinstance(memory, rr.MemoryRecording)
    recording._finish(rec, memory, tmp_path / "typed.rrd")
    assert (tmp_path / "typed.rrd").stat().st_size > 0


@pytest.mark.needs("ray")
def test_ray_is_typed_by_its_own_annotations() -> None:
    import ray

    spec = importlib.util.find_spec("ray")
    assert spec is not None and spec.origin is not None
    assert (Path(spec.origin).parent / "py.typed").is_file()
    # The names sim/_ray.py uses, with the types it is checked against.
    for name in ("init", "is_initialized", "shutdown", "remote", "wait", "get", "cancel"):
        assert callable(getattr(ray, name)), name
    assert isinstance(ray.ObjectRef, type)
    assert issubclass(ray.exceptions.RayError, Exception)
