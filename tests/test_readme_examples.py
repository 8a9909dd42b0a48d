"""The examples of README and docs/ run as written from a fresh clone (the
reference moved from README to docs/ keeps its examples tested): every motion file
a ``motiontool`` example reads is in the repository, a transcript (``$ motiontool ...`` and what
follows) is what the command prints, and the library example runs."""

from __future__ import annotations

import glob
import re
import shlex
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path
from string import Template

import pytest
from conftest import ROOT
from typer.testing import CliRunner

from motiontool.cli.app import app

README = ROOT / "README.md"

DOCUMENTS = (README, *sorted((ROOT / "docs").glob("*.md")))
"""README and every page of docs/: their examples are held to the same tests."""


def documents() -> list[tuple[str, str]]:
    """(name relative to the repository, text) of README and each page of docs/."""
    return [(str(p.relative_to(ROOT)), p.read_text(encoding="utf-8")) for p in DOCUMENTS]


PLACEHOLDERS: frozenset[str] = frozenset()
"""Motion files README's examples name that are not in the repository on purpose, each declared
a placeholder in README. None: every example names a file of the clone (``motions/``, or Webots'
files vendored in ``tests/data/corpus/webots``)."""

OUTPUT_OPTIONS = frozenset({"-o", "--output"})
"""Options whose value is a file the command writes, not one it reads."""

_ASSIGNMENT = re.compile(r"([A-Z_][A-Z0-9_]*)=(\S+)")


@dataclass(frozen=True)
class Block:
    """A fenced code block of README: its info string, the line number of its first line, its
    lines."""

    info: str
    line: int
    lines: tuple[str, ...]


@dataclass(frozen=True)
class Example:
    """A command line of a code block that runs ``motiontool``, continuation lines joined,
    ``$NAME`` replaced by the block's ``NAME=value``; ``cwd`` where the block's ``cd`` left it."""

    line: int
    tokens: tuple[str, ...]
    cwd: Path


def blocks(text: str) -> list[Block]:
    """Every fenced code block of ``text``."""
    out: list[Block] = []
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        if lines[i].startswith("```"):
            end = next(j for j in range(i + 1, len(lines)) if lines[j].startswith("```"))
            out.append(Block(lines[i][3:].strip(), i + 2, tuple(lines[i + 1 : end])))
            i = end
        i += 1
    return out


def _joined(block: Block) -> list[tuple[int, str]]:
    """The block's lines, a line ending in a backslash joined with the next; ``$ `` (a prompt)
    dropped."""
    out: list[tuple[int, str]] = []
    pending = ""
    for number, line in enumerate(block.lines, block.line):
        text = line.removeprefix("$ ")
        if text.endswith("\\"):
            pending += text[:-1] + " "
            continue
        out.append((number, pending + text))
        pending = ""
    return out


def block_examples(block: Block) -> list[Example]:
    """Every ``motiontool`` command line of ``block``."""
    found: list[Example] = []
    variables: dict[str, str] = {}
    cwd = ROOT
    for number, line in _joined(block):
        if match := _ASSIGNMENT.fullmatch(line.strip()):
            variables[match[1]] = match[2]
            continue
        try:
            tokens = shlex.split(Template(line).safe_substitute(variables), comments=True)
        except ValueError:  # not shell (TOML, Python): no example there
            continue
        if tokens[:1] == ["cd"]:
            cwd = cwd / tokens[1]
        elif any(t == "motiontool" or t.endswith("/motiontool") for t in tokens):
            found.append(Example(number, tuple(t.strip("[]") for t in tokens), cwd))
    return found


def examples(text: str) -> list[Example]:
    """Every ``motiontool`` command line of ``text``'s code blocks."""
    return [example for block in blocks(text) for example in block_examples(block)]


def motion_inputs(example: Example) -> list[str]:
    """The ``.motion`` files an example reads: its arguments ending in ``.motion`` but the
    value of ``-o`` / ``--output`` and ``convert``'s OUT (its second argument)."""
    tokens = example.tokens
    written = {i for i in range(1, len(tokens)) if tokens[i - 1] in OUTPUT_OPTIONS}
    if tokens[1:2] == ("convert",):
        written.add(3)
    return [t for i, t in enumerate(tokens) if t.endswith(".motion") and i not in written]


