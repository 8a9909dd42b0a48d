"""Fuzz the ``.motion`` reader, the document layer and the player against each other and against
the plain-loop oracle of Webots (``tests/oracle.py``, glibc's own ``sscanf``).

Inputs are small files built from the Webots corpus: a header and a random window of 1-8 pose
lines (sometimes only the first few columns), then 1-5 byte- or token-level mutations (time
fields of 1-5 digits and times that wrap a C int, nan / inf / the -9999999.9 marker, ``*``,
``,,``, CR, NUL, blank lines, non-UTF-8 bytes, huge numbers, and now and then a line of 4095
bytes or more). Input ``i`` depends only on ``--seed`` and ``i``, not on ``--jobs``. For each one:

* the exact, fast and bulk (numpy loadtxt) reading paths agree: verdict, diagnostics, times, values
  bit for bit (NaN positions included) and the commanded mask;
* the reader agrees with the oracle: accepted or not, the line where Webots stops (and the
  finding there is reported, also after a cut line), the times, the values and which cells are
  ``*``;
* a file Webots accepts round-trips: ``dumps(loads(x)) == x``, and the document's motion is the
  reader's (a file with a cut line must be refused with MotionSyntaxError instead);
* the command stream of an accepted file (``sample``) is the oracle's, step by step, bit for bit,
  with the same steps without command (skipped when the stream would be huge);
* nothing raises.

Each disagreement or traceback is saved under ``--out`` (the input as ``<kind>-<seed>-<i>.motion``
and what differed as ``.txt``); the exit status is 1 if there was any. Not a timed test: run it
by hand, e.g. ``.venv/bin/python dev/fuzz.py --count 1000000 --seed 1 --jobs 2``.
"""

from __future__ import annotations

import argparse
import math
import multiprocessing
import random
import struct
import sys
import time
import traceback
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))  # the oracle and the three reading paths

from oracle import UNDEFINED, webots_load, webots_play  # noqa: E402
from readpaths import differences, read_all  # noqa: E402

from motiontool.motionfmt import MotionSyntaxError, dumps, loads, sample  # noqa: E402

MAX_STEPS = 4000
"""Longest command stream (steps) compared with the oracle; longer ones are not sampled."""
MAX_ORACLE_WORK = 300_000
"""Largest steps x joints x poses the oracle's plain loop plays for one input."""
TIMESTEPS = (1, 7, 8, 20, 32, 40)
CHUNK = 250

# -- corpus --------------------------------------------------------------------------------------


def default_corpus() -> Path:
    vendored = ROOT / "tests" / "data" / "corpus" / "webots"
    return vendored if vendored.is_dir() else ROOT.parent / "shared" / "corpus" / "webots"


def load_corpus(folder: Path) -> list[tuple[bytes, list[bytes]]]:
    """(header, pose lines) of every ``*.motion`` under ``folder``, in a stable order."""
    out = []
    for path in sorted(folder.rglob("*.motion")):
        lines = path.read_bytes().replace(b"\r\n", b"\n").split(b"\n")
        poses = [line for line in lines[1:] if line.strip()]
        if poses:
            out.append((lines[0], poses))
    return out


# -- mutations -----------------------------------------------------------------------------------

WRAPPING_TIMES = (
    b"35791:23:647", b"35791:23:648", b"35792:00:000", b"71582:47:295", b"71582:47:296",
    b"71582:47:396", b"99999:99999:99999", b"2147483647", b"2147483648", b"4294967295",
    b"4294967296", b"0:2147483", b"0:2147484", b"35791:23:646",
)  # fmt: skip
CELLS = (
    b"nan", b"inf", b"-inf", b"-nan", b"NaN", b"Infinity", b"infinit", b"nanx", b"-9999999.9",
    b"-9999999.90", b"*", b" *", b"* ", b"", b" ", b"1e308", b"1e309", b"-1e999", b"1e-400",
    b"0x1p3", b"0x", b"2rad", b"1.5.3", b"+.5", b".", b"e5", b"-0", b"1e", b"1e+", b"0x1.8p1",
    b"1_0", b"\t2", b"99999999999999999999", b"4.9e-324", b"1,5", b"#", b"abc",
)  # fmt: skip
BYTES = b"0123456789:,.-+*eE \t\r\n#x\0\xff\xe9\xc3"


