"""Generate the built-in robot models from the robot data JSON (the single source of truth).

Usage (from the repository root; ``<robots-dir>`` is the folder of the robot facts, e.g. the copy
vendored in ``tests/data/robot_facts``)::

    python -m motiontool.kinematics._modelgen <robots-dir> kinematics/models
    python -m motiontool.kinematics._modelgen <robots-dir> kinematics/models --check

It reads ``nao.json`` and ``ur5e.json`` (numbers transcribed from the Webots PROTO files) and
writes ``nao.xml`` and ``ur5e.xml`` (MJCF, loadable by MuJoCo and by Pinocchio's MJCF reader) and
``nao-v5.json`` (the real NAO V5's limits, applied on top of ``nao.xml`` by
:mod:`motiontool.kinematics.robots`). The output is deterministic: the same JSON gives the same
bytes, which a test checks against the committed files.

Modelling choices (also written into each file's header comment):

* Joint names are the Webots motor names; each joint carries ``range`` (the motor's soft limits
  ``minPosition``/``maxPosition``, rad) and ``actuatorfrcrange`` (``±maxTorque``, N·m).
* ``maxVelocity`` lives in one MuJoCo ``velocity`` actuator per motor, named like its joint:
  ``ctrlrange = ±maxVelocity`` (rad/s) and ``forcerange = ±maxTorque`` (N·m). A plain XML reader
  finds both limits there and on the joint; MuJoCo compiles them as a usable (if simple) motor.
* Inertias are the PROTO tensors (about the centre of mass, body axes). The two upper-arm tensors
  violate the triangle inequality; the smallest principal moment is raised just enough to satisfy
  it (a minimal correction, so MuJoCo and Pinocchio see the same physical tensor) and the
  original PROTO values are kept in a comment next to it.
* The three massless helper frames of the Webots ``Hinge2Joint``s (``neck_virtual``,
  ``*_shoulder_virtual``) get a negligible mass (``_VIRTUAL_MASS``) so MuJoCo accepts them.
* The foot force sensors ``LFsr``/``RFsr`` are jointless child bodies of the feet (MuJoCo welds
  them, Pinocchio merges them into the ankle-roll body) carrying their 0.08057 kg and the
  0.147 x 0.089 x 0.01 m box that touches the floor.

May import the rest of ``kinematics`` and the standard library; a build-time tool that no
library module imports and the wheel does not ship.
"""

from motiontool.kinematics._modelgen.main import generate, main

__all__ = ["generate", "main"]
