"""PNG plots of motions (``plot``, ``diff --plot``): the only module that imports matplotlib.

matplotlib is imported inside the functions, so ``motiontool --help`` never loads it. Figures
are drawn on an explicit :class:`matplotlib.figure.Figure` with the Agg canvas (no pyplot, no
display, no global figure state), in matplotlib's default style whatever the user's matplotlibrc
says, and saved without a timestamp: the same input gives the same bytes with the same library
versions.
"""

from __future__ import annotations

import functools
import io
import math
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ParamSpec, TypeVar

from motiontool.extras import require
from motiontool.kinematics.robot_spec import fmt_name
from motiontool.motionfmt.units import MS_PER_S

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

    from motiontool.cli._held_lines import Line
    from motiontool.motionfmt.motion import Motion

__all__ = ["JointLimits", "Panel", "limb_groups", "panels_for", "plot_diff", "plot_motion"]

_P = ParamSpec("_P")
_R = TypeVar("_R")

_DPI = 100
_PANEL_W_IN = 3.4
_PANEL_H_IN = 2.1
_MAX_COLUMNS = 6
_MIN_WIDTH_IN = 7.0  # room for the title and the caption
_CAPTION_IN = 0.4  # room below the grid for a two-line caption
_TITLE_IN = 0.35  # room above it for the title
_DRAWABLE = 1e300
"""The largest |y| a panel's range reaches: padding a range of -1e308 to 1e308 overflows a
double (a value past it is drawn leaving the panel)."""
_NEAR_LIMIT_RAD = 0.2  # a limit this close to the plotted values (or one span) is drawn in view
_SPANS = 2 * int(_PANEL_W_IN * _DPI)
"""A panel's time axis in this many equal spans, two a pixel column: a line of more than four
points a span is drawn from the first, last, lowest and highest point of each span, and its
first break (:func:`_decimated`)."""

_NAO_TITLES = {
    "Head": "head",
    "LArm": "left arm",
    "RArm": "right arm",
    "LLeg": "left leg",
    "RLeg": "right leg",
    "LHand": "hands",
    "RHand": "hands",
}
"""Plot titles of the Nao's limbs (:data:`motiontool.kinematics.limbs.NAO_LIMBS`, in order;
both hands share a row)."""


@dataclass(frozen=True)
class JointLimits:
    """A joint's range (rad or m; ±inf if none) and maximum velocity (unit/s; inf if none)."""

    lower: float
    upper: float
    max_velocity: float
    unit: str = "rad"


@dataclass
class Panel:
    """One subplot: joints drawn together (same base name, e.g. ``LPhalanx1`` to ``8``)."""

    title: str
    joints: list[str] = field(default_factory=list)


def limb_groups(
    joints: Sequence[str], robot: str | None, order: Sequence[str] = ()
) -> list[tuple[str, list[str]]]:
    """Joints grouped by limb (:func:`motiontool.kinematics.limbs.limb_of`, the grouping of
    recordings and ``play`` reports too): for the Nao head, left arm, right arm, left leg, right
    leg, hands; for a serial arm such as the UR5e arm, wrist; then ``other`` (``joints`` when
    no name says its limb). Without a robot, one group ``joints``. Within a group, joints come
    in the robot's ``order`` (its model order, shoulder to wrist, hip to ankle), then in file
    order.
    """
    from motiontool.kinematics.limbs import NAO_LIMBS, limb_of

    rank = {name: k for k, name in enumerate(order)}
    names = list(dict.fromkeys(joints))
    names.sort(key=lambda n: rank.get(n, len(rank)))  # stable: file order among the unranked
    if robot is None:
        return [("joints", names)]
    groups: dict[str, list[str]] = {_NAO_TITLES[limb]: [] for limb in NAO_LIMBS}
    other: list[str] = []
    for name in names:
        limb = limb_of(name, "")
        if limb:
            groups.setdefault(_NAO_TITLES.get(limb, limb), []).append(name)
        else:
            other.append(name)
    out = [(title, js) for title, js in groups.items() if js]
    if other:
        out.append(("other" if out else "joints", other))
    return out


