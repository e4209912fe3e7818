"""Moves on the ends of a reversing car's path: how it leaves the start, how it
reaches the goal.

A Reeds–Shepp chromosome (:mod:`hga_jax.model.reversing`) decides its first leg by
three genes at once: the start's label (which turning circle), the goal position's
leg gene (the gear the car starts in) and the start's leg gene (a tangent, a free
circle, a quarter turn); its last leg by two: the goal's label and the leg gene of
the last touched position. A parking manoeuvre often needs all of them changed
together (back out on the other circle into a quarter turn): one gene at a time,
every step in between is a longer path, and the search stays where it is. An end
move redraws one end's genes together, uniformly, or both ends of the direct path
(no obstacle touched), the shape of most parking manoeuvres. On development scenes
of the parking-like families (9 obstacles, 24 scenes, 50 runs each) the recommended
preset hit the optimum in 83 % of runs without end moves and 93 % with them
(``pm_ends`` 0.5). A child moved at its ends gets no path move: the path move
changes the touched obstacles of every child it takes, so with it the end move never
tried an end on the best path itself (a held-out ``wall`` scene: 10 % of runs hit
before, most after).

Operators of the ``end_mutation`` kind (:mod:`hga_jax.search.registry`) take a key,
ONE individual's positional labels and leg genes (``(n + 2,)`` int32 each) and the
number of values a leg gene takes (``values``), and return both; they jit and vmap.
How often a move applies is the GA's business (``pm_ends`` per child, after every other
move: :mod:`hga_jax.search.variation`).
"""
from __future__ import annotations

import jax
import jax.numpy as jnp
from jax import Array


def keep(key: Array, labels: Array, legs: Array, values: int) -> tuple[Array, Array]:
    """No move (``end_mutation = "none"``)."""
    return labels, legs


def redraw(key: Array, labels: Array, legs: Array, values: int) -> tuple[Array, Array]:
    """Redraw one end (the start's label, its leg gene and the gear gene, the goal
    position's; or the goal's label and the leg gene of the last touched position
    before it), 3/8 of the time each, or (1/4) both ends of the direct path: every
    obstacle untouched. Every value uniform."""
    w = jax.random.bits(key, (6,), dtype=jnp.uint32)
    last = labels.shape[0] - 1
    flip = lambda word: jnp.where((word & 1) == 1, 1, -1).astype(labels.dtype)  # noqa: E731
    gene = (w[2] % values).astype(legs.dtype)
    gear = (w[3] % values).astype(legs.dtype)
    touched = jnp.arange(last) * (labels[:last] != 0)  # the last touched before the goal
    before = jnp.max(touched)
    start = (labels.at[0].set(flip(w[1])), legs.at[0].set(gene).at[last].set(gear))
    goal = (labels.at[last].set(flip(w[1])), legs.at[before].set(gene))
    middle = jnp.zeros_like(labels).at[0].set(flip(w[1])).at[last].set(flip(w[4]))
    direct = (middle, legs.at[0].set(gene).at[last].set(gear))
    case = w[0] % 8
    pick = lambda a, b, c: jnp.where(case < 3, a, jnp.where(case < 6, b, c))  # noqa: E731
    return (pick(start[0], goal[0], direct[0]), pick(start[1], goal[1], direct[1]))
