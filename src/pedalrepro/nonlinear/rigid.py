"""Rigid-body mass algebra: one rigid part, combined and taken apart (a leaf module).

A :class:`RigidPart` is a mass (kg), its centre of mass (3,) and its central inertia tensor
(3 x 3, kg m^2), all in the benchmark frame of Meijaard et al. (2007) (x forward, z down, origin
at the rear contact). Bodies of the benchmark parameter set (``B`` rear frame + rider, ``H``
front frame) are read and written as parts with :func:`body_part` and :func:`with_body`.

Used to lump the rider, legs, cranks and arm particles into the benchmark bodies of the
non-linear models (thesis Sec 3.1.1.3) and to take them out again.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass

import numpy as np

__all__ = [
    "MIRROR_Y", "RigidPart", "point_mass", "parallel_axis", "combine", "subtract", "inertia_tensor",
    "body_part", "with_body",
]

#: Reflection in the bicycle's plane of symmetry (y -> -y).
MIRROR_Y = np.diag([1.0, -1.0, 1.0])


@dataclass(frozen=True)
class RigidPart:
    """Mass (kg), COM (3,) and central inertia (3 x 3, kg m^2) in the benchmark frame."""

    mass: float
    com: np.ndarray
    inertia: np.ndarray

    def moved(self, offset_m: np.ndarray) -> RigidPart:
        """The same part translated by ``offset_m`` (3,)."""
        return RigidPart(self.mass, self.com + np.asarray(offset_m, float), self.inertia)

    def mirrored(self) -> RigidPart:
        """The part reflected in the plane of symmetry (the other arm's hand)."""
        return RigidPart(self.mass, MIRROR_Y @ self.com, MIRROR_Y @ self.inertia @ MIRROR_Y)


def point_mass(mass_kg: float, position_m: np.ndarray) -> RigidPart:
    """A particle: mass at a point, zero central inertia."""
    return RigidPart(float(mass_kg), np.asarray(position_m, float), np.zeros((3, 3)))


def parallel_axis(mass_kg: float, offset_m: np.ndarray) -> np.ndarray:
    """Parallel-axis (Steiner) term ``m (|r|^2 I - r r^T)`` for an offset ``r``."""
    r = np.asarray(offset_m, float)
    return mass_kg * (r @ r * np.eye(3) - np.outer(r, r))


def combine(parts: Iterable[RigidPart]) -> RigidPart:
    """One part from several: total mass, common COM, central inertia (parallel axes)."""
    parts = list(parts)
    m = sum(p.mass for p in parts)
    com = sum(p.mass * p.com for p in parts) / m
    inertia = sum(p.inertia + parallel_axis(p.mass, p.com - com) for p in parts)
    return RigidPart(m, com, inertia)


def subtract(total: RigidPart, parts: Iterable[RigidPart]) -> RigidPart:
    """``total`` without ``parts`` (the inverse of :func:`combine`: combining the result with
    ``parts`` gives ``total`` back)."""
    parts = list(parts)
    m_rest = total.mass - sum(p.mass for p in parts)
    com_rest = (total.mass * total.com - sum(p.mass * p.com for p in parts)) / m_rest
    about = total.inertia + parallel_axis(total.mass, total.com - com_rest) - sum(
        p.inertia + parallel_axis(p.mass, p.com - com_rest) for p in parts)
    return RigidPart(m_rest, com_rest, about)


def inertia_tensor(bench: Mapping[str, float], body: str) -> np.ndarray:
    """Central inertia of benchmark body ``body`` (``I<body>xx`` ... ``I<body>xz``; symmetric
    about the x-z plane)."""
    i = np.zeros((3, 3))
    i[0, 0], i[1, 1], i[2, 2] = bench[f"I{body}xx"], bench[f"I{body}yy"], bench[f"I{body}zz"]
    i[0, 2] = i[2, 0] = bench.get(f"I{body}xz", 0.0)
    return i


def body_part(bench: Mapping[str, float], body: str) -> RigidPart:
    """Benchmark body ``body`` (``"B"`` or ``"H"``) as a part (``m``, ``x``, ``z``, ``I``)."""
    com = np.array([bench[f"x{body}"], bench.get(f"y{body}", 0.0), bench[f"z{body}"]])
    return RigidPart(bench[f"m{body}"], com, inertia_tensor(bench, body))


def with_body(bench: Mapping[str, float], body: str, part: RigidPart) -> dict[str, float]:
    """A copy of the benchmark parameters with body ``body`` replaced by ``part`` (the lateral
    COM offset and the ``xy``/``yz`` products are dropped: the benchmark bodies are symmetric)."""
    out = dict(bench)
    i = part.inertia
    out.update({f"m{body}": part.mass, f"x{body}": part.com[0], f"z{body}": part.com[2],
                f"I{body}xx": i[0, 0], f"I{body}yy": i[1, 1], f"I{body}zz": i[2, 2],
                f"I{body}xz": i[0, 2]})
    return out
