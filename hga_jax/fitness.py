"""Fitness with the paper's penalty strategy (sections 3.1, 3.2).

``Dist_m = Dist + delta * violations`` with ``delta = 2*pi*R`` (largest model
radius), and ``fitness = 10000 / (Dist_m + 1)``; higher is better.
"""
from __future__ import annotations

from typing import Any, NamedTuple

from .decode import decode_batch
from .scenario import ScenarioArrays

FITNESS_CONST = 10000.0


class Evaluation(NamedTuple):
    """Per chromosome: fitness, path length (m) and violation count."""

    fitness: Any
    length: Any
    violations: Any


def penalised_length(length, violations, delta):
    """``Dist_m``: the length plus ``delta`` metres per violation."""
    return length + delta * violations


def fitness_of(length, violations, delta):
    """``10000 / (Dist_m + 1)``."""
    return FITNESS_CONST / (penalised_length(length, violations, delta) + 1.0)


def length_of_fitness(fitness):
    """Inverse of :func:`fitness_of` for a feasible path: the length (m)."""
    return FITNESS_CONST / fitness - 1.0


def evaluate(sa: ScenarioArrays, perm, labels, collision: str = "full") -> Evaluation:
    """Evaluate a batch ``perm`` (B, n), ``labels`` (B, n + 2). Pure, jit/vmap-able."""
    d = decode_batch(sa, perm, labels, collision)
    return Evaluation(fitness_of(d.length, d.violations, sa.delta), d.length, d.violations)
