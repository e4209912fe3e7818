"""Fitness with the paper's penalty strategy (sections 3.1, 3.2).

``Dist_m = Dist + delta * violations`` with ``delta = 2*pi*R`` (largest model
radius), and ``fitness = 10000 / (Dist_m + 1)``; higher is better.

The length and violations of a chromosome come from the scenario's turn table
(:mod:`hga_jax.model.turns`: one lookup per touched circle) when the scenario arrays
carry one for the collision mode, else from the leg-by-leg decoder
(:func:`hga_jax.model.decode.decode_batch`); both give the same values.
"""
from __future__ import annotations

from typing import Any, NamedTuple

import jax
import jax.numpy as jnp

from .decode import decode_batch, position_circles
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


def looked_up(entries, circles: int, perm, labels):
    """Length (m) and violations of a batch ``perm`` (B, n), ``labels`` (B, n + 2)
    from a turn table's ``entries`` ((C + 1) * C * (C + 1), 2) with ``circles = C``.

    A scan over the positions (batch innermost) carries the path's last two
    circles ``(a, b)``, the start point standing for ``a`` at first; each touched
    circle ``c`` (the goal circle always) adds turn ``(a, b, c)`` and moves on to
    ``(b, c)``; the goal arc is turn ``(a, goal circle, goal point)``.
    """
    c, entries = circles, jnp.asarray(entries)
    ids, touched = position_circles(perm, labels)
    batch = perm.shape[0]
    dt = entries.dtype

    def turn(a, b, nxt, on=True):
        # (B, 2): one gather per position. An untouched position reads row 0, the
        # same row for all of them: a cache hit instead of a miss (at n = 9 the
        # lookups took 2.1 instead of 3.1-3.6 ms per 50,000 chromosomes, at n = 100
        # 7.1-7.6 instead of 8.9-9.3 ms per 10,000).
        return entries[jnp.where(on, (a * c + b) * (c + 1) + nxt, 0)]

    def body(carry, xs):
        a, b, length, viol = carry
        nxt, on = xs
        row = turn(a, b, nxt, on)
        length = length + jnp.where(on, row[:, 0], 0.0)
        viol = viol + jnp.where(on, row[:, 1], 0.0)
        return (jnp.where(on, b, a), jnp.where(on, nxt, b), length, viol), None

    init = (jnp.full((batch,), c, jnp.int32), ids[0], jnp.zeros((batch,), dt),
            jnp.zeros((batch,), dt))
    (a, b, length, viol), _ = jax.lax.scan(body, init, (ids[1:], touched[1:]))
    row = turn(a, b, jnp.full((batch,), c, jnp.int32))
    return length + row[:, 0], (viol + row[:, 1]).astype(jnp.int32)


def evaluate(sa: ScenarioArrays, perm, labels, collision: str = "full") -> Evaluation:
    """Evaluate a batch ``perm`` (B, n), ``labels`` (B, n + 2). Pure, jit/vmap-able."""
    table = sa.turns_full if collision == "full" else sa.turns_paper
    if table is None:
        d = decode_batch(sa, perm, labels, collision)
        length, violations = d.length, d.violations
    else:
        length, violations = looked_up(table, sa.tangents.circles.shape[0], perm, labels)
    return Evaluation(fitness_of(length, violations, sa.delta), length, violations)
