"""``expect --infer`` proposes expectations only for motion files Webots loads."""

from __future__ import annotations

from pathlib import Path

import pytest
from typer.testing import CliRunner

from motiontool.cli.app import app

runner = CliRunner()


@pytest.mark.parametrize(
    ("data", "where", "why"),
    [
        (b"x\n", "1:1", "expected '#WEBOTS_MOTION' as the first token, found 'x'"),
        (b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,P,abc\n", "2:13", "for HeadYaw, found 'abc'"),
    ],
)
def test_a_file_that_is_not_a_motion_gets_no_proposal(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, data: bytes, where: str, why: str
) -> None:
    monkeypatch.chdir(tmp_path)
    Path("TurnLeft60.motion").write_bytes(data)
    result = runner.invoke(app, ["expect", "--infer", "TurnLeft60.motion"])
    assert (result.exit_code, result.stdout) == (2, "")
    assert result.stderr.startswith(
        f"motiontool: error: TurnLeft60.motion:{where}: not a motion file Webots loads: "
    )
    assert why in result.stderr and result.stderr.count("\n") == 1
