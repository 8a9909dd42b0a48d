"""The Python that Choregraphe exports a timeline as, both ways::

    names = list()
    times = list()
    keys = list()

    names.append("HeadYaw")
    times.append([0.52, 1.04])
    keys.append([[0.1, [3, -0.17, 0], [3, 0.17, 0]], [0.2, [3, -0.17, 0], [3, 0, 0]]])

    motion.angleInterpolationBezier(names, times, keys)

Read: the arguments of every ``names.append``, ``times.append`` and ``keys.append`` (``self.``
before them too), paired in their order, each a literal that :func:`ast.literal_eval` reads
alone. Nothing else of the file is evaluated, imported or run, and the file need not be
Python 3 (Choregraphe's own exports are Python 2: ``except BaseException, err``). A key is
``[angle, [type, dTime, dAngle], [type, dTime, dAngle]]`` (times s, angles rad), or a plain
angle, as Choregraphe's simplified export for ``angleInterpolation(names, keys, times, True)``
writes it; a plain angle gets Choregraphe's automatic handles (:mod:`.choregraphe`).

Written: the keys of the NAOqi export (:func:`~.naoqi.bezier_curves`: the corners of Webots'
command stream at the control step, times with the lead-in), in the form above, floats as
Python writes them (read back, the same doubles).
"""

from __future__ import annotations

import ast
import io
import json
import math
import tokenize
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from motiontool.errors import MotionSyntaxError, MotionToolError
from motiontool.motionfmt.convert.base import (
    Exported,
    ExportOptions,
    Imported,
    ImportOptions,
    robot_check,
)
from motiontool.motionfmt.convert.choregraphe import (
    Curve,
    auto_handles,
    bezier_handle,
    curves_motion,
    refuse_handles,
)
from motiontool.motionfmt.convert.naoqi import bezier_curves

if TYPE_CHECKING:
    from motiontool.motionfmt.convert.naoqi_curve import Key
    from motiontool.motionfmt.motion import Motion

__all__ = ["read_choregraphe_py", "write_choregraphe_py"]

_LISTS = ("names", "times", "keys")
_KEY_SHAPE = "an angle, or [angle, [type, dTime, dAngle], [type, dTime, dAngle]]"


@dataclass(frozen=True)
class _Append:
    """One ``X.append(value)``: which list, its value, and where the value starts."""

    list_name: str
    value: Any
    line: int
    column: int


def _literal(text: str, path: str, line: int, column: int) -> Any:
    """The literal ``text`` (the argument of an append at ``line``:``column``, 1-based)."""
    try:
        node = ast.parse("(" + text + "\n)", mode="eval")
    except SyntaxError as e:
        at_line = line + (e.lineno or 1) - 1
        at_col = column + (e.offset or 2) - 2 if (e.lineno or 1) == 1 else (e.offset or 1)
        raise MotionSyntaxError(f"Python syntax: {e.msg}", path, at_line, at_col) from None
    try:
        return ast.literal_eval(node)
    except (ValueError, TypeError, SyntaxError, MemoryError, RecursionError):
        raise MotionSyntaxError(
            "expected a literal (numbers, strings, lists), got an expression", path, line, column
        ) from None