def _time_token(rng: random.Random) -> bytes:
    if rng.random() < 0.3:
        return rng.choice(WRAPPING_TIMES)
    n_fields = rng.randint(1, 3)
    fields = []
    for _ in range(n_fields):
        value = rng.choice((rng.randint(0, 9), rng.randint(0, 999), rng.randint(0, 99999)))
        width = rng.randint(len(str(value)), 5)
        fields.append(b"%0*d" % (width, value))
    return b":".join(fields)


def _cells(line: bytes) -> list[bytes]:
    return line.split(b",")


def _mutate_line(rng: random.Random, line: bytes) -> bytes:
    cells = _cells(line)
    kind = rng.randrange(7)
    if kind == 0:  # a new time
        cells[0] = _time_token(rng)
    elif kind == 1 and len(cells) > 2:  # a special value
        cells[rng.randrange(2, len(cells))] = rng.choice(CELLS)
    elif kind == 2 and len(cells) > 2:  # a random finite value, sometimes huge
        value = rng.choice((rng.uniform(-4, 4), rng.uniform(-1e308, 1e308), -9999999.9))
        cells[rng.randrange(2, len(cells))] = repr(value).encode()
    elif kind == 3:  # ',,' or a missing comma
        k = rng.randrange(len(cells))
        if rng.random() < 0.5:
            cells.insert(k, b"")
        elif len(cells) > 1:
            cells[k : k + 2] = [b"".join(cells[k : k + 2])]
    elif kind == 4:  # a time field edit: digits in / out
        t = bytearray(cells[0])
        pos = rng.randint(0, len(t))
        if t and rng.random() < 0.5:
            del t[min(pos, len(t) - 1)]
        else:
            t[pos:pos] = rng.choice((b"9", b"0", b":", b"99999", b" "))
        cells[0] = bytes(t)
    elif kind == 5:  # trailing comma or CR
        cells[-1] += rng.choice((b"", b"\r", b","))
    else:  # drop or duplicate a cell
        k = rng.randrange(len(cells))
        if rng.random() < 0.5 and len(cells) > 1:
            del cells[k]
        else:
            cells.insert(k, cells[k])
    return b",".join(cells)


def _mutate_bytes(rng: random.Random, data: bytes) -> bytes:
    out = bytearray(data)
    pos = rng.randint(0, len(out))
    op = rng.randrange(3)
    if op == 0 or not out:
        out[pos:pos] = bytes([rng.choice(BYTES)])
    elif op == 1:
        del out[min(pos, len(out) - 1)]
    else:
        out[min(pos, len(out) - 1)] = rng.choice(BYTES)
    return bytes(out)


def make_input(corpus: list[tuple[bytes, list[bytes]]], seed: int, index: int) -> bytes:
    """Input ``index`` of the run with ``seed``: a window of a corpus file, mutated."""
    rng = random.Random(f"{seed}:{index}")
    header, poses = rng.choice(corpus)
    n = rng.randint(1, min(8, len(poses)))
    start = rng.randrange(len(poses) - n + 1)
    lines = [header, *poses[start : start + n]]
    if rng.random() < 0.5:  # keep the first few columns only: small and fast
        keep = 2 + rng.randint(1, 4)
        lines = [b",".join(line.split(b",")[:keep]) for line in lines]
    for _ in range(rng.randint(1, 5)):
        op = rng.random()
        k = rng.randrange(1, len(lines)) if len(lines) > 1 else 0
        if op < 0.55 and len(lines) > 1:
            lines[k] = _mutate_line(rng, lines[k])
        elif op < 0.62:  # a blank line, a CR-only line or a line of spaces
            lines.insert(rng.randint(1, len(lines)), rng.choice((b"", b"\r", b"  ", b"\t")))
        elif op < 0.68 and len(lines) > 2:  # swap or duplicate a pose (equal/decreasing times)
            j = rng.randrange(1, len(lines))
            if rng.random() < 0.5:
                lines[k], lines[j] = lines[j], lines[k]
            else:
                lines.insert(j, lines[k])
        elif op < 0.72:  # header trouble
            lines[0] = rng.choice(
                (
                    b"\xef\xbb\xbf" + lines[0],
                    lines[0].replace(b"V1.0", b"V1.1"),
                    lines[0].lower(),
                    lines[0] + b"," + lines[0].split(b",")[-1],
                    lines[0].replace(b",", b", ", 1),
                    b"#WEBOTS_MOTION,V1.0",
                )
            )
        elif op < 0.74:  # a long line: Webots' fgets cuts it at 4095 bytes
            pad = rng.choice((4095, 4094, 4096, 4200, 8300)) - len(lines[k])
            if pad > 0:
                cells = lines[k].split(b",")
                c = rng.randrange(len(cells))
                cells[c] = cells[c] + b" " * pad if c != 0 else b" " * pad + cells[c]
                lines[k] = b",".join(cells)
        elif op < 0.78:  # increasing times that wrap
            for i in range(1, len(lines)):
                if rng.random() < 0.5:
                    cells = lines[i].split(b",")
                    cells[0] = _time_token(rng)
                    lines[i] = b",".join(cells)
        else:
            joined = b"\n".join(lines)
            lines = _mutate_bytes(rng, joined).split(b"\n")
    eol = b"\r\n" if rng.random() < 0.15 else b"\n"
    data = eol.join(lines)
    if rng.random() < 0.85:
        data += eol
    return data


