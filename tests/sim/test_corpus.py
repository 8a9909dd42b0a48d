"""The Webots Nao motions do what their names say (acceptance bands: docs/simulation.md).

Every motion is simulated once per session (module-scoped cache); the tests only read reports.
Played from the standing zero pose (StandUpFromFront: lying face down), 20 ms control step,
1 s of held targets after the motion.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from conftest import CORPUS, missing_data

from motiontool.sim import PlayOptions, PlayReport, play

pytestmark = [pytest.mark.slow, pytest.mark.needs("sim"), pytest.mark.usefixtures("corpus")]

WALKS = {  # name: (dx band m, dy band m), None = not bounded
    "Forwards50": ((0.35, 0.55), (-0.05, 0.05)),
    "Forwards": ((0.06, 0.13), None),
    "Backwards": ((-0.13, -0.06), None),
    "SideStepLeft": ((-0.03, 0.03), (0.04, 0.09)),
    "SideStepRight": ((-0.03, 0.03), (-0.09, -0.04)),
}
TURNS = {  # name: yaw band, degrees
    "TurnLeft40": (32.0, 46.0),
    "TurnRight40": (-46.0, -32.0),
    "TurnLeft60": (50.0, 68.0),
    "TurnRight60": (-68.0, -50.0),
    "TurnLeft180": (170.0, 215.0),
}
ARMS = ("HandWave", "HandWaveLeft", "WipeForehead")


def corpus_file(name: str) -> Path:
    found = sorted(CORPUS.rglob(f"{name}.motion"))
    if not found:
        missing_data(f"{name}.motion not in the Webots corpus at {CORPUS}")
    return found[0]


class Runs:
    """Each (motions, options) simulated once."""

    def __init__(self) -> None:
        self._cache: dict[tuple[tuple[str, ...], PlayOptions, bool], PlayReport] = {}
        self.rrd_dir: Path | None = None

    def __call__(self, *names: str, rrd: bool = False, **options: object) -> PlayReport:
        opts = PlayOptions(**options)  # type: ignore[arg-type]
        key = (names, opts, rrd)
        if key not in self._cache:
            path = self.rrd_dir / ("+".join(names) + ".rrd") if rrd and self.rrd_dir else None
            self._cache[key] = play(
                [corpus_file(n) for n in names], robot="nao", options=opts, rrd=path
            )
        return self._cache[key]


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> Runs:
    cache = Runs()
    cache.rrd_dir = tmp_path_factory.mktemp("rrd")
    return cache


def assert_walked_upright(report: PlayReport) -> None:
    base = report.base
    assert base is not None
    assert not base.fell, f"fell at {base.fell_at_s} s"
    assert base.max_tilt_deg < 15.0
    assert base.final_tilt_deg < 5.0
    assert report.clean, report.problems


@pytest.mark.parametrize("name", sorted(WALKS))
def test_walks_go_where_their_name_says(runs: Runs, name: str) -> None:
    report = runs(name)
    assert_walked_upright(report)
    assert report.base is not None
    (dx_lo, dx_hi), dy = WALKS[name]
    assert dx_lo <= report.base.dx_m <= dx_hi
    if dy is not None:
        assert dy[0] <= report.base.dy_m <= dy[1]
    if name == "Forwards50":
        assert report.base.yaw_change_deg is not None
        assert abs(report.base.yaw_change_deg) < 5.0


@pytest.mark.parametrize("name", sorted(TURNS))
def test_turns_turn_by_roughly_their_angle_on_the_spot(runs: Runs, name: str) -> None:
    report = runs(name)
    assert_walked_upright(report)
    assert report.base is not None and report.base.yaw_change_deg is not None
    lo, hi = TURNS[name]
    assert lo <= report.base.yaw_change_deg <= hi
    assert abs(report.base.dx_m) < 0.03 and abs(report.base.dy_m) < 0.03


def test_turn_left_10_turns_left(runs: Runs) -> None:
    # The "10" is not degrees: it turns about 32 degrees.
    report = runs("TurnLeft10")
    assert report.base is not None and report.base.yaw_change_deg is not None
    assert not report.base.fell
    assert report.base.yaw_change_deg > 10.0


@pytest.mark.parametrize("name", ARMS)
def test_arm_motions_keep_the_feet_planted(runs: Runs, name: str) -> None:
    report = runs(name)
    assert report.base is not None and report.base.yaw_change_deg is not None
    assert all(f.max_displacement_m < 0.005 for f in report.feet), report.feet
    assert report.base.max_tilt_deg < 3.0
    assert abs(report.base.yaw_change_deg) < 1.0
    assert not report.base.fell


def test_taichi_balances_on_one_leg_without_falling(runs: Runs) -> None:
    report = runs("TaiChi")
    assert report.base is not None
    assert not report.base.fell
    assert report.base.max_tilt_deg > 20.0  # it does lean over its standing leg
    assert report.base.final_tilt_deg < 5.0


def test_stand_up_from_front_ends_standing(runs: Runs) -> None:
    report = runs("StandUpFromFront", start="lying-front")
    base = report.base
    assert base is not None
    assert base.started_down and base.upright_at_end and not base.fell
    assert base.final_height_m > 0.30
    assert base.final_tilt_deg < 15.0


@pytest.mark.needs("rerun")
def test_fall_falls_and_the_recording_says_when(runs: Runs) -> None:
    report = runs("Fall", rrd=True)
    assert report.base is not None and report.base.fell
    assert report.exit_code == 1 and "fell" in "; ".join(report.problems)
    from rerun.chunk import RrdReader

    assert runs.rrd_dir is not None
    texts: list[str] = []
    for chunk in RrdReader(runs.rrd_dir / "Fall.rrd").stream().to_chunks():
        if chunk.entity_path == "/events":
            for row in chunk.to_record_batch().column("TextLog:text").to_pylist():
                texts += row
    assert any("fell" in t for t in texts)


def test_a_sequence_walks_along_the_new_heading(runs: Runs) -> None:
    report = runs("TurnLeft60", "Forwards50")
    assert_walked_upright(report)
    assert report.base is not None and report.base.yaw_change_deg is not None
    assert 50.0 <= report.base.yaw_change_deg <= 68.0
    import math

    heading = math.degrees(math.atan2(report.base.dy_m, report.base.dx_m))
    assert 45.0 <= heading <= 75.0
    assert math.hypot(report.base.dx_m, report.base.dy_m) > 0.35


def test_looping_a_walk_walks_further(runs: Runs) -> None:
    once = runs("Forwards")
    twice = runs("Forwards", loops=2)
    assert once.base is not None and twice.base is not None
    assert_walked_upright(twice)
    assert 1.6 * once.base.dx_m <= twice.base.dx_m <= 2.4 * once.base.dx_m
