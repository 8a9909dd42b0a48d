"""The robot's kinematic tables on disk (``kinematics/tables_cache.py``): read back equal to
the tables Pinocchio builds, keyed by what they depend on, rebuilt when unreadable."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from motiontool.kinematics import tables_cache
from motiontool.kinematics._pinocchio import kinematic_tables
from motiontool.kinematics.collision import scan_self_collisions
from motiontool.kinematics.robots import load_robot


@pytest.fixture
def cache(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.setattr(tables_cache, "_IN_PROCESS", {})
    return tmp_path / "motiontool" / "kinematics"


def _same(a: tables_cache.KinematicTables, b: tables_cache.KinematicTables) -> None:
    for name, x, y in zip(a._fields, a, b, strict=True):
        if isinstance(x, np.ndarray):
            assert x.dtype == y.dtype and np.array_equal(x, y), name
        else:
            assert x == y and type(x) is type(y), name


@pytest.mark.needs("kinematics", "sim")
@pytest.mark.parametrize("robot", ["nao", "nao-v5", "ur5e"])
def test_stored_tables_read_back_equal_to_the_built_ones(robot: str, cache: Path) -> None:
    spec = load_robot(robot)
    built = kinematic_tables(spec)
    _same(tables_cache.stored_tables(spec), built)
    assert [p.name for p in cache.iterdir()] == [f"{tables_cache.tables_key(spec)}.npy"]
    tables_cache._IN_PROCESS.clear()
    _same(tables_cache.stored_tables(spec), built)  # this time from the file


def test_robots_and_code_have_their_own_key() -> None:
    nao, v5 = load_robot("nao"), load_robot("nao-v5")
    assert tables_cache.tables_key(nao) != tables_cache.tables_key(v5)  # overrides differ


@pytest.mark.needs("kinematics", "sim")
@pytest.mark.parametrize("cut", [None, 0.5, 0.999])
def test_an_unreadable_file_is_built_again(cache: Path, cut: float | None) -> None:
    spec = load_robot("ur5e")
    path = cache / f"{tables_cache.tables_key(spec)}.npy"
    tables_cache.stored_tables(spec)
    tables_cache._IN_PROCESS.clear()
    whole = path.read_bytes()
    # Not a table at all, or one cut short (in an array, or in the last).
    path.write_bytes(b"not a table" if cut is None else whole[: int(len(whole) * cut)])
    _same(tables_cache.stored_tables(spec), kinematic_tables(spec))
    assert path.read_bytes() == whole  # stored again, whole


@pytest.mark.needs("kinematics", "sim")
def test_collisions_are_the_same_from_stored_tables(cache: Path) -> None:
    spec = load_robot("nao")
    rng = np.random.default_rng(7)
    lower = np.array([j.lower for j in spec.joints])
    upper = np.array([j.upper for j in spec.joints])
    q = rng.uniform(lower, upper, size=(300, len(spec.joints)))
    fresh = scan_self_collisions(spec, q, penetration_tolerance_m=0.015)
    assert fresh  # random poses of the Nao run into themselves
    tables_cache._IN_PROCESS.clear()
    stored = scan_self_collisions(spec, q, penetration_tolerance_m=0.015)
    assert [c[:3] for c in stored] == [c[:3] for c in fresh]
    # coal's GJK/EPA starts from its previous answer: depths agree to well under a micrometre
    assert [c.depth_m for c in stored] == pytest.approx([c.depth_m for c in fresh], abs=1e-6)
