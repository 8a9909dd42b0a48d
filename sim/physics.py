"""The physics a run uses: the MuJoCo step and the floor friction, by profile.

MuJoCo is not ODE: the numbers of the Webots Nao worlds (floor ``coulombFriction`` 7, physics
at the 20 ms ``basicTimeStep``) make the Webots walks fall in MuJoCo, while μ = 1 and a 2 ms
step make them walk as their names say (docs/play.md, *Fidelity*; ``dev/fidelity_sweep.py`` measures
it). So the ``default`` profile is μ = 1 and 2 ms; ``webots`` takes Webots' numbers, for
comparison only, and every report made with it says so (:data:`WEBOTS_PROFILE_NOTE`).

Pure Python: reading a built scene back (:func:`read_back`) only reads the compiled model's
arrays; nothing here imports :mod:`mujoco`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from motiontool.errors import MotionToolError
from motiontool.motionfmt.units import MS_PER_S

if TYPE_CHECKING:
    from motiontool.sim._mujoco import Scene

__all__ = [
    "DEFAULT_FRICTION",
    "DEFAULT_PHYSICS_STEP_MS",
    "PROFILES",
    "WEBOTS_FRICTION",
    "WEBOTS_PROFILE_NOTE",
    "Physics",
    "check_physics",
    "physics_run_options",
    "profile_note",
    "read_back",
    "resolve_physics",
]

PROFILES = ("default", "webots")
"""Physics profiles: ``default`` (μ = 1, 2 ms) and ``webots`` (μ = 7, physics step = control
step)."""

DEFAULT_FRICTION = 1.0
"""Robot-floor Coulomb friction coefficient of the ``default`` profile (pyramidal cone)."""

DEFAULT_PHYSICS_STEP_MS = 2.0
"""MuJoCo step of the ``default`` profile, ms (where it does not divide the control step: the
largest step below it that does)."""

WEBOTS_FRICTION = 7.0
"""The floor's ``coulombFriction`` in the Webots Nao worlds (``nao_demo.wbt``)."""

WEBOTS_PROFILE_NOTE = (
    "profile webots uses Webots' floor friction (7) and physics step (= the control step); "
    "this is not what makes walks match Webots: MuJoCo's contacts are not ODE's, and with "
    "these numbers the Webots walks fall (docs/play.md, Fidelity)"
)
"""The line a report made with ``--profile webots`` carries when it ran with Webots' numbers
(:func:`profile_note` says what ran when ``--friction`` / ``--physics-step`` override them)."""

STEP_RATIO_SLACK = 1e-9
"""Relative rounding slack when dividing the control step by the physics step: a 20 ms step
over 2 ms is 10 substeps even where the float quotient comes out a hair off 10."""


def substeps_at_most(control_step_ms: float, physics_step_ms: float) -> int:
    """Physics steps per control step: the fewest whose step is at most ``physics_step_ms``.

    Raises:
        MotionToolError: a step that is not a positive number.
    """
    if not control_step_ms > 0:
        raise MotionToolError(f"control step must be positive, got {control_step_ms} ms")
    if not physics_step_ms > 0:
        raise MotionToolError(f"physics step must be positive, got {physics_step_ms} ms")
    return max(1, math.ceil(control_step_ms / physics_step_ms - STEP_RATIO_SLACK))


def substeps_dividing(control_step_ms: float, physics_step_ms: float) -> int | None:
    """Physics steps per control step where ``physics_step_ms`` divides the control step
    (within :data:`STEP_RATIO_SLACK`), else None."""
    ratio = control_step_ms / physics_step_ms
    substeps = round(ratio)
    if substeps < 1 or abs(ratio - substeps) > STEP_RATIO_SLACK * ratio:
        return None
    return substeps


@dataclass(frozen=True)
class Physics:
    """The physics of one run.

    Attributes:
        profile: ``default`` or ``webots``.
        timestep_ms: MuJoCo's step, ms (it divides the control step).
        friction: robot-floor Coulomb friction coefficient, perturbation scale included.
        substeps: physics steps per control step.
        note: what the profile means for the results (``webots``), else None.
    """

    profile: str
    timestep_ms: float
    friction: float
    substeps: int
    note: str | None = None

    def to_json(self) -> dict[str, Any]:
        """The report's ``physics`` section (``profile_note`` only when there is a note)."""
        doc: dict[str, Any] = {
            "timestep_ms": self.timestep_ms,
            "friction": self.friction,
            "profile": self.profile,
        }
        if self.note:
            doc["profile_note"] = self.note
        return doc


def _divisors_ms(control_step_ms: int) -> str:
    found = [d for d in range(1, control_step_ms + 1) if control_step_ms % d == 0]
    return ", ".join(str(d) for d in found)


def check_physics(
    *,
    profile: str = "default",
    physics_step_ms: float | None = None,
    friction: float | None = None,
    friction_scale: float = 1.0,
) -> None:
    """Raise :class:`MotionToolError` (one line) for an unknown profile or a step, friction or
    scale that is not a positive number (whether the step divides the control step is
    :func:`resolve_physics`'s to check: it knows the control step)."""
    if profile not in PROFILES:
        raise MotionToolError(f"physics profile {profile!r}: choose {', '.join(PROFILES)}")
    if friction is not None and not (math.isfinite(friction) and friction > 0):
        raise MotionToolError(f"floor friction must be a number > 0, got {friction:g}")
    if not (math.isfinite(friction_scale) and friction_scale > 0):
        raise MotionToolError(f"friction scale must be a number > 0, got {friction_scale:g}")
    if physics_step_ms is not None and not (math.isfinite(physics_step_ms) and physics_step_ms > 0):
        raise MotionToolError(f"physics step must be a number > 0 ms, got {physics_step_ms:g}")


