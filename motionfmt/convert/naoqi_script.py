"""The Python script written beside a NAOqi export: it reads the JSON and sends it to a NAO
with ``qi`` (the NAOqi Python SDK, Python 2.7 or 3), as ``python wave_send.py --ip 10.0.0.5``."""

from __future__ import annotations

__all__ = ["script"]

_TEMPLATE = '''#!/usr/bin/env python
# -*- coding: utf-8 -*-
"""Play {json_name} on a NAO: ALMotion.angleInterpolationBezier with the names, times (s) and
Bezier keys (rad) that motiontool convert wrote. The robot wakes up (motors on; ALMotion may
take it to its initial posture), reaches the first pose during the lead-in, then plays the
motion as Webots plays it. Needs the NAOqi Python SDK (qi).

    python {script_name} --ip 10.0.0.5 [--port 9559] [--json {json_name}]
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
    parser.add_argument("--json", default=os.path.join(here, {json_name!r}))
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


def script(json_name: str) -> str:
    """The script's text; it reads ``json_name`` beside it unless told another file."""
    stem = json_name.split(".", 1)[0]
    return _TEMPLATE.format(json_name=json_name, script_name=f"{stem}_send.py")