def test_the_extraction_finds_the_examples() -> None:
    found = examples(README.read_text(encoding="utf-8"))
    assert len(found) >= 40
    inputs = {name for example in found for name in motion_inputs(example)}
    corpus = "tests/data/corpus/webots/projects/robots/softbank"
    assert f"{corpus}/nao/motions/StandUpFromFront.motion" in inputs  # $NAO expanded
    assert "motions/nao/*.motion" in inputs
    assert not any(name.startswith("out/") for name in inputs)  # -o's value is an output
    sample = "```sh\nW=a/b\nmotiontool play $W/x.motion \\\n  -o y.motion [--rrd z.motion]\n```\n"
    (example,) = examples(sample)
    assert motion_inputs(example) == ["a/b/x.motion", "z.motion"]
    (convert,) = examples("```sh\nmotiontool convert in.csv out/back.motion\n```\n")
    assert motion_inputs(convert) == []  # convert IN OUT: OUT is written


def test_every_motion_file_an_example_reads_is_in_the_repository() -> None:
    missing = []
    for document, text in documents():
        for example in examples(text):
            for name in motion_inputs(example):
                if name in PLACEHOLDERS:
                    continue
                found = list(example.cwd.glob(name)) if "*" in name else [example.cwd / name]
                if not found or not all(path.is_file() for path in found):
                    missing.append(f"{document}:{example.line}: {name} (from {example.cwd})")
    assert missing == [], "files that are not in the repository:\n" + "\n".join(missing)


def transcripts(text: str) -> list[tuple[Example, str]]:
    """Every ``$ motiontool ...`` line of a code block with the lines that follow it (up to the
    next ``$`` line or the block's end): what the command prints."""
    out: list[tuple[Example, str]] = []
    for block in blocks(text):
        if not any(line.startswith("$ motiontool ") for line in block.lines):
            continue
        by_line = {e.line: e for e in block_examples(block)}
        for i, line in enumerate(block.lines):
            if not line.startswith("$ motiontool "):
                continue
            rest = block.lines[i + 1 :]
            end = next((j for j, r in enumerate(rest) if r.startswith("$ ")), len(rest))
            out.append((by_line[block.line + i], "".join(f"{r}\n" for r in rest[:end])))
    return out


def test_every_transcript_is_what_the_command_prints(monkeypatch: pytest.MonkeyPatch) -> None:
    found = [(name, *t) for name, text in documents() for t in transcripts(text)]
    assert {name for name, *_ in found} >= {"README.md", "docs/commands.md"}
    for name, example, printed in found:
        monkeypatch.chdir(example.cwd)
        args = list(example.tokens[example.tokens.index("motiontool") + 1 :])
        result = CliRunner().invoke(app, args)
        assert result.output == printed, f"{name}:{example.line}"


LIBRARY = ROOT / "docs" / "library.md"


