"""``validate``'s findings cache (the pre-commit case): a small file checked
before gets its robot findings from ``~/.cache/motiontool/lint`` without running the checks or
importing numpy, and the report is the one a fresh check gives, whatever changed in between."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from conftest import CORPUS, DATA
from typer.testing import CliRunner

from motiontool.cli.app import app
from motiontool.disk_cache import files_stamp, libraries_stamp
from motiontool.errors import MissingExtraError
from motiontool.kinematics.checks import findings_cache, runner
from motiontool.kinematics.checks.findings_cache import FindingsCache, _decode, _encode
from motiontool.kinematics.checks.limits import Limits
from motiontool.kinematics.checks.self_collision import Collision
from motiontool.kinematics.checks.velocity import Velocity
from motiontool.kinematics.mjcf_table import parse_mjcf_table
from motiontool.motionfmt.diagnostics import Diagnostic

cli = CliRunner()
NAO = CORPUS / "projects" / "robots" / "softbank" / "nao" / "motions"
DANCE = CORPUS / "projects" / "robots" / "softbank" / "dancing_nao" / "motions"
#: MT307 (salute: head and hand 25 mm deep), MT302 runs (Taichi), MT302 and MT303 (HandsUp).
FILES = (DATA / "robots" / "salute_fixed.motion", NAO / "Taichi.motion", DANCE / "HandsUp.motion")


@pytest.fixture
def store(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """The findings cache on (the tests' default is off), in a folder of its own."""
    monkeypatch.delenv("MOTIONTOOL_NO_CACHE", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    return tmp_path / "xdg" / "motiontool" / "lint"


def validate(*args: str | Path) -> tuple[int, str]:
    result = cli.invoke(app, ["validate", *map(str, args)])
    assert not result.stderr, result.stderr
    return result.exit_code, result.stdout


def no_check_may_run(monkeypatch: pytest.MonkeyPatch) -> None:
    def refuse(*_args: object, **_kwargs: object) -> None:
        raise AssertionError("a check ran: the findings were not taken from the cache")

    for check in (Limits, Velocity, Collision):
        monkeypatch.setattr(check, "_check", refuse)


@pytest.mark.parametrize(
    "fmt", [pytest.param("text", marks=pytest.mark.needs("kinematics")), "json", "sarif"]
)
def test_a_report_from_the_cache_is_the_report_checked_afresh(
    store: Path, fmt: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    files = [str(f) for f in FILES]
    fresh = validate("-f", fmt, "--no-cache", *files)
    assert not store.exists()  # --no-cache stores nothing
    assert validate("-f", fmt, *files) == fresh  # checked, then stored
    assert len(list(store.glob("??/*.json"))) == len(FILES)
    with monkeypatch.context() as m:
        no_check_may_run(m)
        assert validate("-f", fmt, *files) == fresh
    if fmt == "text":
        codes = {"MT302", "MT303", "MT307"}
        assert fresh[0] == 1 and all(f" {c}: " in fresh[1] for c in codes), fresh[1]


def test_a_check_skipped_for_a_missing_library_is_noted_from_the_cache_too(
    store: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    def missing(*_args: object, **_kwargs: object) -> None:
        raise MissingExtraError("pinocchio", "kinematics", "the collision check", "Pinocchio")

    files = [str(f) for f in FILES]
    with monkeypatch.context() as m:
        m.setattr(Collision, "_check", missing)
        fresh = validate("--no-cache", *files)
        assert validate(*files) == fresh
        # The same checks asked for by name must run: the missing library is an error.
        named = cli.invoke(app, ["validate", "--checks", "limits,velocity,collision", *files])
        assert named.exit_code == 2 and "needs Pinocchio" in named.stderr, named.output
    assert "info MT902: collision check skipped: Pinocchio is not installed" in fresh[1]
    assert " MT307: " not in fresh[1]
    with monkeypatch.context() as m:
        no_check_may_run(m)
        assert validate(*files) == fresh


@pytest.mark.needs("kinematics")
def test_what_the_findings_depend_on_is_in_the_key(store: Path, tmp_path: Path) -> None:
    motion = tmp_path / "m.motion"
    shutil.copyfile(FILES[0], motion)
    copy = tmp_path / "copy.motion"
    shutil.copyfile(FILES[0], copy)
    variants = [
        [motion],
        ["--robot", "nao-v5", motion],
        ["--checks", "limits", motion],
        ["--collision-tolerance", "30", motion],
        ["--timestep", "40", motion],
        ["--no-group", NAO / "Taichi.motion"],
        [NAO / "Taichi.motion"],
        [copy],  # the same bytes at another path: findings name their file
    ]
    seen = []
    for args in variants:
        fresh = validate("--no-cache", *args)
        assert validate(*args) == fresh, args
        seen.append(fresh[1])
    assert len(set(seen)) == len(seen)  # each variant reports something else
    # The same path, other bytes: RShoulderPitch far past its limit, one finding more.
    motion.write_bytes(motion.read_bytes().replace(b"Pose2,1.5,", b"Pose2,2.5,"))
    fresh = validate("--no-cache", motion)
    assert validate(motion) == fresh and " MT302: " in fresh[1] and " MT302: " not in seen[0]


@pytest.mark.needs("kinematics")
def test_an_edited_robot_model_is_a_new_key(store: Path, tmp_path: Path) -> None:
    model = tmp_path / "nao.xml"
    shutil.copyfile(Path(runner.__file__).parents[1] / "models" / "nao.xml", model)
    args = ("--robot", model, "--checks", "limits", FILES[0])
    fresh = validate("--no-cache", *args)
    assert validate(*args) == fresh and " MT302: " not in fresh[1]
    # The same model file, RShoulderPitch's range narrowed: Pose2's 1.5 rad is past it.
    joint = '<joint name="RShoulderPitch" type="hinge" axis="0 1 0" range='
    text = model.read_text().replace(f'{joint}"-2.08567 2.08567"', f'{joint}"-1 1"')
    model.write_text(text)
    parse_mjcf_table.cache_clear()  # a model is read once per process: this is a new process
    fresh = validate("--no-cache", *args)
    assert validate(*args) == fresh and " MT302: " in fresh[1]


@pytest.mark.needs("kinematics")
def test_a_file_named_otherwise_takes_its_findings_with_its_new_name(
    store: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    shutil.copyfile(FILES[0], tmp_path / "salute.motion")
    monkeypatch.chdir(tmp_path)
    named = validate(tmp_path / "salute.motion")  # as the editor names it: stored
    fresh = validate("--no-cache", "salute.motion")  # as the hook names it
    with monkeypatch.context() as m:
        no_check_may_run(m)
        assert validate("salute.motion") == fresh != named
    assert "\nsalute.motion:2:1: warning MT307: " in fresh[1]
    # A file whose name is in its findings' words (a joint's name): not stored.
    shutil.copyfile(FILES[0], tmp_path / "RElbowRoll")
    fresh = validate("--no-cache", "RElbowRoll", "--robot", "nao-v5")
    assert validate("RElbowRoll", "--robot", "nao-v5") == fresh
    assert "RElbowRoll:3:23: error MT302: RElbowRoll = 0 rad" in fresh[1]
    assert len(list(store.glob("??/*.json"))) == 1


def test_a_note_that_reads_the_sibling_file_is_found_again(store: Path, tmp_path: Path) -> None:
    left, right = tmp_path / "HandHighLeft.motion", tmp_path / "HandHighRight.motion"
    shutil.copyfile(DANCE / "HandHighLeft.motion", left)
    right.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,Pose1,0\n")
    _code, out = validate(left)
    assert "MT309" not in out
    shutil.copyfile(DANCE / "HandHighRight.motion", right)  # now an unmirrored copy
    assert validate(left) == validate("--no-cache", left)
    assert " MT309: " in validate(left)[1]


def test_a_file_checked_before_is_checked_without_numpy(store: Path, tmp_path: Path) -> None:
    small = tmp_path / "small.motion"
    small.write_bytes(b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,Pose1,0\n00:00:500,Pose2,0.5\n")
    script = (
        "import sys\nfrom motiontool.cli.__main__ import main\nsys.argv[0] = 'motiontool'\n"
        "try:\n    main()\nfinally:\n    print('numpy' in sys.modules, file=sys.stderr)\n"
    )
    runs = [
        subprocess.run(
            [sys.executable, "-c", script, "validate", str(small)],
            capture_output=True,
            text=True,
            env=os.environ.copy(),
            check=False,
        )
        for _ in range(2)
    ]
    assert [(r.returncode, r.stderr) for r in runs] == [(0, "True\n"), (0, "False\n")]
    assert (
        runs[0].stdout == runs[1].stdout and "checks: limits, velocity, collision" in runs[1].stdout
    )


def test_a_damaged_or_unwritable_store_is_no_error(
    store: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    files = [str(f) for f in FILES]
    fresh = validate("--no-cache", *files)
    assert validate(*files) == fresh
    entries = sorted(store.glob("??/*.json"))
    for entry, damage in zip(entries, [b"{", b'{"layout": 1}', b"[1, 2]"], strict=True):
        entry.write_bytes(damage)
    assert validate(*files) == fresh
    assert all(json.loads(e.read_bytes())["layout"] for e in entries)  # stored again
    # A FIFO where an entry should be: neither read (it would block) nor written through.
    entries[0].unlink()
    os.mkfifo(entries[0])
    assert validate(*files) == fresh
    assert entries[0].is_file() and json.loads(entries[0].read_bytes())["layout"]
    blocked = tmp_path / "blocked"
    blocked.write_bytes(b"")
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocked))  # a file where the folder should be
    assert validate(*files) == fresh


def test_large_files_and_long_reports_are_not_stored(
    store: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    taichi = NAO / "Taichi.motion"
    fresh = validate("--no-cache", "--no-group", taichi)
    monkeypatch.setattr(runner, "MAX_BYTES", taichi.stat().st_size - 1)
    assert validate("--no-group", taichi) == fresh
    assert not store.exists()
    monkeypatch.setattr(runner, "MAX_BYTES", findings_cache.MAX_BYTES)
    report = json.loads(validate("--no-cache", "--no-group", "-f", "json", taichi)[1])
    robot = [d for d in report["files"][0]["diagnostics"] if d["code"].startswith("MT3")]
    assert len(robot) > 10
    monkeypatch.setattr(runner, "MAX_FINDINGS", len(robot) - 1)
    assert validate("--no-group", taichi) == fresh
    assert not store.exists()
    monkeypatch.setattr(runner, "MAX_FINDINGS", len(robot))
    assert validate("--no-group", taichi) == fresh
    assert len(list(store.glob("??/*.json"))) == 1


def test_storing_one_key_in_256_prunes_the_store(tmp_path: Path) -> None:
    cache = FindingsCache(tmp_path, max_mb=0.0002)  # 200 bytes: three small entries
    for i in range(1, 9):
        cache.store(f"{i:02x}" + "a" * 62, [], {}, "m.motion")
    assert len(list(tmp_path.glob("??/*.json"))) == 8
    cache.store("00" + "a" * 62, [], {}, "m.motion")
    assert cache.results.usage().size_bytes <= 200
    assert cache.load("00" + "a" * 62, "m.motion") == ([], {})  # the last stored is the last to go


def test_an_entry_holds_every_field_of_a_finding_exactly(store: Path) -> None:
    validate("--no-cache", *FILES)  # nothing stored
    validate(*FILES)
    found = [
        _decode(item, "x.motion")
        for entry in sorted(store.glob("??/*.json"))
        for item in json.loads(entry.read_bytes())["findings"]
    ]
    for field in ("run", "pose", "hint", "joint", "time_ms", "end_column"):
        assert any(getattr(d, field) is not None for d in found), field
    for d in found:
        again = _decode(json.loads(json.dumps(_encode(d))), d.path)
        assert again == d and (again.pose, again.run, again.end_column) == (
            d.pose,
            d.run,
            d.end_column,
        )
    with pytest.raises(ValueError, match="expected"):
        _decode([*_encode(found[0])[:-1]], "x.motion")
    with pytest.raises(ValueError, match="expected str"):
        _decode([1, *_encode(found[0])[1:]], "x.motion")
    assert isinstance(found[0], Diagnostic)


def test_the_code_stamp_changes_with_the_code(tmp_path: Path) -> None:
    (tmp_path / "pkg").mkdir()
    module = tmp_path / "pkg" / "m.py"
    module.write_text("x = 1\n")
    (tmp_path / "pkg" / "data.json").write_text("{}")
    before = files_stamp([tmp_path / "pkg"])
    assert files_stamp([tmp_path / "pkg"]) == before
    (tmp_path / "pkg" / "data.json").write_text("{ }")  # not code
    assert files_stamp([tmp_path / "pkg"]) == before
    st = module.stat()
    module.write_text("x = 12\n")
    os.utime(module, ns=(st.st_atime_ns, st.st_mtime_ns))  # the same time, another size
    assert files_stamp([tmp_path / "pkg"]) != before
    before = files_stamp([tmp_path / "pkg"])
    module.write_text("x = 13\n")  # the same size, another time
    os.utime(module, ns=(st.st_atime_ns, st.st_mtime_ns + 1))
    assert files_stamp([tmp_path / "pkg"]) != before
    assert files_stamp([module]) != files_stamp([tmp_path / "pkg" / "n.py"])
    assert libraries_stamp("no_such_library_here") == "no_such_library_here:-"
    assert libraries_stamp("json").startswith("json:/")


def test_cache_info_names_both_caches(store: Path) -> None:
    validate(FILES[0])
    result = cli.invoke(app, ["cache", "info"])
    assert result.exit_code == 0
    lines = result.stdout.splitlines()
    assert lines[0].startswith(f"{store.parent / 'batch'}: 0 results")
    assert lines[1].startswith(f"{store}: 1 results") and "robot findings" in lines[1]
    result = cli.invoke(app, ["cache", "clean"])
    assert result.stdout.splitlines()[1].startswith(f"removed 1 results (0.0 MB) from {store};")
    assert not list(store.glob("??/*.json"))
