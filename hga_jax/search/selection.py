"""Parent selection over one population.

Conventions:

- ``fitness`` is a 1-D float array of shape ``(P,)``, larger is better (the
  model's fitness ``10000 / (Dist_m + 1)`` is always positive).
- A selection returns ``count`` indices into the population (``int32``,
  shape ``(count,)``), drawn with replacement.
- All selections share the signature ``(key, fitness, count, size)``; ``count``
  and ``size`` are static (Python ints), so the functions jit and vmap over
  runs. ``size`` is the tournament size; roulette ignores it.
- The registry's form (:mod:`hga_jax.search.registry`, ``selection``) is
  ``fn(key, fitness) -> (P,)`` indices: :func:`roulette_pick`,
  :func:`tournament_pick`; the GA reads words through ``*_from_words``.
"""
from __future__ import annotations

from typing import Callable

import jax
import jax.numpy as jnp
from jax import Array

from hga_jax.model.reductions import prefix_sum

from .permutation import int_from_words
from .rng import unit

Selection = Callable[[Array, Array, int, int], Array]


def roulette(key: Array, fitness: Array, count: int, size: int = 2) -> Array:
    """Roulette-wheel selection: index ``i`` with probability
    ``fitness[i] / sum(fitness)``, ``count`` times independently.

    ``fitness`` must be positive (zeros are never picked); ``size`` is
    ignored (it exists for the common signature).
    """
    return roulette_from_words(jax.random.bits(key, (count, 1), dtype=jnp.uint32), fitness)


def roulette_from_words(words: Array, fitness: Array) -> Array:
    """:func:`roulette` with one given uint32 word per pick (``words``: (count, 1+)).

    The word's top 24 bits place the pick on the wheel (a grid of 2**-24 of the
    total fitness)."""
    cdf = prefix_sum(fitness)  # shape-independent rounding: run k is the same in any batch
    u = unit(words[:, 0], cdf.dtype) * cdf[-1]
    # The first i with cdf[i] > u; the clip guards float rounding at the top.
    idx = jnp.searchsorted(cdf, u, side="right", method="compare_all")
    return jnp.minimum(idx, fitness.shape[-1] - 1).astype(jnp.int32)


def tournament(key: Array, fitness: Array, count: int, size: int = 2) -> Array:
    """Tournament selection: each of the ``count`` picks draws ``size``
    individuals uniformly with replacement and keeps the fittest; among equal
    fitness, the lower population index wins.
    """
    return tournament_from_words(jax.random.bits(key, (count, size), dtype=jnp.uint32), fitness)


def tournament_from_words(words: Array, fitness: Array) -> Array:
    """:func:`tournament` with given uint32 words, one per entrant (``(count, size)``)."""
    P = fitness.shape[-1]
    entrants = int_from_words(words, 0, P).astype(jnp.int32)
    f = fitness[entrants]
    # Entrant by entrant (the size is small and static): a max over the last axis is a
    # reduce that XLA on the CPU ran element by element (30 of the 870 ms of CPU time of
    # the recommended preset's 1,000 runs at 9 obstacles).
    size = f.shape[-1]
    if size > 8:  # a longer unrolled chain would cost compile time
        best = jnp.max(f, axis=-1, keepdims=True)
        return jnp.min(jnp.where(f == best, entrants, P), axis=-1).astype(jnp.int32)
    best = f[..., 0]
    for k in range(1, size):
        best = jnp.maximum(best, f[..., k])
    pick = jnp.where(f[..., 0] == best, entrants[..., 0], P)
    for k in range(1, size):
        pick = jnp.minimum(pick, jnp.where(f[..., k] == best, entrants[..., k], P))
    return pick.astype(jnp.int32)


def roulette_pick(key: Array, fitness: Array) -> Array:
    """:func:`roulette` in the registry's form: one parent per individual, ``(P,)``."""
    return roulette(key, fitness, fitness.shape[-1])


def tournament_pick(key: Array, fitness: Array, tournament_size: int = 2) -> Array:
    """:func:`tournament` in the registry's form: one parent per individual, ``(P,)``."""
    return tournament(key, fitness, fitness.shape[-1], tournament_size)