def panels_for(joints: Sequence[str]) -> list[Panel]:
    """One panel per joint, except that names differing only in a trailing number
    (``LPhalanx1`` ... ``LPhalanx8``) share one panel."""
    panels: dict[str, Panel] = {}
    for name in joints:
        m = re.fullmatch(r"(.*?\D)(\d+)", name)
        base = m.group(1) if m else name
        key = base if m else f"={name}"
        panels.setdefault(key, Panel(name)).joints.append(name)
    for panel in panels.values():
        if len(panel.joints) > 1:
            first, last = panel.joints[0], panel.joints[-1]
            panel.title = f"{first} to {last}"
    return list(panels.values())


def _mpl(module: str) -> Any:
    """A matplotlib module, or a one-line error naming ``motiontool[plot]``."""
    return require(module, "plot", "plotting (motiontool plot, diff --plot)")


def _style() -> Any:
    """matplotlib's default style, whatever the user's matplotlibrc says (no backend change)."""
    return _mpl("matplotlib.style").context("default")


def _styled(func: Callable[_P, _R]) -> Callable[_P, _R]:
    """``func``, drawing in matplotlib's default style (:func:`_style`), every text as typed
    (a name with ``$`` signs is not mathtext) and names escaped by :func:`fmt_name` (a byte
    that is not UTF-8, a lone surrogate, as ``\\xNN``: matplotlib raised a TypeError), without
    numpy's overflow warnings (values of 1e308 overflow matplotlib's own range arithmetic)."""

    @functools.wraps(func)
    def styled(*args: _P.args, **kwargs: _P.kwargs) -> _R:
        import numpy as np

        with (
            _style(),
            _mpl("matplotlib").rc_context({"text.parse_math": False}),
            np.errstate(over="ignore", invalid="ignore"),
        ):
            return func(*args, **kwargs)

    return styled


def _figure(rows: int, cols: int) -> Any:
    Figure = _mpl("matplotlib.figure").Figure

    width = max(_PANEL_W_IN * cols, _MIN_WIDTH_IN)
    return Figure(figsize=(width, _PANEL_H_IN * rows + _CAPTION_IN + _TITLE_IN), dpi=_DPI)


def _finish(fig: Any, title: str, caption: str) -> None:
    """Title above, caption below (fixed heights in inches), panels in between."""
    height = fig.get_figheight()
    fig.suptitle(fmt_name(title), fontsize=11, y=1.0 - 0.1 / height, va="top")
    fig.text(
        0.01, 0.05 / height, fmt_name(caption), fontsize=7, color="#555555", ha="left", va="bottom"
    )
    fig.tight_layout(rect=(0, _CAPTION_IN / height, 1, 1.0 - _TITLE_IN / height))


def _png(fig: Any, comment: str) -> bytes:
    FigureCanvasAgg = _mpl("matplotlib.backends.backend_agg").FigureCanvasAgg

    FigureCanvasAgg(fig)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=_DPI, metadata={"Software": None, "Comment": comment})
    return buf.getvalue()