def test_the_library_example_runs_from_the_repository_root(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    (code,) = [
        "\n".join(b.lines)
        for b in blocks(LIBRARY.read_text(encoding="utf-8"))
        if b.info == "python" and "from motiontool" in "\n".join(b.lines)
    ]
    monkeypatch.chdir(ROOT)
    exec(compile(code, str(LIBRARY), "exec"), {})  # the page's own example


def _shell_commands(block: Block) -> list[tuple[int, list[str]]]:
    """The ``motiontool`` command lines of a shell block as the shell splits them: variables
    of the block expanded, a pipeline cut at ``|`` (the part that runs ``motiontool``), the
    brackets kept (``[--x]`` is synopsis, not a command)."""
    found: list[tuple[int, list[str]]] = []
    variables: dict[str, str] = {}
    for number, line in _joined(block):
        if match := _ASSIGNMENT.fullmatch(line.strip()):
            variables[match[1]] = match[2]
            continue
        lexer = shlex.shlex(
            Template(line).safe_substitute(variables), posix=True, punctuation_chars=True
        )
        lexer.whitespace_split = True
        lexer.commenters = "#"
        tokens = list(lexer)
        start = 0
        for i, token in enumerate([*tokens, "|"]):
            if token in {"|", "||", "&&", ";"}:
                part = tokens[start:i]
                start = i + 1
                if part and (part[0] == "motiontool" or part[0].endswith("/motiontool")):
                    found.append((number, part[1:]))
    return found


def _parse(args: list[str]) -> str | None:
    """What the command line's own parser says of ``args`` (``motiontool``'s arguments): None
    when they parse, else the reason. Nothing runs: only the options and arguments are read."""
    import typer
    from typer._click.exceptions import ClickException
    from typer.core import TyperGroup

    if any(a.startswith("[") or a.endswith("]") or a.startswith("<") for a in args):
        return f"synopsis, not a command: {args}"
    group = typer.main.get_command(app)
    try:
        with group.make_context("motiontool", list(args)) as ctx:
            name, command, rest = group.resolve_command(ctx, [*ctx._protected_args, *ctx.args])
            assert command is not None
            while isinstance(command, TyperGroup) and rest:
                parent = command.make_context(name or "", rest, parent=ctx)
                name, command, rest = command.resolve_command(
                    parent, [*parent._protected_args, *parent.args]
                )
                assert command is not None
                ctx = parent
            command.make_context(name or "", rest, parent=ctx).close()
    except typer.Exit:  # -V: eager and done
        return None
    except SystemExit as exc:  # --show-completion: eager, prints and exits
        return None if exc.code in (0, None) else f"exit {exc.code}"
    except ClickException as exc:
        return exc.format_message()
    return None


SCRIPT = str(Path(sys.executable).parent / "motiontool")
"""The installed console script, as a user runs it."""

QUICK = frozenset(
    {
        "validate",
        "info",
        "codes",
        "rule",
        "robots",
        "sample",
        "diff",
        "resample",
        "retime",
        "mirror",
        "trim",
        "scale",
        "convert",
        "concat",
        "expect",
    }
)
"""The commands whose README examples the test runs for real (play, batch, generate and plot
take seconds to minutes each: they are parsed, and run by their own tests)."""


def _shell_blocks(text: str | None = None) -> list[Block]:
    """The shell blocks of ``text`` (default: README)."""
    text = README.read_text(encoding="utf-8") if text is None else text
    return [b for b in blocks(text) if b.info in {"sh", "bash", "shell"}]


def test_every_command_line_of_a_shell_block_parses_as_written() -> None:
    """A line of a copyable block runs as written (no ``[--x]``, no
    ``json|sarif``, no option that does not exist); synopsis lives in ``text`` blocks."""
    bad = []
    lines = [
        (name, n, a)
        for name, text in documents()
        for b in _shell_blocks(text)
        for n, a in _shell_commands(b)
    ]
    assert len(lines) >= 55
    assert len([line for line in lines if line[0] == "README.md"]) >= 45
    for name, number, args in lines:
        if (why := _parse(args)) is not None:
            bad.append(f"{name}:{number}: {why}")
    assert bad == [], "\n".join(bad)


def test_the_parse_check_refuses_synopsis() -> None:
    assert _parse(["validate", "motions/", "--format", "json|sarif"]) is not None
    assert _parse(["validate", "motions/", "[--timestep", "20]"]) is not None
    assert _parse(["validate", "motions/", "--no-such-option"]) is not None
    assert _parse(["validate", "motions/", "--format", "sarif"]) is None
    assert _parse(["robots", "show", "nao", "--format", "json"]) is None
    assert _parse(["robots", "show", "nao", "--fromat", "json"]) is not None


@pytest.mark.needs("erd")
def test_the_quick_examples_run_as_written(tmp_path: Path) -> None:
    """The read-only and file-writing examples of the Commands block run in a clone-like folder
    (the repository's motions and test data linked in): none is a usage or I/O error."""
    for name in ("motions", "tests"):
        (tmp_path / name).symlink_to(ROOT / name)
    (commands,) = [b for b in _shell_blocks() if any("DANCE=" in line for line in b.lines)]
    ran = 0
    for number, args in _shell_commands(commands):
        if args[:1] and args[0] in QUICK and "-" not in args and "--fix" not in args:
            expanded = [
                p
                for a in args
                for p in (sorted(glob.glob(a, root_dir=tmp_path)) if "*" in a else [a])
            ]
            result = subprocess.run(
                [SCRIPT, *expanded],
                cwd=tmp_path,
                capture_output=True,
                text=True,
                check=False,
                stdin=subprocess.DEVNULL,
                timeout=120,
            )
            assert result.returncode in (0, 1), f"README.md:{number}: {result.stderr}"
            ran += 1
    assert ran >= 25
