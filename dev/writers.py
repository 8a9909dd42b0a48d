"""Every option of the command line that writes a file, each in the smallest command line that
uses it, ``OUT`` where the output goes: the one list that ``dev/hostile.py`` and
``tests/cli/test_special_outputs.py`` point at devices, FIFOs, symlinks and empty paths (a test
fails on an output option of the command line that is missing here)."""

from __future__ import annotations

__all__ = ["WRITERS", "written_option"]

WRITERS: list[list[str]] = [
    ["validate", "in.motion", "-o", "OUT"],
    ["validate", "in.motion", "-f", "sarif", "-o", "OUT"],
    ["sample", "in.motion", "-o", "OUT"],
    ["play", "in.motion", "--headless", "--json", "OUT"],
    ["play", "in.motion", "--headless", "--rrd", "OUT"],
    ["play", "in.motion", "--headless", "--bag", "OUT"],
    ["batch", "in.motion", "--no-cache", "--json", "OUT"],
    ["batch", "in.motion", "--no-cache", "--junit", "OUT"],
    ["batch", "in.motion", "--no-cache", "--markdown", "OUT"],
    ["diff", "other.motion", "in.motion", "--plot", "OUT"],
    ["plot", "in.motion", "-o", "OUT"],
    ["expect", "--infer", "in.motion", "-o", "OUT"],
    ["generate", "ur5e-jog", "-o", "OUT"],
    ["resample", "in.motion", "--step", "20", "-o", "OUT"],
    ["retime", "in.motion", "--speed", "2", "-o", "OUT"],
    ["mirror", "in.motion", "-o", "OUT"],
    ["concat", "in.motion", "other.motion", "-o", "OUT"],
    ["trim", "in.motion", "--from", "0", "--to", "80", "-o", "OUT"],
    ["scale", "in.motion", "-k", "0.5", "-o", "OUT"],
    ["robots", "export", "ur5e", "--mjcf", "OUT"],
    ["robots", "export", "ur5e", "--urdf", "OUT"],
    ["convert", "in.motion", "in.naoqi.json", "--send-script", "OUT"],
    ["convert", "in.motion", "OUT", "--to", "csv"],
    ["convert", "in.motion", "OUT", "--to", "npz"],
    ["convert", "in.motion", "OUT", "--to", "naoqi"],
    ["convert", "in.motion", "OUT", "--to", "ros-trajectory"],
    ["convert", "in.motion", "OUT", "--to", "rosbag"],
]


def written_option(line: list[str]) -> str:
    """The option of ``line`` that names ``OUT`` (``--output`` for ``-o``), or ``OUT`` for a
    positional output (``convert IN OUT``)."""
    before = line[line.index("OUT") - 1]
    if not before.startswith("-"):
        return "OUT"
    return "--output" if before == "-o" else before