def _appends(text: str, path: str) -> tuple[list[_Append], set[str]]:
    """Every ``names/times/keys.append(...)`` of the source, and the NAOqi calls it names."""
    lines = text.splitlines(keepends=True)
    calls: set[str] = set()
    found: list[_Append] = []
    recent: list[tokenize.TokenInfo] = []
    depth, opened = 0, None
    try:
        for tok in tokenize.generate_tokens(io.StringIO(text).readline):
            if tok.type in (tokenize.NL, tokenize.COMMENT, tokenize.INDENT, tokenize.DEDENT):
                continue
            if tok.type == tokenize.NAME and tok.string.startswith("angleInterpolation"):
                calls.add(tok.string)
            if opened is not None:
                depth += {"(": 1, "[": 1, "{": 1, ")": -1, "]": -1, "}": -1}.get(tok.string, 0)
                if depth == 0:
                    name, start = opened
                    arg = _slice(lines, start, tok.start)
                    value = _literal(arg, path, start[0], start[1] + 1)
                    found.append(_Append(name, value, start[0], start[1] + 1))
                    opened = None
                continue
            recent = [*recent[-3:], tok]
            words = [t.string for t in recent]
            if words[-4:-1] in ([n, ".", "append"] for n in _LISTS) and words[-1] == "(":
                opened, depth = (words[-4], tok.end), 1
    except tokenize.TokenError as e:
        if opened is not None:  # the file ends inside an append: point at it
            line, column = opened[1]
            message = f"Python syntax: {opened[0]}.append( is never closed"
            raise MotionSyntaxError(message, path, line, column) from None
        line, column = e.args[1]
        raise MotionSyntaxError(f"Python syntax: {e.args[0]}", path, line, column + 1) from None
    except SyntaxError as e:
        message = f"Python syntax: {e.msg}"
        raise MotionSyntaxError(message, path, e.lineno or 1, e.offset or 1) from None
    return found, calls


def _slice(lines: list[str], start: tuple[int, int], end: tuple[int, int]) -> str:
    """The source from ``start`` to ``end`` ((row 1-based, column 0-based), end excluded)."""
    if start[0] == end[0]:
        return lines[start[0] - 1][start[1] : end[1]]
    middle = lines[start[0] : end[0] - 1]
    return lines[start[0] - 1][start[1] :] + "".join(middle) + lines[end[0] - 1][: end[1]]


def _number(x: Any) -> bool:
    return isinstance(x, int | float) and not isinstance(x, bool) and math.isfinite(x)


def _times(a: _Append, name: str, path: str) -> list[float]:
    t = a.value
    if not isinstance(t, list | tuple) or not t or not all(_number(x) for x in t):
        raise MotionSyntaxError(
            f"times of {name}: expected a list of key times (s), got {t!r:.60}",
            path,
            a.line,
            a.column,
        )
    if any(t[i + 1] <= t[i] for i in range(len(t) - 1)) or t[0] < 0:
        raise MotionSyntaxError(
            f"times of {name}: {list(t)!r:.60}: key times must be >= 0 s and increase",
            path,
            a.line,
            a.column,
        )
    return [float(x) for x in t]


def _handle(h: Any) -> bool:
    return isinstance(h, list | tuple) and len(h) == 3 and all(_number(x) for x in h)


def _curve(name: _Append, times: _Append, keys: _Append, path: str) -> tuple[Curve, bool]:
    """The curve of one joint's appends, and whether a key of it was a plain angle."""
    if not isinstance(name.value, str) or not name.value:
        raise MotionSyntaxError(
            f"expected a joint's name, got {name.value!r:.60}", path, name.line, name.column
        )
    t = _times(times, name.value, path)
    raw = keys.value
    if not isinstance(raw, list | tuple) or len(raw) != len(t):
        count = len(raw) if isinstance(raw, list | tuple) else "no list"
        raise MotionSyntaxError(
            f"keys of {name.value}: {count} keys for its {len(t)} times (line {times.line})",
            path,
            keys.line,
            keys.column,
        )
    angles: list[float] = []
    for i, k in enumerate(raw):
        full = isinstance(k, list | tuple) and len(k) == 3 and _number(k[0])
        if not (_number(k) or (full and _handle(k[1]) and _handle(k[2]))):
            raise MotionSyntaxError(
                f"keys of {name.value}: key {i + 1} is {k!r:.60}: expected {_KEY_SHAPE}",
                path,
                keys.line,
                keys.column,
            )
        angles.append(float(k if _number(k) else k[0]))
    built: list[Key] = []
    for i, k in enumerate(raw):
        if _number(k):
            before, after = auto_handles(t, angles, i)
            built.append((angles[i], bezier_handle(*before), bezier_handle(*after)))
        else:
            h1, h2 = (bezier_handle(float(h[1]), float(h[2])) for h in (k[1], k[2]))
            built.append((angles[i], h1, h2))
    curve = Curve(name.value, tuple(t), tuple(built), (False,) * (len(t) - 1), name.line)
    refuse_handles(curve, f"{path}:{keys.line}")
    return curve, any(_number(k) for k in raw)