# -- checks --------------------------------------------------------------------------------------


def _cell_bits(x: float | None) -> object:
    if x is None:
        return None
    return "nan" if math.isnan(x) else struct.pack("<d", x)


def check(data: bytes, index: int) -> tuple[bool, list[tuple[str, str]]]:
    """Whether Webots accepts the input, and every disagreement, as (kind, detail); a
    traceback is one too."""
    out: list[tuple[str, str]] = []
    try:
        return _check(data, index, out), out
    except Exception:  # the fuzzer's job is to find these
        return False, [*out, ("traceback", traceback.format_exc())]


def _check(data: bytes, index: int, out: list[tuple[str, str]]) -> bool:
    step = TIMESTEPS[index % len(TIMESTEPS)]
    results = read_all(data, step)
    out.extend(("paths", d) for d in differences(results))
    exact = results["exact"]
    oracle = webots_load(data)
    if exact.accepted != oracle.ok:
        out.append(("oracle", f"accepted {exact.accepted}, Webots {oracle.ok}"))
        return oracle.ok
    if not oracle.ok:
        if oracle.stop_line is not None and (
            exact.rejected_at is None or exact.rejected_at.line != oracle.stop_line
        ):
            where = None if exact.rejected_at is None else exact.rejected_at.line
            out.append(("oracle", f"rejected at line {where}, Webots at {oracle.stop_line}"))
        if not any(d is exact.rejected_at for d in exact.diagnostics):
            out.append(("oracle", "the finding where Webots stops is not among the findings"))
        try:
            loads(data)
        except MotionSyntaxError:
            pass
        else:
            out.append(("roundtrip", "loads accepted a file Webots rejects"))
        return False
    motion = exact.motion
    if motion.times_ms.tolist() != oracle.times:
        out.append(("oracle", f"times {motion.times_ms.tolist()} != {oracle.times}"))
        return True
    want = [[_cell_bits(None if v == UNDEFINED else v) for v in row] for row in oracle.values]
    got = [
        [_cell_bits(v if c else None) for v, c in zip(row, mask, strict=True)]
        for row, mask in zip(motion.values.tolist(), motion.commanded.tolist(), strict=True)
    ]
    if got != want:
        out.append(("oracle", "values or '*' cells differ"))
    cut = any(d.code == "MT111" for d in exact.diagnostics)
    try:
        doc = loads(data)
    except MotionSyntaxError as exc:
        if not cut:
            out.append(("roundtrip", f"loads refused an accepted file: {exc}"))
    else:
        if cut:
            out.append(("roundtrip", "loads accepted a file with a cut line"))
        if dumps(doc) != data:
            out.append(("roundtrip", "dumps(loads(x)) != x"))
        if doc.motion != motion:
            out.append(("roundtrip", "the document's motion is not the reader's"))
    steps = motion.duration_ms // step + 2
    if steps > MAX_STEPS:
        return True
    stream = sample(motion, step)
    if steps * motion.n_joints * motion.n_poses <= MAX_ORACLE_WORK:
        rows = webots_play(oracle.times, oracle.values, step)
        if stream.elapsed_ms.tolist() != [e for e, _ in rows]:
            out.append(("sample", f"steps differ at {step} ms"))
            return True
        want_s = [[_cell_bits(v) for v in row] for _, row in rows]
        got_s = [
            [_cell_bits(v if c else None) for v, c in zip(row, mask, strict=True)]
            for row, mask in zip(stream.targets.tolist(), stream.commanded.tolist(), strict=True)
        ]
        if got_s != want_s:
            k = next(i for i, (a, b) in enumerate(zip(got_s, want_s, strict=True)) if a != b)
            out.append(("sample", f"targets differ at {step} ms, step {k}"))
    return True


