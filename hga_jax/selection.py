"""Parent selection over one population.

Conventions:

- ``fitness`` is a 1-D float array of shape ``(P,)``, larger is better (the
  model's fitness ``10000 / (Dist_m + 1)`` is always positive).
- A selection returns ``count`` indices into the population (``int32``,
  shape ``(count,)``), drawn with replacement.
- All selections share the signature ``(key, fitness, count, size)``; ``count``
  and ``size`` are static (Python ints), so the functions jit and vmap over
  runs. ``size`` is the tournament size; roulette ignores it.
"""
from __future__ import annotations

from typing import Callable

import jax
import jax.numpy as jnp
from jax import Array

from .reductions import prefix_sum

from .perm_ops import uniform_int

Selection = Callable[[Array, Array, int, int], Array]


def roulette(key: Array, fitness: Array, count: int, size: int = 2) -> Array:
    """Roulette-wheel selection: index ``i`` with probability
    ``fitness[i] / sum(fitness)``, ``count`` times independently.

    ``fitness`` must be positive (zeros are never picked); ``size`` is
    ignored (it exists for the common signature).
    """
    del size
    cdf = prefix_sum(fitness)  # shape-independent rounding: run k is the same in any batch
    u = jax.random.uniform(key, (count,), dtype=cdf.dtype) * cdf[-1]
    # The first i with cdf[i] > u; the clip guards float rounding at the top.
    idx = jnp.searchsorted(cdf, u, side="right", method="compare_all")
    return jnp.minimum(idx, fitness.shape[-1] - 1).astype(jnp.int32)


def tournament(key: Array, fitness: Array, count: int, size: int = 2) -> Array:
    """Tournament selection: each of the ``count`` picks draws ``size``
    individuals uniformly with replacement and keeps the fittest; among equal
    fitness, the lower population index wins.
    """
    P = fitness.shape[-1]
    entrants = uniform_int(key, (count, size), 0, P)
    f = fitness[entrants]
    best = jnp.max(f, axis=-1, keepdims=True)
    return jnp.min(jnp.where(f == best, entrants, P), axis=-1).astype(jnp.int32)


SELECTIONS: dict[str, Selection] = {"roulette": roulette, "tournament": tournament}
