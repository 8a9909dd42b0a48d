"""The MT2xx codes explained: files Webots accepts but reads or plays otherwise than they seem
to say (docs/webots-format.md)."""

from __future__ import annotations

from motiontool.cli.rule_model import Example, Rule

__all__ = ["TRAP_RULES"]

H = b"#WEBOTS_MOTION,V1.0,HeadYaw\n"
H2 = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n"
P0 = b"00:00:000,P1,0\n"
P0_2 = b"00:00:000,P1,0,0\n"

TRAP_RULES = (
    Rule(
        "MT201",
        "A line with no cell (empty, or only '\\r') ends the motion without an error: every "
        "later line, poses included, is ignored.",
        Example(H + P0 + b"\n00:00:500,P2,0.5\n"),
        "remove the blank line (or the poses after it, if the motion is meant to end there)",
        H + P0 + b"00:00:500,P2,0.5\n",
        row="a blank line silently ends the motion: everything after it is ignored",
    ),
    Rule(
        "MT202",
        "strtok never returns an empty cell: ',,' is one separator, so every later value "
        "shifts one joint to the left (and the line usually has too few values).",
        Example(
            b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch,LShoulderPitch\n"
            b"00:00:000,P1,0,0,0\n00:00:500,P2,0.1,,0.5\n"
        ),
        "write '*' in the empty cell: ',*,' (no command for that joint)",
        b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch,LShoulderPitch\n"
        b"00:00:000,P1,0,0,0\n00:00:500,P2,0.1,*,0.5\n",
        row="`,,`: Webots skips the empty cell and every later value shifts one joint left",
    ),
    Rule(
        "MT203",
        "sscanf reads the longest number at the start of the cell and ignores the rest: '2rad' "
        "is 2, '1.5.3' is 1.5; degrees are not converted.",
        Example(H + P0 + b"00:00:500,P2,0.5rad\n"),
        "write the number alone, in radians (metres for a linear joint)",
        H + P0 + b"00:00:500,P2,0.5\n",
        row="trailing garbage after a number (`2rad` reads as 2.0, `1.5.3` as 1.5)",
    ),
    Rule(
        "MT204",
        "-9999999.9 is Webots' internal 'no value': a cell that reads as that number is '*', "
        "no command.",
        Example(H2 + P0_2 + b"00:00:500,P2,0.5,-9999999.9\n"),
        "write '*' if no command is meant, else the position",
        H2 + P0_2 + b"00:00:500,P2,0.5,*\n",
        row='the number −9999999.9, Webots\' internal "no value": the cell reads as `*`',
    ),
    Rule(
        "MT205",
        "Two columns of one name both drive that motor, left to right: the later column's "
        "command wins where it sends one, the earlier's where the later is '*'.",
        Example(b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadYaw\n00:00:000,P1,0,0\n00:00:500,P2,0.5,0.5\n"),
        "keep one column per joint (or rename the one meant for another joint)",
        H + P0 + b"00:00:500,P2,0.5\n",
        row="a joint named twice: the later column wins",
    ),
    Rule(
        "MT206",
        "Before the first pose's time Webots already commands the first pose: the robot jumps "
        "to it at 0 ms instead of moving there.",
        Example(H + b"00:00:500,P1,0.5\n00:01:000,P2,0\n"),
        "start the motion at 0 ms (a first pose from where the robot stands)",
        H + b"00:00:000,P0,0\n00:00:500,P1,0.5\n00:01:000,P2,0\n",
        row="first pose at t > 0: the robot jumps to it at t = 0",
    ),
    Rule(
        "MT207",
        "'*' does not interpolate: over a segment with '*' at either end the joint gets no "
        "command and holds its last target, then jumps.",
        Example(H2 + P0_2 + b"00:00:500,P2,*,0.2\n00:01:000,P3,0.5,0.4\n"),
        "write the values the joint should pass through instead of '*'",
        H2 + P0_2 + b"00:00:500,P2,0.25,0.2\n00:01:000,P3,0.5,0.4\n",
        row=(
            "`*` leaves a joint uncommanded over whole segments (it holds its previous target; "
            "`*` does not interpolate)"
        ),
    ),
    Rule(
        "MT208",
        "Webots compares joint names byte for byte; bytes that are not UTF-8 (a file saved in "
        "Latin-1) rarely match a motor name and show up garbled in tools.",
        Example(H + b"00:00:000,Pos\xe9,0\n"),
        "save the file as UTF-8 (or ASCII)",
        H + b"00:00:000,Pose,0\n",
        row="bytes that are not UTF-8",
    ),
    Rule(
        "MT209",
        "The controller steps every time step (20 ms for the Nao): a pose between two steps is "
        "never commanded exactly, the step after it interpolates past it.",
        Example(
            H + P0 + b"00:00:050,P2,0.2\n00:01:000,P3,0\n",
            args=("--robot", "none", "--timestep", "20"),
        ),
        "put pose times on multiples of the time step",
        H + P0 + b"00:00:060,P2,0.2\n00:01:000,P3,0\n",
        row=(
            "at `--timestep` (else the robot's step: Nao 20 ms, UR5e 8 ms): a pose time the "
            "controller never reaches exactly"
        ),
    ),
    Rule(
        "MT210",
        "Spaces around a joint name are part of it: ' HeadYaw' is not the motor 'HeadYaw', and "
        "Webots ignores the column.",
        Example(b"#WEBOTS_MOTION,V1.0, HeadYaw\n" + P0),
        "remove the spaces around the name",
        H + P0,
        row="a joint name with leading or trailing white space",
    ),
    Rule(
        "MT211",
        "A joint that is '*' in every pose is never commanded: the column does nothing.",
        Example(H2 + b"00:00:000,P1,0,*\n00:00:500,P2,0.5,*\n"),
        "remove the column, or give the joint values",
        H + P0 + b"00:00:500,P2,0.5\n",
        row="a joint that is `*` in every pose",
    ),
)
