"""Moves on the ends of a reversing car's path: how it leaves the start, how it
reaches the goal.

A Reeds–Shepp chromosome (:mod:`hga_jax.model.cars.reeds_shepp.reversing`) decides its first leg by
three genes at once: the start's label (which turning circle), the goal position's
leg gene (the gear the car starts in) and the start's leg gene (a tangent, a free
circle, a quarter turn); its last leg by two: the goal's label and the leg gene of
the last touched position. A parking manoeuvre often needs all of them changed
together (back out on the other circle into a quarter turn): one gene at a time,
every step in between is a longer path, and the search stays where it is. An end
move redraws one end's genes together, uniformly, or both ends of the direct path
(no obstacle touched), the shape of most parking manoeuvres. On development scenes
of the parking-like families (9 obstacles, 24 scenes, 50 runs each) the recommended
preset hit the optimum in 77 % of runs without end moves and 94-95 % with them
(``pm_ends`` 0.5, two draws of the move; 93 % at 0.3 and 94 % at 0.7). A child moved at its ends gets no path move: the path move
changes the touched obstacles of every child it takes, so with it the end move never
tried an end on the best path itself (a held-out ``wall`` scene: 10 % of runs hit
before, most after).

Operators of the ``end_mutation`` kind (:mod:`hga_jax.search.registry`) take a key,
ONE individual's positional labels and leg genes (``(n + 2,)`` int32 each) and the
number of values a leg gene takes (``values``), and return both; they jit and vmap.
How often a move applies is the GA's business (``pm_ends`` per child, after every other
move, and on ``ends_of_best`` copies of the parents' best per generation:
:mod:`hga_jax.search.variation`).
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
    obstacle untouched. Every value uniform; two words of ``key`` decide
    (:func:`redraw_from_words`)."""
    w = jax.random.bits(key, (2,), dtype=jnp.uint32)
    return redraw_from_words(w[0], w[1], labels, legs, values)


def redraw_from_words(w1: Array, w2: Array, labels: Array, legs: Array,
                      values: int) -> tuple[Array, Array]:
    """:func:`redraw` from two uint32 words: the case from bits 0-2 of ``w1``, the two
    labels from bits 3 and 4, the leg gene from its bits 8-31 and the gear gene from
    ``w2``'s (as :func:`hga_jax.search.leg_ops.redraw_from_words`, modulo ``values``).
    ``w1``, ``w2`` scalars or one per individual (then ``labels``, ``legs`` (P, L))."""
    last = labels.shape[-1] - 1
    w1, w2 = w1[..., None], w2[..., None]

    def sign(bit):
        return jnp.where(((w1 >> bit) & 1) == 1, 1, -1).astype(labels.dtype)

    gene = ((w1 >> 8) % values).astype(legs.dtype)
    gear = ((w2 >> 8) % values).astype(legs.dtype)
    pos = jnp.arange(labels.shape[-1])
    # the last touched position before the goal (the start's, 0, when none is)
    before = jnp.max(jnp.where((labels != 0) & (pos < last), pos, 0), axis=-1, keepdims=True)
    start = (jnp.where(pos == 0, sign(3), labels),
             jnp.where(pos == 0, gene, jnp.where(pos == last, gear, legs)))
    goal = (jnp.where(pos == last, sign(3), labels), jnp.where(pos == before, gene, legs))
    direct = (jnp.where(pos == 0, sign(3), jnp.where(pos == last, sign(4), 0)).astype(labels.dtype)
              + 0 * labels, start[1])
    case = w1 & 7
    pick = lambda a, b, c: jnp.where(case < 3, a, jnp.where(case < 6, b, c))  # noqa: E731
    return pick(start[0], goal[0], direct[0]), pick(start[1], goal[1], direct[1])