def resolve_physics(
    control_step_ms: int,
    *,
    profile: str = "default",
    physics_step_ms: float | None = None,
    friction: float | None = None,
    friction_scale: float = 1.0,
) -> Physics:
    """The physics of a run at ``control_step_ms``.

    Args:
        control_step_ms: the control period (Webots' basicTimeStep), ms.
        profile: ``default`` (μ = 1, 2 ms) or ``webots`` (μ = 7, the control step).
        physics_step_ms: MuJoCo's step, ms; it must divide the control step. None: the
            profile's (``default``: 2 ms, or the largest step below 2 ms that divides the
            control step, e.g. 25/13 ms at 25 ms).
        friction: robot-floor friction coefficient, > 0; None: the profile's.
        friction_scale: factor on the friction (batch's ``friction`` perturbation), > 0.

    Raises:
        MotionToolError: an unknown profile, a friction or scale that is not a positive
            number, or a physics step that is not positive or does not divide the control
            step (one line, naming the steps that do).
    """
    check_physics(
        profile=profile,
        physics_step_ms=physics_step_ms,
        friction=friction,
        friction_scale=friction_scale,
    )
    if control_step_ms < 1:
        raise MotionToolError(f"the control step must be >= 1 ms, got {control_step_ms}")
    substeps = _substeps(control_step_ms, profile, physics_step_ms)
    base = friction
    if base is None:
        base = WEBOTS_FRICTION if profile == "webots" else DEFAULT_FRICTION
    return Physics(
        profile=profile,
        timestep_ms=control_step_ms / substeps,
        friction=base * friction_scale,
        substeps=substeps,
        note=profile_note(
            profile,
            control_step_ms,
            substeps,
            friction=friction,
            friction_scale=friction_scale,
        ),
    )


def _substeps(control_step_ms: int, profile: str, physics_step_ms: float | None) -> int:
    """Physics steps per control step: the given physics step's (it must divide the control
    step), else the profile's (``webots``: 1; ``default``: steps of at most 2 ms)."""
    if physics_step_ms is None:
        if profile == "webots":
            return 1
        return substeps_at_most(control_step_ms, DEFAULT_PHYSICS_STEP_MS)
    divides = substeps_dividing(control_step_ms, physics_step_ms)
    if divides is None:
        raise MotionToolError(
            f"physics step {physics_step_ms:g} ms does not divide the control step of "
            f"{control_step_ms} ms; choose one that does, e.g. "
            f"{_divisors_ms(control_step_ms)} ms"
        )
    return divides


def profile_note(
    profile: str,
    control_step_ms: int,
    substeps: int,
    *,
    friction: float | None = None,
    friction_scale: float = 1.0,
) -> str | None:
    """The report's ``physics.profile_note``: what the profile means for the run that ran.

    ``webots`` with Webots' numbers (friction 7, one physics step per control step):
    :data:`WEBOTS_PROFILE_NOTE`. Where ``--friction``, ``--physics-step`` or a friction
    perturbation changed them, the note names what ran instead and does not repeat the claim
    about Webots' numbers (walks fall), which is about those numbers only. ``default``: None.

    Args:
        profile: ``default`` or ``webots``.
        control_step_ms: the control step, ms; substeps: physics steps per control step.
        friction: the ``--friction`` given (None: the profile's); friction_scale: the
            perturbation's factor on it.
    """
    if profile != "webots":
        return None
    ran = (WEBOTS_FRICTION if friction is None else friction) * friction_scale
    if ran == WEBOTS_FRICTION and substeps == 1:
        return WEBOTS_PROFILE_NOTE
    scaled = "" if friction_scale == 1.0 else f" x {friction_scale:g} by the friction perturbation"
    if ran == WEBOTS_FRICTION:
        parts = ["floor friction 7 (Webots')"]
    elif friction is None:
        parts = [f"floor friction {ran:g} (Webots' 7{scaled})"]
    else:
        parts = [f"floor friction {ran:g} ({friction:g} given{scaled}; Webots' is 7)"]
    step_ms = control_step_ms / substeps
    if substeps == 1:
        parts.append(f"physics step {step_ms:g} ms (= the control step, Webots')")
    else:
        parts.append(
            f"physics step {step_ms:g} ms (given; Webots' is the control step, "
            f"{control_step_ms} ms)"
        )
    return (
        f"profile webots, overridden: this run used {' and '.join(parts)}, so it is not a run "
        "with Webots' numbers; how friction and step change the walks: docs/play.md, Fidelity"
    )


def read_back(scene: Scene) -> tuple[float, float]:
    """(physics step in ms, floor friction coefficient) as the compiled MuJoCo model of
    ``scene`` has them: ``opt.timestep`` and the sliding friction of the ``floor`` geom (which
    wins over the robot's, having the higher priority)."""
    model = scene.model
    return float(model.opt.timestep) * MS_PER_S, float(model.geom("floor").friction[0])


def physics_run_options(
    profile: str = "default",
    physics_step_ms: float | None = None,
    friction: float | None = None,
    self_collision: bool | None = None,
) -> dict[str, Any]:
    """The physics options of a batch run (:class:`~motiontool.sim.batch.RunSpec` options, and
    so its cache key): only those that are given (the defaults leave the key as it was);
    ``self_collision``: ``--[no-]self-collision``.

    Raises:
        MotionToolError: a value :func:`check_physics` refuses.
    """
    check_physics(profile=profile, physics_step_ms=physics_step_ms, friction=friction)
    out: dict[str, Any] = {}
    if profile != "default":
        out["profile"] = profile
    if physics_step_ms is not None:
        out["physics_step_ms"] = float(physics_step_ms)
    if friction is not None:
        out["floor_friction"] = float(friction)
    if self_collision is not None:
        out["self_collision"] = bool(self_collision)
    return out
