"""The Pinocchio adapter's typed surface: no ``Any`` creeps into kinematics, and
the Protocols of ``kinematics/_pinocchio/api.py`` say only what the real library has."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest
from conftest import ROOT
from typed_surface import any_count, imports_of, missing

from motiontool.kinematics._pinocchio import api, build_model
from motiontool.kinematics.robots import load_robot

#: Every ``Any`` left in kinematics/, by file: a JSON document as ``json.loads`` gives it (the
#: import and the one annotation). The table only shrinks.
ALLOWED_ANY = {
    "kinematics/mjcf_table.py": 2,  # the robot overrides file (nao-v5.json)
    "kinematics/_modelgen/mjcf.py": 2,  # Facts: the robot facts of tests/data/robot_facts
}


def test_no_any_creeps_into_kinematics() -> None:
    counts = {
        path.relative_to(ROOT).as_posix(): n
        for path in sorted((ROOT / "kinematics").rglob("*.py"))
        if (n := any_count(path))
    }
    assert counts == ALLOWED_ANY


def test_the_any_count_sees_annotations_and_imports(tmp_path: Path) -> None:
    source = tmp_path / "m.py"
    source.write_text(
        "from __future__ import annotations\nimport typing\nfrom typing import Any\n"
        "def f(x: Any) -> typing.Any: ...\n"
    )
    assert any_count(source) == 3


def test_no_kinematics_module_imports_pinocchio_or_coal() -> None:
    # Not even under TYPE_CHECKING: without stubs, `pin.Model` is Any to mypy.
    assert imports_of(ROOT / "kinematics", ("pinocchio", "coal"), ROOT) == []


def test_mypy_rejects_any_in_kinematics() -> None:
    overrides = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["mypy"]["overrides"]
    (strict,) = [o for o in overrides if "motiontool.kinematics.*" in o["module"]]
    assert strict["disallow_any_unimported"] is True
    assert strict["disallow_any_explicit"] is True
    exempt = [o for o in overrides if o.get("disallow_any_explicit") is False]
    assert {m for o in exempt for m in o["module"]} == {
        "motiontool.kinematics."
        + p.removeprefix("kinematics/").removesuffix(".py").replace("/", ".")
        for p in ALLOWED_ANY
    }


@pytest.mark.needs("kinematics", "sim")
@pytest.mark.parametrize("robot", ["nao", "ur5e"])
def test_the_protocols_match_the_real_pinocchio(robot: str) -> None:
    pin = api.pin_module()
    model, geoms = build_model(load_robot(robot))
    data = model.createData()
    geom_data = pin.GeometryData(geoms)
    q = pin.neutral(model)
    pin.forwardKinematics(model, data, q)
    pin.updateGeometryPlacements(model, data, geoms, geom_data)
    obj = geoms.geometryObjects[0]
    obj.geometry.computeLocalAABB()
    found = {
        "Pinocchio": missing(pin, api.Pinocchio),
        "Model": missing(model, api.Model),
        "Data": missing(data, api.Data),
        "JointModel": missing(model.joints[1], api.JointModel),
        "Frame": missing(model.frames[1], api.Frame),
        "Inertia": missing(model.inertias[1], api.Inertia),
        "SE3": missing(model.jointPlacements[1], api.SE3),
        "GeometryModel": missing(geoms, api.GeometryModel),
        "GeometryObject": missing(obj, api.GeometryObject),
        "GeometryData": missing(geom_data, api.GeometryData),
        "CollisionPair": missing(geoms.collisionPairs[0], api.CollisionPair),
    }
    assert found == {name: [] for name in found}
    # A shape's sizes exist where the shape has them; the bounding box on every geometry.
    geometry = obj.geometry
    assert hasattr(geometry, "aabb_center") and hasattr(geometry, "aabb_radius")
    kind = type(geometry).__name__
    sizes = {"Sphere": ["radius"], "Box": ["halfSide"], "Capsule": ["radius", "halfLength"]}
    assert all(hasattr(geometry, size) for size in sizes.get(kind, []))


def test_the_protocol_check_sees_a_missing_member() -> None:
    class Partial:
        njoints = 2

    assert "nframes" in missing(Partial(), api.Model)
    assert "njoints" not in missing(Partial(), api.Model)
