"""The ``motiontool`` console script (also ``python -m motiontool.cli``): the command line of
:mod:`motiontool.cli.app`, started with the garbage collector off until the command runs
(:func:`motiontool.cli.process.start_up_uncollected`)."""

from __future__ import annotations

from motiontool.cli import process

__all__ = ["main"]


def main() -> None:
    """Run the command line as the console script does."""
    process.start_up_uncollected()
    from motiontool.cli.app import main as command_line  # after the collector is off

    command_line()


if __name__ == "__main__":
    main()
