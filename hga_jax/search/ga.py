"""The hierarchical GA loop: :func:`init` and :func:`step`, and what is built from them.

Paper section 3: select, crossover and mutate the upper module (permutation),
crossover and mutate the lower module (labels), evaluate with the penalty.
Generation 0 is the random (or seeded) initial population; generations 1..G
follow, so a run evaluates ``population * (G + 1)`` chromosomes.

One loop: ``state = init(key_0, problem, settings)`` makes generation 0, then
``state = step(key_g, state)`` makes generation g. :func:`init` is :func:`step`
from the :func:`blank` state, in which every run starts anew: generation 0 and
the restarts of stalled runs are one rule, "a run that restarts takes fresh
chromosomes", so no part of a generation depends on its number being 0.
:func:`run` scans :func:`step` over the generation keys of one run,
:func:`steps` over any keys from any state (the runner's blocks of generations),
:func:`run_batch` vmaps :func:`run` over runs; :mod:`hga_jax.running.runner`
vmaps :func:`step` over a batch of runs (``axis_name=RUNS``) and scans it in
blocks. Taken whole, in blocks or in batches, a run gives the same bits.

Everything here is a pure function of arrays, a PRNG key and the static
:class:`~hga_jax.search.settings.GASettings` (carried in the state, without
arrays). Run ``k`` of seed ``s`` uses the key ``fold_in(key(s), k)`` and nothing
else, so it gives the same result alone or inside a batch of any size.
"""
from __future__ import annotations

import jax
import jax.numpy as jnp

from hga_jax.model.fitness import evaluate
from hga_jax.model.scenario import ScenarioArrays

from hga_jax.jax_compat import RUNS, any_run, fixed_stream
from . import islands
from .run_keys import generation_keys, host_generation_keys, run_indices, run_key
from .settings import GASettings
from .state import Best, GAState, Population, Record, blank, record
from .variation import _draw, _fresh, _vary, positional

__all__ = ["RUNS", "Best", "GAState", "Population", "Record", "blank", "compiled_step",
           "generation_keys", "host_generation_keys", "init", "positional", "record", "run",
           "run_batch", "run_indices", "run_key", "step", "steps"]


def _evaluated(sa, perm, labels, legs, settings) -> Population:
    sa = sa._replace(delta=sa.delta * settings.penalty_weight)  # x 1 is exact
    at = None if legs is None else positional(perm, legs, settings)
    e = evaluate(sa, perm, positional(perm, labels, settings), settings.collision, at)
    return Population(perm, labels, e.fitness, e.length, e.violations, legs)


def _update_best(best: Best, pop: Population, generation, settings: GASettings) -> Best:
    """``best`` keeps positional labels whatever the population's binding."""
    i = jnp.argmax(pop.fitness)
    better = pop.fitness[i] > best.fitness
    legs = None if pop.legs is None else positional(pop.perm[i], pop.legs[i], settings)
    cand = Best(pop.perm[i], positional(pop.perm[i], pop.labels[i], settings), pop.fitness[i],
                pop.length[i], pop.violations[i], jnp.asarray(generation, jnp.int32), legs)
    return jax.tree.map(lambda new, old: jnp.where(better, new, old), cand, best)


def _kept(pop: Population, old: Population, restart, settings: GASettings) -> Population:
    """Elitism (island by island), except in generation 0 and restarts."""
    if not settings.elites:
        return pop
    kept = islands.per_island(lambda p, o: _elitist(p, o, settings), settings.island_count, pop, old)
    return jax.tree.map(lambda a, b: jnp.where(restart, b, a), kept, pop)


def _migrated(pop: Population, generation, restart, settings: GASettings) -> Population:
    """The island ring's migrants (:mod:`hga_jax.search.islands`) where they are due."""
    if not settings.migrates:
        return pop
    due = islands.due(generation, settings.migrate_every, restart)
    return islands.migrate(pop, pop.fitness, due, settings.island_count)


def _elitist(pop: Population, old: Population, settings: GASettings) -> Population:
    """The ``elites`` (> 0) best of ``old`` replace the worst of ``pop``."""
    e = settings.elites
    elite = top_indices(old.fitness, e)
    worst = top_indices(-pop.fitness, e)
    return jax.tree.map(lambda new, prev: new.at[worst].set(prev[elite]), pop, old)


def top_indices(x, e: int):
    """The indices of the ``e`` largest entries of ``x`` (m,), largest first, ties to the
    lower index: ``jax.lax.top_k(x, e)[1]`` for values without NaN. Each entry's rank is
    counted from the m x m comparisons (vector work across the runs and islands; XLA's
    top-k of 10 fitnesses, a call per row, cost 3 % of the recommended search at 9
    obstacles)."""
    i = jnp.arange(x.shape[-1], dtype=jnp.int32)
    ahead = (x[None, :] > x[:, None]) | ((x[None, :] == x[:, None]) & (i[None, :] < i[:, None]))
    rank = jnp.sum(ahead, axis=-1, dtype=jnp.int32)  # 0 for the largest; each rank once
    return jnp.stack([jnp.sum(jnp.where(rank == r, i, 0), dtype=jnp.int32) for r in range(e)])