def _layout(
    groups: Sequence[tuple[str, list[str]]],
) -> tuple[list[tuple[str, Panel, int, int]], int, int]:
    """(group title, panel, row, column) for each panel; rows and columns of the grid."""
    placed = []
    row = 0
    cols = 1
    for title, joints in groups:
        panels = panels_for(joints)
        for i, panel in enumerate(panels):
            placed.append(
                (title if i == 0 else "", panel, row + i // _MAX_COLUMNS, i % _MAX_COLUMNS)
            )
        cols = max(cols, min(len(panels), _MAX_COLUMNS))
        row += -(-len(panels) // _MAX_COLUMNS)
    return placed, max(row, 1), cols


def _decimated(
    x: npt.NDArray[np.float64], y: npt.NDArray[np.float64], spans: int = _SPANS
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """The points of the line ``(x, y)`` that draw it at the resolution of ``spans`` spans of
    its time range (:func:`_kept`). The line is the same to the pixel; a file of 100,000
    keyframes drew 100,000 points a line (26 s and 774 MB for the random benchmark file). A
    line so dense is drawn without a marker on each keyframe (they would cover it)."""
    keep = _kept(x, (y,), spans)
    return (x, y) if keep is None else (x[keep], y[keep])


def _decimated_pair(
    x: npt.NDArray[np.float64], a: npt.NDArray[np.float64], b: npt.NDArray[np.float64]
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]:
    """Two lines at the same times ``x`` (``diff --plot``'s old and new), thinned as
    :func:`_decimated` thins one: the points either keeps, for both (the band between them is
    filled from the same points)."""
    keep = _kept(x, (a, b), _SPANS)
    return (x, a, b) if keep is None else (x[keep], a[keep], b[keep])


def _kept(
    x: npt.NDArray[np.float64], ys: Sequence[npt.NDArray[np.float64]], spans: int
) -> npt.NDArray[np.bool_] | None:
    """Which points of the lines ``(x, y)`` for each ``y`` of ``ys`` (``x`` the time, not
    decreasing; NaN in either: a break) draw them in ``spans`` equal spans of the time range:
    None (all of them) where there are at most four a span, else in each span its first and
    last point and, of each line, the points of its lowest and highest ``y`` and its first
    break (a break belongs to the span of the time before it)."""
    import numpy as np

    n = x.shape[0]
    timed = ~np.isnan(x)
    if n <= 4 * spans or not timed.any() or float(x[timed].max()) <= float(x[timed].min()):
        return None
    lo, hi = float(x[timed].min()), float(x[timed].max())
    at = np.maximum.accumulate(np.where(timed, np.arange(n), 0))
    t = np.where(timed[at], x[at], lo)  # breaks before the first time: the first span
    span = np.minimum(((t - lo) * (spans / (hi - lo))).astype(np.int64), spans - 1)
    first = np.flatnonzero(np.diff(span, prepend=-1))
    kept = np.zeros(n, dtype=bool)
    kept[first] = True
    kept[np.append(first[1:], n) - 1] = True
    for y in ys:
        finite = timed & ~np.isnan(y)
        for extreme in (np.where(finite, y, np.inf), np.where(finite, -y, np.inf)):
            heads = _first_lowest(extreme, first)  # a span's points follow each other
            kept[heads[finite[heads]]] = True
        breaks = np.flatnonzero(~finite)
        kept[breaks[np.flatnonzero(np.diff(span[breaks], prepend=-1))]] = True
    return kept


def _first_lowest(
    values: npt.NDArray[np.float64], starts: npt.NDArray[np.intp]
) -> npt.NDArray[np.intp]:
    """The index of the first lowest of ``values`` in each run ``[starts[k], starts[k + 1])``
    (``starts`` increasing from 0; the last run ends with ``values``); no NaN."""
    import numpy as np

    lowest = np.minimum.reduceat(values, starts)
    at = np.flatnonzero(values == np.repeat(lowest, np.diff(starts, append=values.shape[0])))
    run = np.searchsorted(starts, at, side="right") - 1
    heads: npt.NDArray[np.intp] = at[np.flatnonzero(np.diff(run, prepend=-1))]
    return heads


def _view(
    values: npt.NDArray[np.float64], limits: JointLimits | None
) -> tuple[float, float, list[float]]:
    """y range for a panel and the limits to draw inside it."""
    import numpy as np

    finite = values[np.isfinite(values)]
    lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 0.0)
    lo, hi = (min(max(y, -_DRAWABLE), _DRAWABLE) for y in (lo, hi))
    span = hi - lo
    shown: list[float] = []
    if limits is not None:
        reach = max(span, _NEAR_LIMIT_RAD)
        for lim in (limits.lower, limits.upper):
            if math.isfinite(lim) and lo - reach <= lim <= hi + reach:
                shown.append(lim)
                lo, hi = min(lo, lim), max(hi, lim)
    # A flat panel at 1e300 needs a pad matplotlib's ticks can resolve there, not 0.02.
    pad = max(0.08 * (hi - lo), 0.02, 1e-6 * max(abs(lo), abs(hi)))
    return lo - pad, hi + pad, shown


@_styled
def plot_motion(
    motion: Motion,
    *,
    groups: Sequence[tuple[str, list[str]]],
    limits: Mapping[str, JointLimits],
    held: Sequence[Line] | None,
    title: str,
    caption: str,
    comment: str,
) -> tuple[bytes, int, int]:
    """Every joint over time as a PNG; returns (png bytes, limit violations, fast segments).

    Args:
        motion: the motion (keyframes drawn as a polyline, broken where a segment touches ``*``).
        groups: (group title, joint names) per grid row (see :func:`limb_groups`).
        limits: per joint name; limit lines and shaded out-of-range bands where given.
        held: per column of ``motion``, the line of its held target, dotted, where it gets
            no command (:func:`~motiontool.cli._held_lines.held_lines`); None to leave those
            spans empty.
        title, caption: text above and below the grid; ``comment`` goes into the PNG's text.
    """
    import numpy as np

    placed, rows, cols = _layout(groups)
    fig = _figure(rows, cols)
    t_s = motion.times_ms.astype(np.float64) / MS_PER_S
    n_limit = n_fast = 0
    axes = fig.subplots(rows, cols, squeeze=False)
    used: set[tuple[int, int]] = set()
    for group, panel, r, c in placed:
        used.add((r, c))
        row_title = group if c == 0 else None
        counts = _draw_panel(axes[r][c], motion, panel, t_s, limits, held, row_title)
        n_limit += counts[0]
        n_fast += counts[1]
    _finish_grid(axes, rows, cols, used)
    _finish(fig, title, caption)
    return _png(fig, comment), n_limit, n_fast


def _draw_panel(
    ax: Any,
    motion: Motion,
    panel: Panel,
    t_s: npt.NDArray[np.float64],
    limits: Mapping[str, JointLimits],
    held: Sequence[Line] | None,
    row_title: str | None,
) -> tuple[int, int]:
    """One panel of :func:`plot_motion`: its joints over time (``t_s``, (P,) s), the first
    joint's limits; ``row_title``: the group's title on the y axis, with the unit ('' for the
    unit alone), for the first panel of a row (else None). Returns (keyframe values outside the
    limits, segments above maxVelocity)."""
    columns = [motion.column(j) for j in panel.joints]
    lim = limits.get(panel.joints[0])
    y0, y1, shown = _view(motion.values[:, columns], lim)
    if lim is not None:
        _draw_limits(ax, lim, y0, y1, shown)
    n_limit = n_fast = 0
    for k, (name, col) in enumerate(zip(panel.joints, columns, strict=True)):
        color = f"C{k % 10}"
        v = motion.values[:, col]
        x, y = _decimated(t_s, v)
        marker = "o" if x.shape[0] == t_s.shape[0] else None  # too dense: they would cover it
        ax.plot(x, y, color=color, lw=1.2, marker=marker, ms=2.2, label=fmt_name(name), zorder=3)
        if held is not None:  # dotted where the joint holds its target (cli/_held_lines.py)
            ax.plot(*held[col], color=color, lw=1.0, ls=":", zorder=2)
        jl = limits.get(name)
        if jl is None:
            continue
        n_limit += _mark_out_of_range(ax, t_s, v, jl)
        n_fast += _mark_too_fast(ax, t_s, v, jl)
    ax.set_ylim(y0, y1)
    ax.set_xlim(0.0, max(float(t_s[-1]), 1e-3) * 1.0)
    ax.set_title(fmt_name(panel.title), fontsize=9, pad=10)
    ax.tick_params(labelsize=7)
    ax.grid(True, lw=0.3, alpha=0.6)
    unit = lim.unit if lim is not None else "rad"
    if row_title is not None:
        ax.set_ylabel(f"{row_title}\n({unit})" if row_title else f"({unit})", fontsize=8)
    if len(panel.joints) > 1 and len(panel.joints) <= 4:
        ax.legend(fontsize=6, loc="best")
    return n_limit, n_fast


def _finish_grid(axes: Any, rows: int, cols: int, used: set[tuple[int, int]]) -> None:
    """The grid's cells without a panel hidden; the time axis labelled under the bottom panel
    of each column."""
    for r in range(rows):
        for c in range(cols):
            if (r, c) not in used:
                axes[r][c].set_visible(False)
    for c in range(cols):
        bottom = max((r for r in range(rows) if (r, c) in used), default=None)
        if bottom is not None:
            axes[bottom][c].set_xlabel("time (s)", fontsize=8)


def _draw_limits(ax: Any, lim: JointLimits, y0: float, y1: float, shown: list[float]) -> None:
    """A joint's range above the panel (when both ends are finite), the out-of-range bands
    shaded up to the view ``y0``..``y1`` (rad or m), and the limits ``shown`` as dashed lines."""
    if math.isfinite(lim.lower + lim.upper):
        ax.text(
            0.5,
            1.01,
            f"range {lim.lower:.3g} to {lim.upper:.3g} {lim.unit}",
            transform=ax.transAxes,
            ha="center",
            va="bottom",
            fontsize=6,
            color="#777777",
        )
    if math.isfinite(lim.upper):
        ax.axhspan(lim.upper, max(y1, lim.upper), color="#f4c7c3", lw=0, zorder=0)
    if math.isfinite(lim.lower):
        ax.axhspan(min(y0, lim.lower), lim.lower, color="#f4c7c3", lw=0, zorder=0)
    for value in shown:
        ax.axhline(value, color="#c0392b", lw=0.8, ls="--", zorder=1)


def _mark_out_of_range(
    ax: Any, t_s: npt.NDArray[np.float64], v: npt.NDArray[np.float64], jl: JointLimits
) -> int:
    """An x on each keyframe value ``v`` ((P,) at ``t_s`` s) outside ``jl``'s range; how many."""
    out = (v < jl.lower) | (v > jl.upper)
    if out.any():
        ax.plot(
            *_decimated(t_s[out], v[out]),
            ls="none",
            marker="x",
            ms=7,
            mew=2,
            color="#c0392b",
            zorder=5,
        )
    return int(out.sum())


def _mark_too_fast(
    ax: Any, t_s: npt.NDArray[np.float64], v: npt.NDArray[np.float64], jl: JointLimits
) -> int:
    """Each segment of ``v`` ((P,) at ``t_s`` s) faster than ``jl.max_velocity`` drawn thick
    red, all of them one line broken by NaN (one artist, however many: a file of random
    values has millions); how many."""
    import numpy as np

    if not (math.isfinite(jl.max_velocity) and t_s.shape[0] > 1):
        return 0
    with np.errstate(invalid="ignore"):
        speed = np.abs(np.diff(v)) / np.diff(t_s)
    fast = np.flatnonzero(speed > jl.max_velocity * (1.0 + 1e-9))
    if fast.shape[0]:
        x = np.full((fast.shape[0], 3), np.nan)  # start, end, a break
        y = np.full((fast.shape[0], 3), np.nan)
        x[:, 0], x[:, 1] = t_s[fast], t_s[fast + 1]
        y[:, 0], y[:, 1] = v[fast], v[fast + 1]
        ax.plot(*_decimated(x.ravel(), y.ravel()), color="#c0392b", lw=3.2, zorder=4)
    return int(fast.shape[0])


@_styled
def plot_diff(
    elapsed_ms: npt.NDArray[np.int64],
    old: Mapping[str, npt.NDArray[np.float64]],
    new: Mapping[str, npt.NDArray[np.float64]],
    joints: Sequence[str],
    *,
    title: str,
    caption: str,
    comment: str,
) -> bytes:
    """Old (grey) and new (blue) held targets of ``joints`` over time, one panel each, with
    their difference shaded, as a PNG."""
    import numpy as np

    cols = min(max(len(joints), 1), 4)
    rows = max(-(-len(joints) // cols), 1)
    fig = _figure(rows, cols)
    axes = fig.subplots(rows, cols, squeeze=False)
    t = elapsed_ms / MS_PER_S
    for i in range(rows * cols):
        ax = axes[i // cols][i % cols]
        if i >= len(joints):
            ax.set_visible(False)
            continue
        name = joints[i]
        x, a, b = _decimated_pair(t, old[name], new[name])
        ax.plot(x, a, color="#7f7f7f", lw=2.2, label="old", zorder=2)
        ax.plot(x, b, color="#1f77b4", lw=1.0, label="new", zorder=3)
        # Shaded only where both hold a finite height: NaN is a joint not commanded yet (no
        # target) or a 'nan' command (a target with no height), and neither can be drawn.
        with np.errstate(invalid="ignore"):
            ax.fill_between(
                x,
                a,
                b,
                where=~(np.isnan(a) | np.isnan(b)),
                color="#d62728",
                alpha=0.25,
                lw=0,
                zorder=1,
            )
        ax.set_title(fmt_name(name), fontsize=9)
        ax.tick_params(labelsize=7)
        ax.grid(True, lw=0.3, alpha=0.6)
        if i % cols == 0:
            ax.set_ylabel("target (rad)", fontsize=8)
        if i // cols == rows - 1 or i + cols >= len(joints):
            ax.set_xlabel("time (s)", fontsize=8)
        if i == 0:
            ax.legend(fontsize=7, loc="best")
    if not joints:
        axes[0][0].set_visible(True)
        axes[0][0].axis("off")
        axes[0][0].text(0.5, 0.5, "no joint in common", ha="center", va="center")
    _finish(fig, title, caption)
    return _png(fig, comment)
