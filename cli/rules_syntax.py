"""The MT1xx codes explained: what makes Webots reject a file, or read it otherwise than it is
written (docs/webots-format.md, *Reading*)."""

from __future__ import annotations

from motiontool.cli.rule_model import Example, Rule

__all__ = ["SYNTAX_RULES"]

H = b"#WEBOTS_MOTION,V1.0,HeadYaw\n"
H2 = b"#WEBOTS_MOTION,V1.0,HeadYaw,HeadPitch\n"
P0 = b"00:00:000,P1,0\n"

SYNTAX_RULES = (
    Rule(
        "MT100",
        "wbu_motion_new returns NULL: the controller gets no motion at all.",
        Example(b""),
        "write the header and at least one pose",
        H + P0,
        row=(
            "what makes Webots reject the file: empty file, header (`#WEBOTS_MOTION`, `V1.0`, a "
            "BOM, lower case), no joint, no pose, invalid time (spaces, signs, dots, a third "
            'colon, a `#` "comment", a line of spaces), times not strictly increasing, missing '
            "pose name, a value that is not a number or `*` (`' * '`, `abc`, `infinit`), too few "
            "/ too many values (with a decimal-comma hint)"
        ),
    ),
    Rule(
        "MT101",
        "The first cell must be exactly '#WEBOTS_MOTION' (case, spaces and a byte-order mark "
        "count); otherwise Webots rejects the file. Cells are separated by commas only: a "
        "header separated by '%', ';', tabs or spaces is one cell (the hint names the "
        "separator).",
        Example(b"#webots_motion,V1.0,HeadYaw\n" + P0),
        "write '#WEBOTS_MOTION' in capitals, first on line 1",
        H + P0,
    ),
    Rule(
        "MT102",
        "The second header cell must be 'V1.0', the only version there is; otherwise Webots "
        "rejects the file.",
        Example(b"#WEBOTS_MOTION,V1.1,HeadYaw\n" + P0),
        "write 'V1.0'",
        H + P0,
    ),
    Rule(
        "MT103",
        "After reading every pose Webots checks that the header named a joint; with none it "
        "rejects the file. Joint names on a line of their own below the header are read as a "
        "pose line, whose time is not a time: Webots stops there, and motiontool says so once "
        "(the 'expected 0 values' on every later line follow from it and are only counted).",
        Example(b"#WEBOTS_MOTION,V1.0\nHeadYaw\n00:00:000,P1,0\n"),
        "name the joints (motors) on the header line, after 'V1.0', one column each, and give "
        "every pose a value for each",
        H + P0,
    ),
    Rule(
        "MT104",
        "A file whose header is not followed by a pose (or whose first pose line is blank) is "
        "rejected.",
        Example(H),
        "add a pose line: time, name, one value per joint",
        H + P0,
    ),
    Rule(
        "MT105",
        "A time is ms, s:ms or m:s:ms, digits only; a space, a sign, a dot, a third colon or a "
        "'#' comment line is an invalid time and Webots rejects the file (there are no "
        "comments).",
        Example(H + P0 + b"# raise the head\n00:00:500,P2,0.5\n"),
        "remove the comment line, or write the time with digits and colons only",
        H + P0 + b"00:00:500,P2,0.5\n",
    ),
    Rule(
        "MT106",
        "Pose times must strictly increase: an equal or earlier time makes Webots reject the file.",
        Example(H + P0 + b"00:00:500,P2,0.5\n00:00:400,P3,0\n"),
        "give each pose a later time than the one before",
        H + P0 + b"00:00:500,P2,0.5\n00:00:600,P3,0\n",
    ),
    Rule(
        "MT107",
        "A pose line needs a name after its time; a line with only a time is rejected.",
        Example(H + b"00:00:000\n"),
        "write the pose name, then the values",
        H + P0,
    ),
    Rule(
        "MT108",
        "A value is read with sscanf(\"%lf\") or is exactly '*'; a cell where no number starts "
        "('abc', ' * ', 'infinit') makes Webots reject the file.",
        Example(H + P0 + b"00:00:500,P2,abc\n"),
        "write a number, or '*' (no command) without spaces",
        H + P0 + b"00:00:500,P2,0.5\n",
    ),
    Rule(
        "MT109",
        "Every pose needs one value per joint of the header; fewer makes Webots reject the file.",
        Example(H2 + P0),
        "write one value per joint ('*' for no command)",
        H2 + b"00:00:000,P1,0,*\n",
    ),
    Rule(
        "MT110",
        "More values than joints makes Webots reject the file; a decimal comma ('0,5' for 0.5) "
        "is the usual cause.",
        Example(H + P0 + b"00:00:500,P2,0,5\n"),
        "write decimals with a point; one value per joint",
        H + P0 + b"00:00:500,P2,0.5\n",
    ),
    Rule(
        "MT111",
        "Webots reads lines with fgets into a 4096-byte buffer: a line of 4095 bytes or more "
        "comes back in pieces, and each later piece is read as a line of its own.",
        Example(H + b"00:00:000,P1," + b"0" * 4100 + b"\n"),
        "keep every line under 4095 bytes (fewer joints per file, shorter numbers)",
        H + P0,
        row=(
            "a line of 4095 bytes or more: Webots' `fgets` cuts it and reads the rest as a new line"
        ),
    ),
    Rule(
        "MT112",
        "Times are summed in a C int of milliseconds, which wraps past 2147483647 ms (24.8 "
        "days): 4294967396 reads as 100 ms. Webots rejects the file where the wrapped time is "
        "invalid, and plays the wrapped time otherwise.",
        Example(H + P0 + b"4294967396,P2,0.5\n"),
        "write times under 2147483647 ms",
        H + P0 + b"00:00:100,P2,0.5\n",
        row="a pose time past 2³¹−1 ms: Webots' `int` wraps",
    ),
    Rule(
        "MT113",
        "'nan' and 'inf' (and numbers too large for a double) are read, and Webots sends them "
        "to the motor as its target.",
        Example(H + P0 + b"00:00:500,P2,nan\n"),
        "write a finite number, or '*' for no command",
        H + P0 + b"00:00:500,P2,0.5\n",
        row="`nan` / `inf`: Webots sends it to the motor",
    ),
    Rule(
        "MT114",
        "A NUL byte ends the C string: Webots does not see the rest of the line.",
        Example(H + P0 + b"00:00:500,P2,0.5\x00 head up\n"),
        "remove the NUL byte (and what follows it, which Webots never read)",
        H + P0 + b"00:00:500,P2,0.5\n",
        row="a NUL byte: the rest of the line is lost",
    ),
    Rule(
        "MT115",
        "The playback time is a C int of ms too: at this controller time step it passes "
        "2147483647 before the last pose, wraps negative, and Webots sends the first pose "
        "again; the motion may never end.",
        Example(
            H + P0 + b"2147483647,P2,1\n", args=("--robot", "none", "--timestep", "1000000000")
        ),
        "end the motion well before 2147483647 ms (24.8 days), or use a smaller time step",
        H + P0 + b"00:01:000,P2,1\n",
        row=(
            "at the `--timestep` given (else the robot's step), the playback time (a C `int` of "
            "ms) passes 2³¹−1 before the motion ends: it wraps negative, Webots sends the first "
            "pose again and the motion may never end"
        ),
    ),
)
