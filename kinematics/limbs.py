"""Which limb a motor belongs to: the one grouping of joints that plots, Rerun recordings and
``play`` reports share.

Names, not models, decide where they can: the Webots Nao's motors by its naming scheme (``Head``,
``LArm``, ``RArm``, ``LLeg``, ``RLeg``, ``LHand``, ``RHand``), a serial arm's by the words
industrial arms use (``shoulder``/``elbow``/``upper_arm``/``forearm`` joints form the ``arm``,
``wrist`` joints the ``wrist``, ``finger``/``gripper`` joints the ``gripper``: the UR5e's
``shoulder_pan_joint`` to ``elbow_joint`` and ``wrist_1_joint`` to ``wrist_3_joint``). Any other
name takes the caller's fallback: the branch of the kinematic tree it hangs on where the caller
has the tree (the simulation), else one shared group.
"""

from __future__ import annotations

import re

__all__ = ["NAO_LIMBS", "limb_of"]

NAO_LIMBS = ("Head", "LArm", "RArm", "LLeg", "RLeg", "LHand", "RHand")
"""The Webots Nao's limbs, in the order plots show them."""

_RULES = (
    (re.compile(r"^Head"), "Head"),
    (re.compile(r"^([LR])(Hand|Phalanx\d*)$"), r"\1Hand"),
    (re.compile(r"^([LR])(Shoulder|Elbow|Wrist)"), r"\1Arm"),
    (re.compile(r"^([LR])(Hip|Knee|Ankle)"), r"\1Leg"),
    (re.compile(r"wrist", re.IGNORECASE), "wrist"),
    (re.compile(r"finger|gripper", re.IGNORECASE), "gripper"),
    (re.compile(r"shoulder|elbow|upper_?arm|fore_?arm", re.IGNORECASE), "arm"),
)


def limb_of(joint: str, fallback: str = "other") -> str:
    """The limb of the motor called ``joint``; ``fallback`` when its name does not say.

    >>> [limb_of(j) for j in ("LElbowRoll", "RPhalanx3", "elbow_joint", "wrist_2_joint")]
    ['LArm', 'RHand', 'arm', 'wrist']
    """
    for pattern, limb in _RULES:
        found = pattern.search(joint)
        if found:
            return found.expand(limb)
    return fallback
