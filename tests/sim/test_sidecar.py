"""``motions.toml`` sidecars: lookup, matching, errors with their line; the project's own."""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import ROOT

from motiontool.motionfmt.fileio import collect_motion_files
from motiontool.sim.sidecar import (
    SidecarError,
    expectations_for,
    find_sidecar,
    load_sidecar,
    lookup,
    search_boundary,
)

MOTION = b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n200,B,0.1\n"

SIDECAR = """\
# comment
["Turn*"]
expect = ["upright"]
start = "lying-back"

[TurnLeft60]  # the exact name
expect = ["yaw=60±10"]
start = "standing"

["nao/*"]
expect = ["feet-planted"]
"""


def tree(root: Path, *names: str) -> list[Path]:
    out = []
    for name in names:
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(MOTION)
        out.append(path)
    return out


def test_sections_match_names_globs_and_paths_and_add_up(tmp_path: Path) -> None:
    turn, nao_turn, other = tree(
        tmp_path, "TurnLeft60.motion", "nao/TurnRight40.motion", "nao/sub/wave.motion"
    )
    (tmp_path / "motions.toml").write_text(SIDECAR, encoding="utf-8")
    sidecar = load_sidecar(tmp_path / "motions.toml")
    assert [(s.key, s.line) for s in sidecar.sections] == [
        ("Turn*", 2),
        ("TurnLeft60", 6),
        ("nao/*", 10),
    ]
    entry = sidecar.lookup(turn)
    assert entry is not None
    assert entry.sections == ("Turn*", "TurnLeft60")
    assert entry.expect == ("upright", "yaw=60±10")  # in file order
    assert entry.start == "standing"  # the exact name beats the glob
    entry = sidecar.lookup(nao_turn)
    assert entry is not None
    assert (entry.expect, entry.start) == (("upright", "feet-planted"), "lying-back")
    entry = sidecar.lookup(other)  # fnmatch: '*' matches '/' too, 'nao/*' is all below nao/
    assert entry is not None and entry.expect == ("feet-planted",)
    assert sidecar.lookup(tmp_path / "TurnLeft60.txt") is not None  # the stem is matched
    assert sidecar.lookup(tmp_path / "wave.motion") is None
    assert expectations_for(turn, ["dx>0"], roots=[tmp_path]) == (
        ("upright", "yaw=60±10", "dx>0"),
        "standing",
    )
    assert expectations_for(turn, ["dx>0"], sidecar=False) == (("dx>0",), None)


def test_the_nearest_sidecar_up_to_the_boundary_wins(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (deep,) = tree(tmp_path, "project/motions/nao/wave.motion")
    project = tmp_path / "project"
    (tmp_path / "motions.toml").write_text('[wave]\nexpect = ["fell"]\n')  # above the boundary
    # Not below the current directory: the search stops at the batch root, or the folder.
    assert search_boundary(deep) == deep.parent
    assert search_boundary(deep, [project]) == project
    assert find_sidecar(deep, project) is None
    (project / "motions.toml").write_text('[wave]\nexpect = ["upright"]\n')
    assert find_sidecar(deep, project) == project / "motions.toml"
    assert find_sidecar(deep) is None  # default boundary: the motion's own folder
    nearer = project / "motions" / "motions.toml"
    nearer.write_text('["w*"]\nexpect = ["feet-planted"]\n')
    entry = lookup(deep, [project])
    assert entry is not None and entry.expect == ("feet-planted",)  # sidecars do not merge
    monkeypatch.chdir(project)  # below the current directory: it is the boundary
    assert search_boundary(deep) == project
    assert find_sidecar(deep) == Path("motions/motions.toml")  # shown relative to it


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (
            "[wave\nexpect = []\n",
            r"motions.toml:1:6: Expected ']' at the end of a table declaration",
        ),
        (
            '[wave]\nexpects = ["upright"]\n',
            r"motions.toml:2: unknown key 'expects' in \[wave\]; did you mean 'expect'\? \(keys: expect, start, world, robot-node, after\)",
        ),
        (
            '[wave]\nexpect = [\n  "upright",\n  "dxx>0",\n]\n',
            r"motions.toml:4: expectation 'dxx>0': unknown quantity 'dxx'; did you mean 'dx'\?",
        ),
        (
            '[wave]\nstart = "sitting"\n',
            r"motions.toml:2: start 'sitting' in \[wave\]: choose standing, lying-front, lying-back",
        ),
        ('expect = ["upright"]\n', r"motions.toml:1: 'expect' is not a \[section\]"),
        ("[wave]\nexpect = 3\n", r"motions.toml:2: expect in \[wave\] must be a list of strings"),
    ],
)
def test_sidecar_errors_name_the_line(tmp_path: Path, text: str, message: str) -> None:
    path = tmp_path / "motions.toml"
    path.write_text(text)
    with pytest.raises(SidecarError, match=message) as info:
        load_sidecar(path)
    assert str(info.value).startswith(str(path)) and "\n" not in str(info.value)


def test_a_sidecar_that_is_not_utf8_names_the_line(tmp_path: Path) -> None:
    path = tmp_path / "motions.toml"
    path.write_bytes(b'[wave]\n# caf\xe9\nexpect = ["upright"]\n')
    with pytest.raises(SidecarError, match=r"motions.toml:2: not UTF-8"):
        load_sidecar(path)


def test_the_project_library_has_a_sidecar_for_every_motion() -> None:
    sidecar = load_sidecar(ROOT / "motions" / "motions.toml")
    motions = collect_motion_files([ROOT / "motions"])
    matched = set()
    for motion in motions:
        assert find_sidecar(motion, ROOT) == ROOT / "motions" / "motions.toml" or (
            find_sidecar(motion, ROOT) == Path("motions/motions.toml")
        )
        entry = sidecar.lookup(motion)
        assert entry is not None and entry.expect, motion
        assert "no-self-collision" in entry.expect
        matched.update(entry.sections)
    assert matched == {s.key for s in sidecar.sections}  # no section matches nothing


def test_after_names_the_motion_played_before(tmp_path: Path) -> None:
    (tmp_path / "motions.toml").write_text(
        '["*_Loop"]\nafter = "Walk_Start"\n\n[Walk_Stop]\nafter = "Walk_Loop"\n'
        "\n[Odd]\nafter = 3\n",
        encoding="utf-8",
    )
    with pytest.raises(SidecarError, match=r"motions.toml:8: after in \[Odd\] must be a string"):
        load_sidecar(tmp_path / "motions.toml")
    (tmp_path / "motions.toml").write_text(
        '["*_Loop"]\nafter = "Walk_Start"\n\n[Walk_Stop]\nafter = "Walk_Loop"\n',
        encoding="utf-8",
    )
    sidecar = load_sidecar(tmp_path / "motions.toml")
    loop, stop = (
        sidecar.lookup(tmp_path / "Walk_Loop.motion"),
        sidecar.lookup(tmp_path / "Walk_Stop.motion"),
    )
    assert loop is not None and loop.after == "Walk_Start"
    assert stop is not None and stop.after == "Walk_Loop"
