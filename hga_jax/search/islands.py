"""Islands: a run's population as sub-populations that select and keep their elites
apart, with a migrant from each to the next now and then.

With ``islands = K`` (> 1) the population of P is K islands of P / K consecutive
individuals (island ``k`` holds positions ``k P / K .. (k + 1) P / K - 1``). A child
at a position is made from parents of that position's island only (the selection
draws among its island), the crossovers pair neighbours (islands hold an even count
where P / K is even), and the ``elites`` best of an island's parents replace the worst
of its children. Every ``migrate_every`` generations (a generation whose number is a
multiple of it, not a restart) the best of island ``k`` replaces the worst of island
``k + 1`` (the last island's best goes to the first): a ring. Restarts stay the run's
(all islands start anew together), and so do the children that copy the parents'
best (``straight_of_best`` and the like: the run's best, into the last island).

Islands keep several ways round in one population for longer than one panmictic
population does, which converges on the first colliding path it finds; the
migrants let a better way spread, slowly (docs/results.md). ``islands = 1``:
one population, the GA as it was, bit for bit.

Pure functions of arrays, jit- and vmap-able; ``islands`` and the population size
are static, ``migrate_every`` is data (:class:`~hga_jax.search.settings.Rates`).
"""
from __future__ import annotations

from typing import Callable

import jax
import jax.numpy as jnp
from jax import Array


def per_island(fn: Callable, islands: int, *trees):
    """``fn`` applied to each island of ``trees`` (pytrees of arrays whose leading
    axis is the population, P), vmapped over the islands: the results put back on
    the population axis. ``islands = 1``: ``fn(*trees)``."""
    if islands == 1:
        return fn(*trees)

    def split(x):
        return x.reshape((islands, x.shape[0] // islands) + x.shape[1:])

    out = jax.vmap(fn)(*(jax.tree.map(split, t) for t in trees))
    return jax.tree.map(lambda x: x.reshape((x.shape[0] * x.shape[1],) + x.shape[2:]), out)


def offsets(population: int, islands: int) -> Array:
    """The first position of each island, ``(islands,)`` int32."""
    return jnp.arange(islands, dtype=jnp.int32) * (population // islands)


def select(pick: Callable[[Array, Array], Array], words: Array, fitness: Array,
           islands: int) -> Array:
    """Parents' indices into the whole population, ``(P,)``: ``pick(words, fitness)``
    (a selection's word-reading form) within each island, from that island's rows of
    ``words`` (P, ...)."""
    local = per_island(pick, islands, words, fitness)  # indices within the island
    if islands == 1:  # the island is the population: its indices are the population's
        return local
    size = fitness.shape[0] // islands
    return (local + jnp.repeat(offsets(fitness.shape[0], islands), size)).astype(jnp.int32)


def migrate(pop, fitness: Array, due, islands: int):
    """``pop`` (a pytree of arrays with the population axis first) with the best of
    each island (by ``fitness``, the first of equals) written over the worst of the
    next (the first of equals), where ``due`` (a bool, or bools of the batch's runs
    under vmap) says so; otherwise ``pop`` as it was."""
    p = fitness.shape[0]
    f = fitness.reshape(islands, p // islands)
    first = offsets(p, islands)
    best = jnp.argmax(f, axis=1).astype(jnp.int32) + first
    worst = jnp.argmin(f, axis=1).astype(jnp.int32) + first
    arriving = jnp.roll(best, 1)  # island k receives the best of island k - 1
    moved = jax.tree.map(lambda a: a.at[worst].set(a[arriving]), pop)
    return jax.tree.map(lambda a, b: jnp.where(due, a, b), moved, pop)


def due(generation, migrate_every, restart) -> Array:
    """Whether the generation ``generation`` makes takes migrants: a multiple of
    ``migrate_every`` (> 0), not a restart."""
    return (generation % jnp.maximum(migrate_every, 1) == 0) & ~restart
