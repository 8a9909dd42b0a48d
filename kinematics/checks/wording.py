"""How the front end's user does what a check's hint tells them to do: name a robot, leave a
code out, mirror a file. The checks word their hints with a :class:`Wording` the front end
gives (the CLI: ``--robot``, ``--ignore``, ``motiontool mirror``), one object instead of a
parameter per phrase; without one the hints use plain words."""

from __future__ import annotations

from typing import NamedTuple

__all__ = ["PLAIN_WORDING", "Wording"]


class Wording(NamedTuple):
    """The front end's words for three remedies; None: plain words.

    Attributes:
        robot_option: how the user names a robot (the CLI's ``--robot``).
        ignore_option: how the user leaves a code out (the CLI's ``--ignore``).
        mirror_command: the command that mirrors a file, with ``{source}`` and ``{target}``
            (the CLI's ``motiontool mirror {source} -o {target}``).
    """

    robot_option: str | None = None
    ignore_option: str | None = None
    mirror_command: str | None = None

    def name_robot(self, which: str = "the") -> str:
        """``name the robot with --robot``, or ``name the robot explicitly`` in plain words."""
        how = f"with {self.robot_option}" if self.robot_option else "explicitly"
        return f"name {which} robot {how}"

    def ignore(self, code: str) -> str:
        """``--ignore MT309``, or ``leave MT309 out`` in plain words."""
        return f"{self.ignore_option} {code}" if self.ignore_option else f"leave {code} out"

    def mirror(self, source: str, target: str) -> str | None:
        """The command that makes ``target`` the mirror of ``source``, or None without one."""
        if not self.mirror_command:
            return None
        return self.mirror_command.format(source=source, target=target)


PLAIN_WORDING = Wording()
"""Plain words: what a library caller that gives no wording gets."""
