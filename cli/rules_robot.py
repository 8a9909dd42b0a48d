"""The MT3xx codes (robot checks) and the MT9xx notes explained (docs/webots-format.md,
*Playing*; docs/simulation.md)."""

from __future__ import annotations

from motiontool.cli.rule_model import Example, Rule

__all__ = ["ROBOT_RULES"]

NAO = ("--robot", "nao", "--checks", "limits,velocity")
NAO_V5 = ("--robot", "nao-v5", "--checks", "limits")
RSR = b"#WEBOTS_MOTION,V1.0,RShoulderRoll\n00:00:000,P1,0\n"
ARM = b"#WEBOTS_MOTION,V1.0,RShoulderPitch,RShoulderRoll,RElbowRoll\n00:00:000,P1,0,0,0\n"
LEGS = (
    b"#WEBOTS_MOTION,V1.0,LHipPitch,RHipPitch,LKneePitch,RKneePitch,LAnklePitch,RAnklePitch\n"
    b"00:00:000,P1,0,0,0,0,0,0\n"
)
RIGHT = (
    b"#WEBOTS_MOTION,V1.0,RShoulderPitch,RShoulderRoll\n"
    b"00:00:000,P1,0,0\n00:01:000,P2,-1,-0.3\n00:02:000,P3,0,0\n"
)
LEFT = RIGHT.replace(b"RShoulder", b"LShoulder")
LEFT_MIRRORED = LEFT.replace(b"-1,-0.3", b"-1,0.3")

