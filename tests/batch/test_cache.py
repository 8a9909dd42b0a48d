"""batch's result cache: bounded in size (least recently used results go first), and
``motiontool cache`` to see and empty it."""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import pytest
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.disk_cache import ResultCache
from motiontool.sim.batch import RunSpec, plan, run_batch

cli = CliRunner()


def runner(spec: RunSpec) -> dict[str, Any]:
    """A stand-in for the simulator: every run is clean, its report names the file."""
    return {"clean": True, "reason": "", "path": spec.path}


def _filled(directory: Path, n: int = 5, size: int = 1000) -> ResultCache:
    """``n`` results of about ``size`` bytes, result i last used at t = i s."""
    cache = ResultCache(directory, max_bytes=None)
    for i in range(n):
        key = f"{i:02d}" + "a" * 62
        cache.store(key, {"i": i, "pad": "x" * (size - 20)})
        os.utime(directory / key[:2] / f"{key}.json", (i, i))
    return cache


def _kept(directory: Path) -> list[int]:
    return sorted(int(p.name[:2]) for p in directory.glob("??/*.json"))


def test_prune_removes_the_least_recently_used_first(tmp_path: Path) -> None:
    cache = _filled(tmp_path)
    size = cache.usage().size_bytes // 5
    assert cache.load("00" + "a" * 62) == {"i": 0, "pad": "x" * 980}  # read: used just now
    removed = cache.prune(3 * size)
    assert (removed.results, removed.size_bytes) == (2, 2 * size)
    assert _kept(tmp_path) == [0, 3, 4]
    assert cache.usage().size_bytes <= 3 * size
    assert not (tmp_path / "01").exists()  # an emptied folder goes too
    assert cache.prune(0).results == 3 and cache.usage().results == 0


def test_a_batch_leaves_the_cache_within_its_limit(tmp_path: Path) -> None:
    motions = []
    for i in range(6):
        path = tmp_path / f"m{i}.motion"
        path.write_bytes(f"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n{500 + i},B,0.5\n".encode())
        motions.append(path)
    specs = plan(motions, ["nao"])
    directory = tmp_path / "cache"
    run_batch(specs, runner, model_hash=lambda r: "h", jobs=1, cache_dir=directory)
    one = ResultCache(directory).usage().size_bytes // 6
    assert ResultCache(directory).usage().results == 6  # far below the default 500 MB
    run_batch(
        specs,
        runner,
        model_hash=lambda r: "h2",
        jobs=1,
        cache_dir=directory,
        cache_max_bytes=4 * one,
    )
    usage = ResultCache(directory).usage()
    assert usage.size_bytes <= 4 * one and usage.results == 4


def test_cache_info_and_clean(tmp_path: Path) -> None:
    _filled(tmp_path / "c")
    result = cli.invoke(app, ["cache", "info", "--cache-dir", str(tmp_path / "c")])
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith(f"{tmp_path / 'c'}: 5 results, 0.0 MB")
    result = cli.invoke(
        app, ["cache", "clean", "--cache-dir", str(tmp_path / "c"), "--max-mb", "0.0025"]
    )
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith("removed 3 results (0.0 MB) from ")
    assert result.stdout.count("\n") == 1 and "2 left" in result.stdout
    assert _kept(tmp_path / "c") == [3, 4]
    result = cli.invoke(app, ["cache", "clean", "--cache-dir", str(tmp_path / "c")])
    assert result.exit_code == 0 and "removed 2 results" in result.stdout
    assert _kept(tmp_path / "c") == []


def test_cache_options_are_checked(tmp_path: Path) -> None:
    for args in (
        ["cache", "clean", "--max-mb", "-1"],
        ["cache", "clean", "--max-mb", "nan"],
        ["cache", "wipe"],
        ["batch", "x.motion", "--cache-max-mb", "inf"],
    ):
        result = cli.invoke(app, [*args, "--cache-dir", str(tmp_path)])
        assert result.exit_code == 2, (args, result.output)
        assert result.stderr.startswith("motiontool: error: "), result.stderr


def test_prune_keeps_at_most_max_results_the_most_recently_used(tmp_path: Path) -> None:
    _filled(tmp_path, n=5, size=100)
    cache = ResultCache(tmp_path, max_bytes=None, max_results=2)
    assert cache.prune().results == 3
    assert _kept(tmp_path) == [3, 4]
    assert ResultCache(tmp_path, max_bytes=10**6, max_results=2).prune().results == 0


@pytest.mark.parametrize("where", ["open", "fdopen", "replace"])
def test_a_signal_while_a_result_is_stored_leaves_no_temporary_file(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, where: str
) -> None:
    """Ctrl-C (or SIGTERM, which the CLI raises as an exception) at any moment of a store: the
    temporary file made so far is removed, whatever was stored before stays whole."""
    import motiontool.disk_cache as disk_cache

    cache = ResultCache(tmp_path)
    assert cache.store("ab" + "c" * 62, {"kept": 1})
    real = {"open": os.open, "fdopen": os.fdopen, "replace": os.replace}[where]

    def interrupted(*args: Any, **kwargs: Any) -> Any:
        if where == "open":
            real(*args, **kwargs)  # the file is made, then the signal comes
        raise KeyboardInterrupt

    monkeypatch.setattr(disk_cache.os, where, interrupted)
    with pytest.raises(KeyboardInterrupt):
        cache.store("ab" + "c" * 62, {"kept": 2})
    monkeypatch.undo()
    assert [p.name for p in tmp_path.rglob("*")] == ["ab", "ab" + "c" * 62 + ".json"]
    assert cache.load("ab" + "c" * 62) == {"kept": 1}
