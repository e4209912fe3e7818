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

from .cars.reeds_shepp import reversing as reversing_rule
from .in_time import windows
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


def looked_up(entries, circles: int, perm, labels, legs=None, variants: int = 3,
              reversing: bool = False):
    """Length (m) and violations of a batch ``perm`` (B, n), ``labels`` (B, n + 2)
    from a turn table's ``entries`` ((V C + 1) * C * (V C + 1), 2) with ``circles = C``.

    A scan over the positions (batch innermost) carries the leg that arrived on the
    path's last circle ``b`` (``i = v_a C + a``, the start point standing for it at
    first) and ``b``; each touched circle ``c`` (the goal circle always) adds turn
    ``(i, b, v_b C + c)`` and moves on; the goal arc is turn ``(i, goal circle, goal
    point)``. ``legs`` (B, n + 2), positional: the leg genes of free turns
    (:mod:`hga_jax.model.cars.free_turns.legs`), ``V = variants``; without them ``V = 1``, the
    tight rope. ``reversing``: the genes are a reversing car's, whose start and goal
    circles follow its gears (:mod:`hga_jax.model.cars.reeds_shepp.reversing`): the scan also carries
    the gear changes so far.
    """
    c, entries = circles, jnp.asarray(entries)
    timed = entries.shape[1] > 2  # a table among robots that move (hga_jax.model.in_time.windows)
    ids, touched = position_circles(perm, labels)
    batch = perm.shape[0]
    dt = entries.dtype
    rows = c if legs is None else variants * c  # V C: the start point's row, the goal point's column
    genes = None if legs is None else legs.T.astype(jnp.int32)  # (S, B)
    if reversing:
        lab = labels.T.astype(jnp.int32)
        back = reversing_rule.start_backward(genes[-1])
        ids = ids.at[0].add(reversing_rule.offset(c) * back.astype(ids.dtype))
        last = jnp.arange(ids.shape[0] - 1) == ids.shape[0] - 2  # the goal's step

    def turn(i, b, d, on=True):
        # (B, 2): one gather per position. An untouched position reads row 0, the
        # same row for all of them: a cache hit instead of a miss (at n = 9 the
        # lookups took 2.1 instead of 3.1-3.6 ms per 50,000 chromosomes, at n = 100
        # 7.1-7.6 instead of 8.9-9.3 ms per 10,000).
        return entries[jnp.where(on, (i * c + b) * (rows + 1) + d, 0)]

    def body(carry, xs):
        i, b, vb, length, viol, gear = carry
        nxt, on, vn, ln, goal = xs
        if gear is not None:  # the goal circle of the gear the path arrives in
            lb, odd = gear
            first = i == rows  # the leg leaves the start
            odd = odd ^ (on & reversing_rule.odd_leg(vb, lb, ln, first, goal))
            nxt = nxt + reversing_rule.offset(c) * (goal & (odd ^ back)).astype(nxt.dtype)
            gear = (jnp.where(on, ln, lb), odd)
        row = turn(i, b, nxt if vb is None else vb * c + nxt, on)
        if timed:  # the windows in time hold the metres driven on arrival
            viol = viol + jnp.where(on, windows.hits(row[:, 2:], length), 0)
        length = length + jnp.where(on, row[:, 0], 0.0)
        viol = viol + jnp.where(on, row[:, 1], 0.0)
        i = jnp.where(on, b if vb is None else vb * c + b, i)
        vb = None if vb is None else jnp.where(on, vn, vb)
        return (i, jnp.where(on, nxt, b), vb, length, viol, gear), None

    gear0 = (lab[0], jnp.zeros((batch,), bool)) if reversing else None
    init = (jnp.full((batch,), rows, jnp.int32), ids[0], None if genes is None else genes[0],
            jnp.zeros((batch,), dt), jnp.zeros((batch,), dt), gear0)
    xs = (ids[1:], touched[1:], None if genes is None else genes[1:],
          lab[1:] if reversing else None, last if reversing else None)
    (i, b, _, length, viol, _), _ = jax.lax.scan(body, init, xs)
    row = turn(i, b, jnp.full((batch,), rows, jnp.int32))
    if timed:
        viol = viol + windows.hits(row[:, 2:], length)
    return length + row[:, 0], (viol + row[:, 1]).astype(jnp.int32)


def turn_table(sa: ScenarioArrays, collision: str = "full", genes: bool = False):
    """``(table, reversing)``: the turn table :func:`evaluate` reads for chromosomes with
    leg genes (``genes``) or without, None where it decodes leg by leg; and whether the
    legs are a reversing car's (their cusps counted). Among robots that move a table
    carries each turn's windows in time (:mod:`hga_jax.model.in_time.windows`); without one
    the decoder runs the tests in time (:mod:`hga_jax.model.in_time.clearance`)."""
    if genes:
        return sa.turns_free, sa.free_legs is not None and sa.free_legs.cusps is not None
    return (sa.turns_full if collision == "full" else sa.turns_paper), False


def present_labels(sa: ScenarioArrays, perm, labels):
    """Positional ``labels`` (B, n + 2) with 0 wherever the position's obstacle is not there
    (``sa.present``, a frame padded to a bound: :mod:`hga_jax.loop`); unchanged without."""
    if sa.present is None:
        return labels
    n = perm.shape[-1]
    there = jnp.take(jnp.asarray(sa.present), perm)
    return jnp.concatenate([labels[:, :1], jnp.where(there, labels[:, 1:n + 1], 0),
                            labels[:, n + 1:]], axis=1)


def evaluate(sa: ScenarioArrays, perm, labels, collision: str = "full", legs=None) -> Evaluation:
    """Evaluate a batch ``perm`` (B, n), ``labels`` (B, n + 2) (and, under free turns,
    positional leg genes ``legs`` (B, n + 2), the full rule only). Pure, jit/vmap-able."""
    labels = present_labels(sa, perm, labels)
    table, reversing = turn_table(sa, collision, legs is not None)
    if table is None:
        d = decode_batch(sa, perm, labels, collision, legs)
        length, violations = d.length, d.violations
    else:
        variants = 1 if legs is None else sa.free_legs.p1x.shape[0]
        length, violations = looked_up(table, sa.tangents.circles.shape[0], perm, labels, legs,
                                       variants, reversing)
    return Evaluation(fitness_of(length, violations, sa.delta), length, violations)