ROBOT_RULES = (
    Rule(
        "MT301",
        "Webots looks each column up among the robot's motors; a name that is not one is "
        "ignored (with a warning in the console) and the joint is not moved.",
        Example(b"#WEBOTS_MOTION,V1.0,HeadYaw,HedPitch\n00:00:000,P1,0,0\n", args=NAO),
        "spell the motor as the robot names it (the hint gives the closest name)",
        b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n00:00:000,P1,0,0\n",
        row=(
            "a joint that is not a motor of the robot (Webots ignores the column), with a "
            "did-you-mean"
        ),
    ),
    Rule(
        "MT302",
        "Webots clamps a target outside [minPosition, maxPosition] to the range, and warns at "
        "every step: the joint stops at its limit, not where the file says.",
        Example(RSR + b"00:01:000,P2,0.5\n", args=NAO),
        "keep the value within the joint's limits (motiontool robots show ROBOT lists them; "
        "'validate --fix --unsafe-fixes' clamps it to the limit, where the motor stops anyway)",
        RSR + b"00:01:000,P2,0.3\n",
        row=(
            "a position outside the joint's limits (Webots clamps it): value, bound and excess "
            "in the joint's unit"
        ),
    ),
    Rule(
        "MT303",
        "The motor's speed is capped at maxVelocity: a keyframe segment that asks for more is "
        "played slower, and the joint arrives late.",
        Example(RSR + b"00:00:100,P2,-1.2\n", args=NAO),
        "give the move more time ('motiontool retime --fit-limits', or 'validate --fix "
        "--unsafe-fixes', stretches every segment that is too fast)",
        RSR + b"00:00:200,P2,-1.2\n",
        row="a keyframe segment faster than maxVelocity: how many ms the motor falls behind",
    ),
    Rule(
        "MT304",
        "What the controller sends at each time step moves faster than maxVelocity: after a "
        "'*' stretch the target jumps at once from the held value to the next one.",
        Example(b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n500,B,*\n1000,C,1\n2000,D,1.4\n", args=NAO),
        "write values instead of '*' so that the joint moves there gradually",
        b"#WEBOTS_MOTION,V1.0,HeadYaw\n0,A,0\n500,B,0.5\n1000,C,1\n2000,D,1.4\n",
        row=(
            "the command stream at the controller time step is faster than maxVelocity (e.g. a "
            "jump after `*`)"
        ),
    ),
    Rule(
        "MT305",
        "Webots' Nao lets HeadPitch use its whole range at any HeadYaw; the real NAO's head "
        "pitches less the more it turns (its shell hits the shoulders). Checked with --robot "
        "nao-v5.",
        Example(b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n0,P1,1.5,0.4\n", args=NAO_V5),
        "pitch the head less at that yaw (the hint gives the range)",
        b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n0,P1,1.5,0.2\n",
        row=(
            "`nao-v5` only: the real robot's HeadYaw-dependent HeadPitch range; LHipYawPitch = "
            "RHipYawPitch (one motor)"
        ),
    ),
    Rule(
        "MT306",
        "Webots' Nao has a motor per joint; on the real NAO one motor drives LHipYawPitch and "
        "RHipYawPitch, and one the fingers of a hand. Checked with --robot nao-v5.",
        Example(b"#WEBOTS_MOTION,V1.0,LHipYawPitch,RHipYawPitch\n0,P1,-0.4,-0.5\n", args=NAO_V5),
        "write the same value in the columns one motor drives",
        b"#WEBOTS_MOTION,V1.0,LHipYawPitch,RHipYawPitch\n0,P1,-0.4,-0.4\n",
    ),
    Rule(
        "MT307",
        "A simulator with self-collision off lets the bodies pass through each other; the real "
        "robot hits itself. Checked at every keyframe and segment midpoint (Pinocchio).",
        Example(
            ARM + b"00:01:000,P2,1.4,0.3,1.5\n00:02:000,P3,0,0,0\n",
            args=("--robot", "nao", "--checks", "collision"),
        ),
        "move the limbs apart in that pose (here: the forearm folded into the belly)",
        ARM + b"00:01:000,P2,1.4,0.3,0.5\n00:02:000,P3,0,0,0\n",
        row=(
            "self-collision at a keyframe or segment midpoint (Pinocchio + coal on the model's "
            "collision shapes; overlaps under 15 mm ignored, `--collision-tolerance`)"
        ),
    ),
    Rule(
        "MT308",
        "Held still in that pose the robot tips over: its centre of mass is outside the "
        "polygon of its feet (a static estimate; opt-in with --checks balance).",
        Example(
            LEGS + b"00:01:000,P2,-0.5,-0.5,0,0,0,0\n",
            args=("--robot", "nao", "--checks", "balance"),
        ),
        "keep the centre of mass over the feet (here: bend the knees and ankles with the hips, "
        "a squat)",
        LEGS + b"00:01:000,P2,-0.5,-0.5,1,1,-0.5,-0.5\n",
        row="opt-in static balance: the centre of mass leaves the support polygon (margin in mm)",
    ),
    Rule(
        "MT309",
        "It plays what the file says: a left-arm file copied from a right-arm one without "
        "negating the roll and yaw joints moves the left arm the wrong way.",
        Example(
            LEFT,
            name="WaveLeft.motion",
            args=("--robot", "nao", "--checks", "limits"),
            siblings=(("WaveRight.motion", RIGHT),),
        ),
        "write the true mirror: 'motiontool mirror WaveRight.motion -o WaveLeft.motion'",
        LEFT_MIRRORED,
        row=(
            "a `*Left*`/`*Right*` file equals its sibling in the same folder (the other side, or "
            "no side: `HandWaveLeft` beside `HandWave`) with the L/R columns swapped but some "
            "roll/yaw joint not negated: an unmirrored copy"
        ),
    ),
    Rule(
        "MT901",
        "It checks nothing against a robot before it plays; validate needs to know the robot: "
        "with --robot auto, no built-in robot has half of the file's joints or more (or two "
        "tie), so the robot checks were skipped.",
        Example(b"#WEBOTS_MOTION,V1.0,Hip,Knee\n00:00:000,P1,0,0\n", args=("--robot", "auto")),
        "name the robot with --robot (a built-in one, a .urdf or .xml model, erd:NAME)",
        row=(
            "robot checks skipped: no built-in robot has half of the file's joints or more, or "
            "two tie (name one with `--robot`)"
        ),
    ),
    Rule(
        "MT902",
        "Nothing is wrong in the file: a default check of validate (collision, balance) needs "
        "a library that is not installed, so it was skipped; the other checks still ran.",
        Example(
            b"#WEBOTS_MOTION,V1.0,HeadYaw\n00:00:000,P1,0\n",
            args=("--robot", "nao"),
            missing=("pinocchio",),
        ),
        "pip install 'motiontool[kinematics]' (or leave the check out with --checks)",
        row=(
            "a check skipped because a library it needs is not installed (collision and balance "
            "without Pinocchio: `pip install 'motiontool[kinematics]'`), once a run; the other "
            "checks still run"
        ),
    ),
)
