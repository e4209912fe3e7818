"""Genetic operators on the leg module of free-turn chromosomes: one gene per position.

Conventions (:mod:`hga_jax.model.cars.free_turns.legs`):

- Leg genes are a 1-D ``int32`` array of length ``L = n + 2``, positioned like the
  labels (:mod:`hga_jax.search.label_ops`): the gene of a touched position picks the
  leg from its circle to the next touched one, ``0`` a straight tangent, ``1`` or
  ``2`` a free circle of radius rho on one side or the other (a car that reverses
  has ``3`` and ``4`` too, and reads the goal's gene as the start's gear:
  :mod:`hga_jax.model.cars.reeds_shepp.reversing`). The genes of untouched positions (and the goal's,
  for the forward car) are carried but not read.
- Every value is allowed at every position (a free leg that does not exist reads
  as straight), so crossover and mutation need no repair.
- As elsewhere, operators work on ONE individual or ONE pair and jit and vmap.

The settings' names are those of :mod:`hga_jax.search.registry` (``leg_crossover``:
``two_point``, the labels' two-point crossover; ``leg_mutation``: ``redraw``).
"""
from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
from jax import Array

from .label_ops import redraw_mask, two_point  # noqa: F401  (two_point: the crossover)
from .permutation import int_from_words

GENES = 3  # values 0, 1, 2 (the forward car's; a model's gene module may have more)


def genes_from_words(words: Array, weights: tuple[int, ...]) -> Array:
    """Fresh genes from uint32 words (one per gene): value ``v`` with probability
    ``weights[v] / sum(weights)`` (a car model's
    :attr:`~hga_jax.model.car_model.GeneModule.weights`), from one integer in
    ``0 .. sum - 1`` per word."""
    k = int_from_words(words, 0, sum(weights))
    value = jnp.zeros_like(k)
    for edge in np.cumsum(weights)[:-1]:
        value = value + (k >= int(edge)).astype(k.dtype)
    return value


def legs_from_words(words: Array) -> Array:
    """Fresh leg genes from uint32 words (one per gene, last axis L): 0 with probability
    1/2, 1 and 2 with 1/4 each (weights 2, 1, 1). (Uniform genes cost hits where the
    tight rope is optimal, 91.8 % instead of 99.0 % of runs on the bundled RoboCup
    scene; straight ones a third of the hits where free turns win.)"""
    return genes_from_words(words, (2, 1, 1))


def redraw_apply(legs: Array, mask: Array, choice: Array, values: int = GENES) -> Array:
    """Change every masked gene to one of its ``values - 1`` other values (``1 + choice``
    steps along the cycle ``0 -> 1 -> ... -> values - 1 -> 0``); unmasked genes are kept."""
    new = (legs + 1 + choice.astype(legs.dtype)) % values
    return jnp.where(mask, new, legs)


def redraw_from_words(words: Array, legs: Array, pm: float | Array, values: int = GENES) -> Array:
    """:func:`redraw` of genes ``(..., L)`` from one given uint32 word per gene (the
    labels' rule: the top 24 bits against ``pm``; the choice from the lowest 8 bits,
    modulo ``values - 1``: the lowest bit for three values, the lowest two for five)."""
    # a batch with its genes first, as the labels' (label_ops.redraw_from_words)
    words, legs = jnp.moveaxis(words, -1, 0), jnp.moveaxis(legs, -1, 0)
    mask, _ = redraw_mask(words, pm)
    choice = (words & 0xFF) % (values - 1)
    return jnp.moveaxis(redraw_apply(legs, mask, choice, values), 0, -1)


def redraw(key: Array, legs: Array, pm: float | Array, values: int = GENES) -> Array:
    """Per-gene mutation: each gene, with probability ``pm``, takes one of its
    ``values - 1`` other values, uniformly."""
    return redraw_from_words(jax.random.bits(key, legs.shape[-1:], dtype=jnp.uint32), legs,
                             pm, values)

