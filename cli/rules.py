"""Every diagnostic code explained, one :class:`~motiontool.cli.rule_model.Rule` each: the one
home of what ``motiontool rule CODE`` prints and of SARIF's rule help (MT1xx
:mod:`.rules_syntax`, MT2xx :mod:`.rules_traps`, MT3xx and MT9xx :mod:`.rules_robot`). They live
in the CLI: the examples are ``validate`` command lines and the fixes name commands."""

from __future__ import annotations

import difflib

from motiontool.cli.rule_model import Example, Rule
from motiontool.cli.rules_robot import ROBOT_RULES
from motiontool.cli.rules_syntax import SYNTAX_RULES
from motiontool.cli.rules_traps import TRAP_RULES
from motiontool.errors import MotionToolError
from motiontool.motionfmt.diagnostics import CODES

__all__ = ["RULES", "Example", "Rule", "UnknownCodeError", "rule"]

RULES: dict[str, Rule] = {
    r.code: r for r in sorted((*SYNTAX_RULES, *TRAP_RULES, *ROBOT_RULES), key=lambda r: r.code)
}
"""Every code's explanation, by code, in the order of :data:`CODES`."""


class UnknownCodeError(MotionToolError):
    """A code that is not one of :data:`CODES`; the message has a did-you-mean."""


def rule(code: str) -> Rule:
    """The explanation of ``code`` (any case, spaces around it ignored).

    Raises:
        UnknownCodeError: ``unknown code 'MT33'; did you mean 'MT303'?``
    """
    key = code.strip().upper()
    if key in RULES:
        return RULES[key]
    close = difflib.get_close_matches(key, list(CODES), n=1)
    hint = f"; did you mean '{close[0]}'?" if close else "; 'motiontool rule' lists them"
    raise UnknownCodeError(f"unknown code '{code}'{hint}")
