"""Random edits of a motion, as a person types them in an editor: for the tests that read or
lint each version from the last one (``motiontool server``) against a full read."""

from __future__ import annotations

import math
import random

__all__ = ["edit", "motion"]


def motion(joints: list[str], poses: int, rng: random.Random, stars: float = 0.02) -> list[bytes]:
    """The lines of a motion of ``poses`` poses, 40 ms apart, a share ``stars`` of its cells
    '*'."""
    lines = [b"#WEBOTS_MOTION,V1.0," + ",".join(joints).encode()]
    for p in range(poses):
        cells = [b"*" if rng.random() < stars else _number(rng) for _ in joints]
        lines.append(b",".join([str(40 * (p + 1)).encode(), f"Pose{p}".encode(), *cells]))
    return lines


def _time(lines: list[bytes], at: int, rng: random.Random, wild: float = 0.2) -> bytes:
    """A time for a pose at line ``at``: just after the line before's, but for a share
    ``wild`` of them."""
    before = lines[at - 1].split(b",")[0] if at > 1 else b"0"
    after = lines[at + 1].split(b",")[0] if at + 1 < len(lines) else b""
    if rng.random() < wild or not before.isdigit():
        return str(rng.randrange(0, 40 * len(lines))).encode()
    if after.isdigit() and int(after) - int(before) > 1:  # between the two
        return str(rng.randrange(int(before) + 1, int(after))).encode()
    return str(int(before) + rng.randrange(1, 20)).encode()


def _valid(lines: list[bytes], at: int) -> bool:
    """Whether line ``at`` is a pose line that Webots reads, after the line before it."""
    cells = lines[at].split(b",")
    if len(cells) != lines[0].count(b",") + 1:
        return False
    before = lines[at - 1].split(b",")[0] if at > 1 else b"-1"
    try:
        later = int(cells[0]) > int(before)
        return later and all(c == b"*" or math.isfinite(float(c)) for c in cells[2:])
    except ValueError:
        return False


def _number(rng: random.Random) -> bytes:
    return repr(round(rng.uniform(-2.5, 2.5), 4)).encode()


def edit(lines: list[bytes], rng: random.Random) -> list[bytes]:
    """``lines`` with one random edit: a value, a time, a pose line inserted or removed, a blank
    line, the header, a cell made unreadable (or a line cut short), a '*', a NaN, the end."""
    lines = list(lines)
    broken = [i for i in range(1, len(lines)) if not _valid(lines, i)]
    if broken and rng.random() < 0.5:  # made valid again: a blank line first
        at = next((i for i in broken if not lines[i]), broken[0])
        if not lines[at]:
            del lines[at]
        else:
            time = _time(lines, at, rng, 0.0)
            width = lines[0].count(b",") - 1
            lines[at] = b",".join([time, b"Fixed", *[_number(rng) for _ in range(width)]])
        return lines
    kind = rng.randrange(11)
    at = rng.randrange(1, len(lines)) if len(lines) > 1 else 1
    cells = lines[at].split(b",") if at < len(lines) else []
    if kind <= 2 and len(cells) > 2:  # a value, most often
        cells[rng.randrange(2, len(cells))] = _number(rng)
    elif kind == 3 and cells:  # a time: may now come before the previous one
        cells[0] = _time(lines, at, rng)
    elif kind == 4:
        new = lines[min(at, len(lines) - 1)].split(b",")
        new[0] = _time(lines, at, rng)
        lines.insert(at, b",".join(new))
    elif kind == 5 and len(lines) > 2:
        del lines[at]
    elif kind == 6:
        lines.insert(at, b"")
    elif kind == 7:  # the header: a joint renamed, and back
        lines[0] = lines[0].replace(b"HeadYaw", b"HeadYw", 1) or lines[0]
        if b"HeadYaw" not in lines[0]:
            lines[0] = lines[0].replace(b"HeadYw", b"HeadYaw")
    elif kind == 8 and len(cells) > 2:  # unreadable, or one cell short
        if rng.random() < 0.5:
            cells[rng.randrange(2, len(cells))] = rng.choice([b"abc", b"1rad", b" ", b"-9999999.9"])
        else:
            cells.pop()
    elif kind == 9 and len(cells) > 2:
        cells[rng.randrange(2, len(cells))] = rng.choice([b"*", b"nan", b"inf"])
    elif kind == 10:
        width = lines[0].count(b",") - 1
        lines.append(b",".join([str(40 * len(lines) + 40).encode(), b"End", *[b"0"] * width]))
    if cells and kind not in (4, 5, 6, 7, 10):
        lines[at] = b",".join(cells)
    return lines
