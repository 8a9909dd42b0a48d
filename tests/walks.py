"""Random walks of a robot's configurations, for the collision scan's tests."""

from __future__ import annotations

import math

import numpy as np

from motiontool.kinematics import load_robot


def random_walk(robot: str, n: int, step: float, seed: int) -> np.ndarray:
    """A random walk of ``n`` configurations within the limits, ``step`` rad at most a motor
    and a step, from a random start."""
    spec = load_robot(robot)
    lo = np.array([max(j.lower, -math.pi) for j in spec.joints])
    hi = np.array([min(j.upper, math.pi) for j in spec.joints])
    rng = np.random.default_rng(seed)
    start = lo + (hi - lo) * rng.random(lo.shape[0])
    steps = rng.uniform(-step, step, (n, lo.shape[0]))
    return np.clip(start + np.cumsum(steps, axis=0), lo, hi)
