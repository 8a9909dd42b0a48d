"""Inertia tensors (kg·m²): the PROTO tensors checked against the triangle inequality and
minimally corrected, and those of solid primitives. Stdlib only (a cyclic Jacobi eigensolver)."""

from __future__ import annotations

import math
from collections.abc import Sequence

from motiontool.kinematics._modelgen.mjcf import sig

__all__ = [
    "balanced",
    "box_inertia",
    "capsule_inertia",
    "full6",
    "quat_to_mat",
    "rotate_tensor",
]

#: Margin (kg·m²) kept above the triangle inequality when a tensor is corrected.
_TRIANGLE_MARGIN = 1e-9
#: Relative size below which a derived tensor entry is round-off and written as 0.
_RELATIVE_ZERO = 1e-9


def quat_to_mat(q: Sequence[float]) -> list[list[float]]:
    w, x, y, z = q
    n = math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return [
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ]


def rotate_tensor(rot: list[list[float]], diag: Sequence[float]) -> list[list[float]]:
    """``R diag(d) R^T``."""
    return [
        [sum(rot[i][k] * diag[k] * rot[j][k] for k in range(3)) for j in range(3)] for i in range(3)
    ]


def _sym_eig(mat: list[list[float]]) -> tuple[list[float], list[list[float]]]:
    """Eigen-decomposition of a symmetric 3x3 matrix (cyclic Jacobi; stdlib only).

    Returns ascending eigenvalues and the matrix whose columns are the eigenvectors.
    """
    a = [row[:] for row in mat]
    v = [[1.0 if i == j else 0.0 for j in range(3)] for i in range(3)]
    for _sweep in range(100):
        off = a[0][1] ** 2 + a[0][2] ** 2 + a[1][2] ** 2
        if off < 1e-40:
            break
        for p, q in ((0, 1), (0, 2), (1, 2)):
            if a[p][q] == 0.0:
                continue
            theta = (a[q][q] - a[p][p]) / (2 * a[p][q])
            t = math.copysign(1.0, theta) / (abs(theta) + math.sqrt(theta * theta + 1))
            c = 1 / math.sqrt(t * t + 1)
            s = t * c
            for k in range(3):
                akp, akq = a[k][p], a[k][q]
                a[k][p], a[k][q] = c * akp - s * akq, s * akp + c * akq
            for k in range(3):
                apk, aqk = a[p][k], a[q][k]
                a[p][k], a[q][k] = c * apk - s * aqk, s * apk + c * aqk
            for k in range(3):
                vkp, vkq = v[k][p], v[k][q]
                v[k][p], v[k][q] = c * vkp - s * vkq, s * vkp + c * vkq
    order = sorted(range(3), key=lambda i: a[i][i])
    values = [a[i][i] for i in order]
    vectors = [[v[r][i] for i in order] for r in range(3)]
    return values, vectors


def _tensor(inertia: dict[str, float]) -> list[list[float]]:
    i = inertia
    return [
        [i["ixx"], i["ixy"], i["ixz"]],
        [i["ixy"], i["iyy"], i["iyz"]],
        [i["ixz"], i["iyz"], i["izz"]],
    ]


def full6(t: list[list[float]]) -> list[float]:
    """MuJoCo ``fullinertia`` order: ixx iyy izz ixy ixz iyz; round-off (entries below
    ``_RELATIVE_ZERO`` of the largest moment) written as 0."""
    values = [t[0][0], t[1][1], t[2][2], t[0][1], t[0][2], t[1][2]]
    scale = max(abs(v) for v in values[:3])
    return [0.0 if abs(v) < _RELATIVE_ZERO * scale else v for v in values]


def balanced(inertia: dict[str, float]) -> tuple[list[float], bool]:
    """The tensor as ``fullinertia``, minimally corrected if it breaks the triangle inequality."""
    tensor = _tensor(inertia)
    values, vectors = _sym_eig(tensor)
    low, mid, high = values
    if low + mid >= high:
        return [inertia[k] for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")], False
    fixed = [high - mid + _TRIANGLE_MARGIN, mid, high]
    corrected = rotate_tensor(vectors, fixed)
    return [sig(x) for x in full6(corrected)], True


def capsule_inertia(mass: float, radius: float, half_length: float) -> tuple[float, float]:
    """Solid capsule (uniform density) moments about its centre: (perpendicular, axial)."""
    r, length = radius, 2 * half_length
    v_cyl = math.pi * r * r * length
    v_caps = 4.0 / 3.0 * math.pi * r**3
    m_cyl = mass * v_cyl / (v_cyl + v_caps)
    m_caps = mass - m_cyl
    axial = m_cyl * r * r / 2 + m_caps * 2 * r * r / 5
    perp = m_cyl * (r * r / 4 + length * length / 12) + m_caps * (
        2 * r * r / 5 + length * length / 4 + 3 * length * r / 8
    )
    return perp, axial


def box_inertia(mass: float, half: Sequence[float]) -> list[float]:
    a, b, c = (2 * h for h in half)
    return [mass / 12 * (b * b + c * c), mass / 12 * (a * a + c * c), mass / 12 * (a * a + b * b)]