def read_choregraphe_py(data: bytes, path: str, options: ImportOptions | None = None) -> Imported:
    """The motion of a Choregraphe Python export (see the module).

    Raises:
        MotionSyntaxError: Python the tokenizer or a literal's parser refuses, or an append of
            the wrong shape (its position).
        MotionToolError: no appends, appends that do not pair, a joint appended twice.
    """
    text = data.decode("utf-8", "replace")
    appends, calls = _appends(text, path)
    by_list = {n: [a for a in appends if a.list_name == n] for n in _LISTS}
    if not appends:
        raise MotionToolError(f"'{path}': no names.append, times.append or keys.append to read")
    counts = {n: len(v) for n, v in by_list.items()}
    if len(set(counts.values())) != 1:
        short = min(counts, key=lambda n: counts[n])
        extra = by_list[max(counts, key=lambda n: counts[n])][counts[short]]
        raise MotionSyntaxError(
            f"{extra.list_name}.append without its {short}.append "
            f"({', '.join(f'{n}: {c}' for n, c in counts.items())})",
            path,
            extra.line,
            extra.column,
        )
    curves: list[Curve] = []
    plain, seen = False, dict[str, int]()
    for name, times, keys in zip(*by_list.values(), strict=True):
        curve, had_plain = _curve(name, times, keys, path)
        if curve.name in seen:
            raise MotionSyntaxError(
                f"{curve.name} appended twice (first at line {seen[curve.name]}); motiontool "
                "reads a file with one motion",
                path,
                name.line,
                name.column,
            )
        seen[curve.name] = name.line
        curves.append(curve)
        plain = plain or had_plain
    call = " and ".join(sorted(calls)) or "no angleInterpolation"
    notes = ["plain angles: Choregraphe's automatic Bézier handles"] if plain else []
    what = f"a Choregraphe Python export calling {call}"
    return curves_motion(curves, path, options or ImportOptions(), what, notes)


def write_choregraphe_py(motion: Motion, options: ExportOptions) -> Exported:
    """The Python of ``angleInterpolationBezier``'s arguments (see the module)."""
    curves = bezier_curves(motion, options)
    head = [
        "# Choregraphe bezier export in Python.",
        f"# Written by motiontool convert from {options.source!r}, robot check: "
        f"{robot_check(options)}.",
        f"# Times: Webots' playback time + {options.lead_in_ms} ms lead-in (s); angles: rad "
        "(LHand, RHand: 0 closed to 1 open).",
        f"# Worst deviation from Webots' command stream: {curves.deviation.max_rad!r} rad.",
        "names = list()",
        "times = list()",
        "keys = list()",
        "",
    ]
    body = []
    for name, t, keys in zip(curves.names, curves.times, curves.keys, strict=True):
        listed = ", ".join(f"[{a!r}, {list(h1)!r}, {list(h2)!r}]" for a, h1, h2 in keys)
        body += [
            f"names.append({json.dumps(name)})",
            f"times.append({[float(x) for x in t]!r})",
            f"keys.append([{listed}])",
            "",
        ]
    tail = [
        "try:",
        "    # Inside Choregraphe ALProxy is defined; elsewhere: from naoqi import ALProxy, and",
        '    # motion = ALProxy("ALMotion", IP, 9559)',
        '    motion = ALProxy("ALMotion")  # noqa: F821',
        "    motion.angleInterpolationBezier(names, times, keys)",
        "except BaseException as err:",
        "    print(err)",
    ]
    data = "\n".join([*head, *body, *tail, ""]).encode("utf-8", "surrogateescape")
    detail = (
        f"{curves.n_keys} keys of {len(curves.names)} NAOqi joints for "
        f"angleInterpolationBezier in Python, times + {options.lead_in_ms} ms lead-in"
    )
    return Exported(data, curves.n_keys, detail, curves.deviation, stream=curves.stream)