def _restarts(state: GAState):
    """Which runs start anew in the generation ``state`` is about to make: a blank
    run (generation 0), and, at generations R, 2R, ... (``R = restart_after``), a
    run whose best-so-far was not improved in the R generations before."""
    g = state.generation
    if not state.settings.restarts:  # structure: a batch's runs then restart together
        return g == 0
    r = state.rates.restart_after  # data
    return (g == 0) | ((g % jnp.maximum(r, 1) == 0) & (state.best.generation <= g - r))


def _restarted(words, chrom, restart, sa, settings: GASettings, colliding=False):
    """``chrom = (perm, labels, legs)`` with fresh chromosomes (:func:`_fresh`, from the
    generation's words) for a run that restarts (``colliding``: its best so far collides,
    read by ``restart_via``). Drawn only when some run of the batch restarts
    (:func:`~hga_jax.jax_compat.any_run`): at most one generation in
    ``restart_after`` (seeded fresh chromosomes cost about three generations)."""
    n = chrom[0].shape[-1]

    def fresh(old):
        return jax.tree.map(lambda f, o: jnp.where(restart, f, o),
                            _fresh(words, n, settings, sa, colliding), old)

    return jax.lax.cond(any_run(restart), fresh, lambda old: old, chrom)


@fixed_stream
def init(key, problem: ScenarioArrays, settings: GASettings) -> GAState:
    """Generation 0 of a run from its key: :func:`step` from the :func:`blank` state."""
    return step(key, blank(problem, settings))


@fixed_stream
def step(key, state: GAState) -> GAState:
    """The next generation of a run from its key: select and vary the population
    (both modules, then the path move), give the runs that restart fresh chromosomes
    instead, evaluate, keep the elites (not in a restart), send the islands' migrants
    where due, track the best. One draw
    of words serves the whole generation (see the layout above)."""
    settings, sa, g = state.settings.with_rates(state.rates), state.problem, state.generation
    words = _draw(key, sa.centres.shape[0], settings)
    restart = _restarts(state)
    pop = jax.tree.map(jnp.asarray, state.pop)  # a blank state's numpy arrays too
    chrom = jax.lax.cond(  # children, unless every run of the batch restarts
        any_run(~restart), lambda w: _vary(w, pop, settings, sa),
        lambda w: (pop.perm, pop.labels, pop.legs), words)
    colliding = state.best.violations > 0  # a blank state's best (generation 0) has none
    perm, labels, legs = _restarted(words, chrom, restart, sa, settings, colliding)
    pop = _kept(_evaluated(sa, perm, labels, legs, settings), state.pop, restart, settings)
    pop = _migrated(pop, g, restart, settings)
    best = _update_best(state.best, pop, g, settings)
    return GAState(pop, best, g + 1, sa, state.settings, state.rates)


@fixed_stream
def steps(keys, state: GAState, live=None):
    """:func:`step` once per key of ``keys`` (a leading axis) from ``state``:
    ``(state after the last, Record per step)``. ``live`` (bools, one per key, the
    same for every run of a batch) skips steps: such a step leaves the state as it
    was (the padding of a block of generations that runs past the last; a branch,
    not a select of the whole state, which cost 8% at n = 25). The scan does not
    carry ``state.problem``."""
    sa = state.problem

    def one(core, k):
        return step(k, core._replace(problem=sa))._replace(problem=None)

    def body(core, xs):
        k, on = xs
        new = one(core, k) if live is None else jax.lax.cond(on, one, lambda c, _: c, core, k)
        return new, record(new)

    on = jnp.ones(keys.shape[0], bool) if live is None else live
    core, recs = jax.lax.scan(body, state._replace(problem=None), (keys, on))
    return core._replace(problem=sa), recs


@fixed_stream
def run(key, problem: ScenarioArrays, settings: GASettings):
    """One whole run: ``(final GAState, Record of arrays shaped (G + 1,))``."""
    return steps(generation_keys(key, settings), blank(problem, settings))


compiled_step = jax.jit(step)
"""One generation as one compiled function: ``compiled_step(key, state)``."""


def run_batch(seed, ks, problem: ScenarioArrays, settings: GASettings):
    """Runs ``ks`` of ``seed`` (a sequence or 1-D integer array of run indices), vmapped:
    ``(Best, Record)`` with a leading run axis; the history is (runs, G + 1)."""
    def one(k):
        state, history = run(run_key(seed, k), problem, settings)
        return state.best, history

    return jax.vmap(one, axis_name=RUNS)(run_indices(ks))