# -- running -------------------------------------------------------------------------------------


@dataclass
class Batch:
    done: int = 0
    accepted: int = 0
    failures: list[tuple[int, str, str, bytes]] = field(default_factory=list)


_CORPUS: list[tuple[bytes, list[bytes]]] = []


def _init(corpus: list[tuple[bytes, list[bytes]]]) -> None:
    _CORPUS[:] = corpus


def run_chunk(job: tuple[int, int, int]) -> Batch:
    seed, start, stop = job
    batch = Batch()
    for i in range(start, stop):
        data = make_input(_CORPUS, seed, i)
        accepted, found = check(data, i)
        batch.done += 1
        batch.accepted += accepted
        for kind, detail in found:
            batch.failures.append((i, kind, detail, data))
    return batch


def _chunks(seed: int, count: int) -> Iterator[tuple[int, int, int]]:
    for start in range(0, count, CHUNK):
        yield seed, start, min(start + CHUNK, count)


def save(out: Path, seed: int, index: int, kind: str, detail: str, data: bytes) -> Path:
    out.mkdir(parents=True, exist_ok=True)
    stem = out / f"{kind}-{seed}-{index}"
    stem.with_suffix(".motion").write_bytes(data)
    with stem.with_suffix(".txt").open("a", encoding="utf-8") as report:
        report.write(f"input {index} of seed {seed}: {kind}\n{detail}\n")
    return stem.with_suffix(".motion")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--count", type=int, default=20000, help="inputs to try")
    parser.add_argument("--seed", type=int, default=1, help="fixed seed: same inputs every run")
    parser.add_argument("--jobs", type=int, default=1, help="worker processes")
    parser.add_argument("--corpus", type=Path, default=None, help="folder of .motion files")
    parser.add_argument(
        "--out", type=Path, default=ROOT / "build" / "fuzz", help="where reproducers go"
    )
    args = parser.parse_args(argv)
    corpus_dir = args.corpus or default_corpus()
    corpus = load_corpus(corpus_dir)
    if not corpus:
        print(f"fuzz: error: no .motion file with a pose under {corpus_dir}", file=sys.stderr)
        return 2
    print(
        f"fuzz: {args.count} inputs, seed {args.seed}, {args.jobs} job(s), "
        f"{len(corpus)} corpus files from {corpus_dir}",
        flush=True,
    )
    failures: dict[str, int] = {}
    done = accepted = 0
    t0 = last = time.perf_counter()
    jobs = _chunks(args.seed, args.count)
    runner: Callable[[], Iterator[Batch]]
    if args.jobs > 1:
        pool = multiprocessing.get_context("spawn").Pool(
            args.jobs, initializer=_init, initargs=(corpus,)
        )

        def runner() -> Iterator[Batch]:
            return pool.imap_unordered(run_chunk, jobs)
    else:
        pool = None
        _init(corpus)

        def runner() -> Iterator[Batch]:
            return map(run_chunk, jobs)

    try:
        for batch in runner():
            done += batch.done
            accepted += batch.accepted
            for index, kind, detail, data in batch.failures:
                failures[kind] = failures.get(kind, 0) + 1
                path = save(args.out, args.seed, index, kind, detail, data)
                line = detail.strip().splitlines()[-1]
                line = line if len(line) <= 200 else line[:197] + "..."
                print(f"fuzz: {kind} at input {index}: {line} ({path})", flush=True)
            now = time.perf_counter()
            if now - last >= 10 or done == args.count:
                last = now
                print(
                    f"fuzz: {done}/{args.count} inputs ({accepted} accepted by Webots), "
                    f"{sum(v for k, v in failures.items() if k != 'traceback')} disagreements, "
                    f"{failures.get('traceback', 0)} tracebacks, {done / (now - t0):.0f} inputs/s",
                    flush=True,
                )
    finally:
        if pool is not None:
            pool.close()
            pool.join()
    elapsed = time.perf_counter() - t0
    summary = ", ".join(f"{n} {k}" for k, n in sorted(failures.items())) or "none"
    print(
        f"fuzz: done: {done} inputs in {elapsed:.1f} s ({done / elapsed:.0f} inputs/s), "
        f"{accepted} accepted by Webots; failures: {summary}"
    )
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
