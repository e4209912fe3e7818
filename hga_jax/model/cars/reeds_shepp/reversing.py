"""Gears of a reversing car's chromosome: the one rule that says where it drives backward.

A Reeds–Shepp chromosome (:mod:`hga_jax.model.cars.reeds_shepp.legs`) is a free-turn one
whose leg genes take seven values: ``0`` a tangent, ``1``/``2`` a free circle turning
against the circle the leg leaves (on one side or the other), ``3``/``4`` the same
free circle turning the same way as that circle, ``5`` on the leg that leaves the
start a *quarter turn* (a free circle met at a cusp on the start circle, turned a
quarter of a turn, left along a tangent), ``6`` on the leg that reaches the goal the
same driven the other way (elsewhere ``5`` and ``6`` read as ``0``). Where a free
circle turns the same way as a circle it touches, the car stops there and changes
gear (a cusp), so a leg between circles of opposite senses with a gene from 1 to 4
has one cusp, between circles of one sense none or two, and a quarter turn one. Its
*parity* (:func:`odd_leg`) follows from the genes, the labels and the leg's place
alone; a leg gene whose free circle does not exist reads as a tangent, and where it
promised an odd parity the leg table counts a violation.

- The gear at the start: backward when the goal position's gene (which no leg reads)
  is :data:`BACKWARD` or more (:func:`start_backward`).
- The gear at the goal: the start's, changed by every leg of odd parity; the path
  arrives on the goal circle of its label in that gear.

Circles: a reversing car adds, after the scenario's ``C = 2n + 4``, the four pose
circles travelled backward, ``C + k`` for pose circle ``k`` (start CCW, start CW, goal
CCW, goal CW, by their sense of travel): the car's other turning circle at that pose
(:func:`hga_jax.model.cars.reeds_shepp.legs.circles`). A pose circle's backward twin is its
id plus :func:`offset`. Pure functions of arrays (JAX, jit/vmap-able; :func:`odd_leg`
also of numbers and numpy arrays).
"""
from __future__ import annotations

from hga_jax.model import circle_ids

BACKWARD = 3
"""A goal-position gene of at least this value starts the path backward."""
LEAVING, ARRIVING = 5, 6
"""The genes of a quarter turn on the leg that leaves the start, and on the one that
reaches the goal."""


def offset(circles: int) -> int:
    """What a forward pose circle's id adds to become its backward twin, among
    ``circles`` (``C + 4``) circles: ``C``."""
    return circles - circle_ids.POSES


def start_backward(goal_gene):
    """Whether the path leaves the start driven backward: the goal position's gene."""
    return goal_gene >= BACKWARD


def odd_leg(gene, sense_from, sense_to, first, last):
    """Whether the leg with ``gene`` between circles of these senses changes gear an
    odd number of times (once): a free circle between circles of opposite senses, a
    quarter turn on the ``first`` leg (it leaves the start) or the ``last`` (it reaches
    the goal)."""
    return (((gene >= 1) & (gene < LEAVING) & (sense_from != sense_to))
            | ((gene == LEAVING) & first) | ((gene == ARRIVING) & last))


def compacted(ids, genes, count, senses, goal_gene, circles: int):
    """The path's circles (``ids`` (S, B), compacted as the decoder holds them, slots
    ``0 .. count - 1``) with the start and goal circles in their gears; ``genes`` (S, B)
    the slots' leg genes, ``senses`` the sense of every circle id, ``goal_gene`` (B,)
    the goal position's gene. Returns ``(ids, gears)``: gears (B, 2) bool, backward at
    the start and at the goal."""
    import jax.numpy as jnp

    s = ids.shape[0]
    sense = senses[ids]
    legs = jnp.arange(s - 1)[:, None]
    real = legs < (count - 1)[None]
    odd = odd_leg(genes[:-1], sense[:-1], sense[1:], legs == 0, legs == (count - 2)[None]) & real
    back0 = start_backward(goal_gene)
    back1 = back0 ^ (jnp.sum(odd, axis=0) % 2 == 1)
    slots = jnp.arange(s)[:, None]
    shift = ((slots == 0) & back0[None]) | ((slots == (count - 1)[None]) & back1[None])
    return ids + offset(circles) * shift.astype(ids.dtype), jnp.stack([back0, back1], axis=-1)
