"""The Python script written beside a NAOqi export (or where ``--send-script`` names it): it
reads the JSON and sends it to a NAO with ``qi`` (the NAOqi Python SDK, Python 2.7 or 3), as
``python wave_send.py --ip 10.0.0.5``."""

from __future__ import annotations

__all__ = ["SCRIPT_SUFFIX", "script"]

SCRIPT_SUFFIX = "_send.py"
"""The script's name beside ``wave.naoqi.json``: the JSON's name up to its first dot, then
this (``wave_send.py``)."""

_TEMPLATE = '''#!/usr/bin/env python
# -*- coding: utf-8 -*-
"""Play {json_name} on a NAO: ALMotion.angleInterpolationBezier with the names, times (s) and
Bezier keys (rad) that motiontool convert wrote. The robot wakes up (motors on; ALMotion may
take it to its initial posture), reaches the first pose during the lead-in, then plays the
motion as Webots plays it. Needs the NAOqi Python SDK (qi).

    python {script_name} --ip 10.0.0.5 [--port 9559] {json_usage}
"""

import argparse
import json
import os

import qi


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description="Play a motion on a NAO.")
    parser.add_argument("--ip", required=True, help="the robot's IP address")
    parser.add_argument("--port", type=int, default=9559, help="NAOqi's port")
    {json_option}
    args = parser.parse_args()
    with open(args.json) as f:
        doc = json.load(f)
    session = qi.Session()
    session.connect("tcp://%s:%d" % (args.ip, args.port))
    motion = session.service("ALMotion")
    motion.wakeUp()
    motion.angleInterpolationBezier(doc["names"], doc["times"], doc["keys"])


if __name__ == "__main__":
    main()
'''


def script(json_path: str | None, script_name: str | None = None) -> str:
    """The script's text. It reads ``json_path`` (a path from the script's own folder) unless
    told another file with ``--json``; with None (the JSON went to standard output or a
    device) ``--json`` is required. ``script_name``: its own name, for its usage line
    (default: the JSON's name up to its first dot, then :data:`SCRIPT_SUFFIX`)."""
    if json_path is None:
        option = 'parser.add_argument("--json", required=True, help="the JSON to play")'
        return _TEMPLATE.format(
            json_name="the JSON motiontool convert wrote",
            script_name=script_name or f"motion{SCRIPT_SUFFIX}",
            json_usage="--json FILE.naoqi.json",
            json_option=option,
        )
    name = json_path.replace("\\", "/").rsplit("/", 1)[-1]
    option = f'parser.add_argument("--json", default=os.path.join(here, {json_path!r}))'
    return _TEMPLATE.format(
        json_name=name,
        script_name=script_name or name.split(".", 1)[0] + SCRIPT_SUFFIX,
        json_usage=f"[--json {name}]",
        json_option=option,
    )
