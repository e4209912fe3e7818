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

from typing import Any, NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from hga_jax.search import label_ops, path_ops, permutation, registry, rng
from hga_jax.model.fitness import evaluate
from hga_jax.model.reductions import tree_sum
from hga_jax.model.scenario import ScenarioArrays
from .jax_compat import RUNS, any_run, fixed_stream, static_pytree
from .settings import GASettings


class Population(NamedTuple):
    """A population of P chromosomes with their evaluation."""

    perm: Any  # (P, n) int32
    labels: Any  # (P, n + 2) int32
    fitness: Any  # (P,)
    length: Any  # (P,) metres, without penalty
    violations: Any  # (P,) int32


class Best(NamedTuple):
    """Best-so-far individual of a run and the generation it was first reached."""

    perm: Any  # (n,)
    labels: Any  # (n + 2,)
    fitness: Any  # ()
    length: Any  # () metres
    violations: Any  # ()
    generation: Any  # () int32


static_pytree(GASettings)  # settings ride in the state as static data


class GAState(NamedTuple):
    """A run between two generations. ``problem`` is None inside programs that pass
    the scenario's arrays apart (the runner's blocks), so they are not carried."""

    pop: Population
    best: Best
    generation: Any  # () int32: generations made so far, so the number of the next one
    problem: Any  # ScenarioArrays (float32 or float64, with legs if the settings use them)
    settings: GASettings  # static


class Record(NamedTuple):
    """What a run records per generation."""

    best_fitness: Any  # best fitness in this generation's population
    mean_fitness: Any  # mean fitness of this generation's population
    best_so_far_fitness: Any
    best_so_far_length: Any  # metres, without penalty
    best_so_far_violations: Any


@fixed_stream
def run_key(seed: int, k):
    """The PRNG key of run ``k`` of ``seed``: ``fold_in(key(seed), k)`` of JAX's default
    threefry2x32 stream, as a key of :mod:`hga_jax.search.rng` (the same numbers, faster)."""
    return jax.random.fold_in(rng.key(seed), k)


def positional(perm, labels, settings: GASettings):
    """Labels in the decoder's (positional) order. With ``label_binding = "obstacle"``
    the population stores label ``1 + i`` for obstacle ``i``; positions take
    ``labels[1 + perm[k]]``."""
    if settings.label_binding == "position" or perm.shape[-1] == 0:
        return labels
    middle = jnp.take_along_axis(labels[..., 1:-1], perm, axis=-1)
    return jnp.concatenate([labels[..., :1], middle, labels[..., -1:]], axis=-1)


def bound(perm, labels, settings: GASettings):
    """Inverse of :func:`positional`: positional labels in the population's binding."""
    if settings.label_binding == "position" or perm.shape[-1] == 0:
        return labels
    middle = jnp.zeros_like(labels[..., 1:-1])
    middle = jax.vmap(lambda m, p, l: m.at[p].set(l))(
        middle.reshape(-1, middle.shape[-1]), perm.reshape(-1, perm.shape[-1]),
        labels[..., 1:-1].reshape(-1, middle.shape[-1])).reshape(middle.shape)
    return jnp.concatenate([labels[..., :1], middle, labels[..., -1:]], axis=-1)


def _legs(sa: ScenarioArrays):
    if sa.legs is None:
        raise ValueError("these settings use path moves or seeding: pass scenario arrays "
                         "from Scenario.search_arrays(..., with_legs=True)")
    return sa.legs


def _evaluated(sa, perm, labels, settings) -> Population:
    if settings.penalty_weight != 1.0:
        sa = sa._replace(delta=sa.delta * settings.penalty_weight)
    e = evaluate(sa, perm, positional(perm, labels, settings), settings.collision)
    return Population(perm, labels, e.fitness, e.length, e.violations)


def _update_best(best: Best, pop: Population, generation, settings: GASettings) -> Best:
    """``best`` keeps positional labels whatever the population's binding."""
    i = jnp.argmax(pop.fitness)
    better = pop.fitness[i] > best.fitness
    cand = Best(pop.perm[i], positional(pop.perm[i], pop.labels[i], settings), pop.fitness[i],
                pop.length[i], pop.violations[i], jnp.asarray(generation, jnp.int32))
    return jax.tree.map(lambda new, old: jnp.where(better, new, old), cand, best)


def record(state: GAState) -> Record:
    """What a run records of the generation ``state`` holds (the history's row)."""
    pop, best = state.pop, state.best
    mean = tree_sum(pop.fitness) / pop.fitness.shape[-1]
    return Record(jnp.max(pop.fitness), mean, best.fitness, best.length, best.violations)


# --- One draw of random words per generation ----------------------------------------
#
# Generation g of a run draws ``bits(key_g, (draw_rows(n, settings), P))`` once (P the
# population, innermost) and every part of the generation reads its own rows:
# generation 0 the words of its permutations (n rows) and labels (n + 2 rows); a later
# generation its selection's words (built-ins: 1 row, or ``tournament_size``), then a
# do-word and two key words per pair (crossovers) or individual (mutations), then the
# label mutation's words (the built-in redraw: one word per label gene). Pair rows use
# their first P // 2 columns. Operators without a word-reading form (registry.Operator)
# take keys, made from two words each (selection: one key per run, from column 0).

def _word_rows(kind: str, n: int, settings: GASettings) -> int:
    """Rows of words the operator of ``kind`` chosen by ``settings`` reads: a built-in's
    own count (registry ``rows``), else the two of its keys."""
    op = registry.entry(kind, getattr(settings, kind))
    return op.rows(n, settings) if op.from_words is not None else 2


def _layout(n: int, settings: GASettings) -> dict[str, tuple[int, int]]:
    """``name -> (first row, rows)`` of a later generation's draw."""
    parts = (("select", _word_rows("selection", n, settings)),
             ("cross_upper", 3), ("mutate_upper", 3), ("cross_lower", 3),
             ("mutate_lower", _word_rows("label_mutation", n, settings)))
    if settings.path_mutation != "none":
        parts += (("mutate_path", 3),)
    out, row = {}, 0
    for name, rows in parts:
        out[name], row = (row, rows), row + rows
    return out


def draw_rows(n: int, settings: GASettings) -> int:
    """Rows of words (of P each) every generation draws: enough for generation 0
    (``2n + 2``, and 2 more with seeding) and for the later ones."""
    last = max(start + rows for start, rows in _layout(n, settings).values())
    return max(2 * n + 2 + (2 if settings.seeding > 0 else 0), last)


def _draw(key, n: int, settings: GASettings):
    return jax.random.bits(key, (draw_rows(n, settings), settings.population), dtype=jnp.uint32)


unit = rng.unit  # floats uniform on k / 2**24 from words (the one rule, in rng)


def _keys(rows):
    """Keys (of :mod:`hga_jax.search.rng`) from two rows of words: ``(count,)`` keys."""
    return jax.random.wrap_key_data(jnp.stack([rows[0], rows[1]], axis=-1), impl=rng.IMPL)


def _fresh(words, n: int, settings: GASettings | None = None, sa: ScenarioArrays | None = None):
    """Generation 0's chromosomes from its words: random permutations and labels; with
    ``seeding``, the first ``round(seeding * P)`` are then built by
    :func:`hga_jax.search.path_ops.wrap_blockers` from their start and goal labels (keys
    from rows ``2n + 2`` and ``2n + 3``)."""
    perm = permutation.permutation_from_words(words[:n].T)
    labels = label_ops.labels_from_words(words[n:2 * n + 2].T)
    if settings is None or settings.seeding <= 0 or n == 0:
        return perm, labels
    seeded = int(round(settings.seeding * perm.shape[0]))
    legs = _legs(sa)
    keys = _keys(words[2 * n + 2:2 * n + 4, :seeded])
    pos = positional(perm[:seeded], labels[:seeded], settings)
    sp, sl = jax.vmap(lambda k, p, l: path_ops.wrap_blockers(k, p, l, legs))(keys, perm[:seeded],
                                                                           pos)
    sl = bound(sp, sl, settings)
    return perm.at[:seeded].set(sp), labels.at[:seeded].set(sl)


def _pairwise(rows, op, prob, a, b):
    """Apply the pair operator ``op`` to each pair (a[i], b[i]) with probability ``prob``;
    ``rows`` (3, >= pairs): the do-word and the two key words of each pair."""
    m = a.shape[0]
    ca, cb = jax.vmap(op)(_keys(rows[1:, :m]), a, b)
    do = (unit(rows[0, :m]) < prob)[:, None]
    return jnp.where(do, ca, a), jnp.where(do, cb, b)


def _crossover(rows, op, prob, x):
    """Pair consecutive rows (0,1), (2,3), ...; an odd last row passes unchanged."""
    half = x.shape[0] // 2
    a, b = _pairwise(rows, op, prob, x[0:2 * half:2], x[1:2 * half:2])
    paired = jnp.stack([a, b], axis=1).reshape((2 * half,) + x.shape[1:])
    return jnp.concatenate([paired, x[2 * half:]])


def _vary(words, old: Population, settings: GASettings, sa: ScenarioArrays | None = None):
    """Select parents from ``old`` and vary both modules: the children's chromosomes,
    from the generation's words (see the layout above)."""
    n = old.perm.shape[1]
    at = _layout(n, settings)

    def rows(name):
        start, count = at[name]
        return words[start:start + count]

    sel = registry.entry("selection", settings.selection)
    if sel.from_words is not None:
        idx = sel.from_words(rows("select").T, old.fitness)
    else:
        idx = sel.fn(_keys(rows("select")[:, :1])[0], old.fitness, **sel.options(settings))
    perm, labels = old.perm[idx], old.labels[idx]
    if n >= 2:
        perm = _crossover(rows("cross_upper"), registry.get("perm_crossover", settings.perm_crossover),
                          settings.pc_upper, perm)
        m = rows("mutate_upper")
        mutated = jax.vmap(registry.get("perm_mutation", settings.perm_mutation))(_keys(m[1:]), perm)
        perm = jnp.where((unit(m[0]) < settings.pm_upper)[:, None], mutated, perm)
    labels = _crossover(rows("cross_lower"), registry.get("label_crossover", settings.label_crossover),
                        settings.pc_lower, labels)
    mut = registry.entry("label_mutation", settings.label_mutation)
    if mut.from_words is not None:
        labels = mut.from_words(rows("mutate_lower").T, labels, settings.pm_lower)
    else:
        labels = jax.vmap(lambda k, l: mut.fn(k, l, settings.pm_lower))(
            _keys(rows("mutate_lower")), labels)
    if settings.path_mutation != "none" and n >= 1:
        m, legs = rows("mutate_path"), _legs(sa)
        move = registry.get("path_mutation", settings.path_mutation)
        pos = positional(perm, labels, settings)
        mp, ml = jax.vmap(lambda k, p, l: move(k, p, l, legs))(_keys(m[1:]), perm, pos)
        do = (unit(m[0]) < settings.pm_path)[:, None]
        perm, labels = jnp.where(do, mp, perm), jnp.where(do, bound(mp, ml, settings), labels)
    return perm, labels


def _restarts(state: GAState):
    """Which runs start anew in the generation ``state`` is about to make: a blank
    run (generation 0), and, at generations R, 2R, ... (``R = restart_after``), a
    run whose best-so-far was not improved in the R generations before."""
    g, r = state.generation, state.settings.restart_after
    if not r:
        return g == 0
    return (g == 0) | ((g % r == 0) & (state.best.generation <= g - r))


def _restarted(words, perm, labels, restart, sa, settings: GASettings):
    """``perm, labels`` with fresh chromosomes (:func:`_fresh`, from the generation's
    words) for a run that restarts. Drawn only when some run of the batch restarts
    (:func:`~hga_jax.search.jax_compat.any_run`): at most one generation in
    ``restart_after`` (seeded fresh chromosomes cost about three generations)."""
    n = perm.shape[-1]

    def fresh(pl):
        fp, fl = _fresh(words, n, settings, sa)
        return jnp.where(restart, fp, pl[0]), jnp.where(restart, fl, pl[1])

    return jax.lax.cond(any_run(restart), fresh, lambda pl: pl, (perm, labels))


def _kept(pop: Population, old: Population, restart, settings: GASettings) -> Population:
    """Elitism, except in generation 0 and restarts."""
    if not settings.elites:
        return pop
    kept = _elitist(pop, old, settings)
    return jax.tree.map(lambda a, b: jnp.where(restart, b, a), kept, pop)


def _elitist(pop: Population, old: Population, settings: GASettings) -> Population:
    """The ``elites`` best of ``old`` replace the worst of ``pop``."""
    if not settings.elites:
        return pop
    e = settings.elites
    # top_k breaks ties by the lower index, as the stable argsort it replaced did.
    elite = jax.lax.top_k(old.fitness, e)[1]
    worst = jax.lax.top_k(-pop.fitness, e)[1]
    return jax.tree.map(lambda new, prev: new.at[worst].set(prev[elite]), pop, old)


def blank(problem: ScenarioArrays, settings: GASettings) -> GAState:
    """A run before generation 0: an empty population (generation 0 replaces it whole)
    and a best-so-far that any individual beats. Made with numpy (no device program
    runs), in the shapes and dtypes of every later state."""
    n, p = problem.centres.shape[0], settings.population
    dt = problem.centres.dtype
    pop = Population(np.zeros((p, n), np.int32), np.zeros((p, n + 2), np.int32),
                     np.zeros(p, dt), np.zeros(p, dt), np.zeros(p, np.int32))
    best = Best(np.zeros(n, np.int32), np.zeros(n + 2, np.int32), np.array(-np.inf, dt),
                np.zeros((), dt), np.zeros((), np.int32), np.zeros((), np.int32))
    return GAState(pop, best, np.zeros((), np.int32), problem, settings)


@fixed_stream
def init(key, problem: ScenarioArrays, settings: GASettings) -> GAState:
    """Generation 0 of a run from its key: :func:`step` from the :func:`blank` state."""
    return step(key, blank(problem, settings))


@fixed_stream
def step(key, state: GAState) -> GAState:
    """The next generation of a run from its key: select and vary the population
    (both modules, then the path move), give the runs that restart fresh chromosomes
    instead, evaluate, keep the elites (not in a restart), track the best. One draw
    of words serves the whole generation (see the layout above)."""
    settings, sa, g = state.settings, state.problem, state.generation
    words = _draw(key, sa.centres.shape[0], settings)
    restart = _restarts(state)
    perm, labels = _vary(words, state.pop, settings, sa)  # of no use in a restart
    perm, labels = _restarted(words, perm, labels, restart, sa, settings)
    pop = _kept(_evaluated(sa, perm, labels, settings), state.pop, restart, settings)
    best = _update_best(state.best, pop, g, settings)
    return GAState(pop, best, g + 1, sa, settings)


@fixed_stream
def steps(keys, state: GAState, live=None):
    """:func:`step` once per key of ``keys`` (a leading axis) from ``state``:
    ``(state after the last, Record per step)``. ``live`` (bools, one per key) masks
    steps off: such a step leaves the state as it was (a block of generations that
    runs past the last). The scan does not carry ``state.problem``."""
    sa = state.problem

    def body(core, xs):
        k, on = xs
        new = step(k, core._replace(problem=sa))._replace(problem=None)
        if live is not None:
            new = jax.tree.map(lambda a, b: jnp.where(on, a, b), new, core)
        return new, record(new)

    on = jnp.ones(keys.shape[0], bool) if live is None else live
    core, recs = jax.lax.scan(body, state._replace(problem=None), (keys, on))
    return core._replace(problem=sa), recs


@fixed_stream
def generation_keys(key, settings: GASettings):
    """The keys of generations 0..G of the run with key ``key``: ``(G + 1,)``.

    ``k0, kg = split(key)``; generation 0 uses ``k0``, generation g >= 1 uses
    ``split(kg, G)[g - 1]`` (:func:`host_generation_keys` makes the same on the host).
    """
    k0, kg = jax.random.split(key)
    later = jax.random.split(kg, settings.generations)
    return jnp.concatenate([k0[None], later])


def host_generation_keys(seed: int, ks, settings: GASettings):
    """:func:`generation_keys` of runs ``ks`` of ``seed``, made on the host (numpy):
    keys of :mod:`hga_jax.search.rng`, shaped ``(len(ks), G + 1)``. A compiled block of
    generations takes them as input instead of hashing them out itself."""
    ks = np.asarray(ks, np.int64)
    run = rng.host_fold_in(np.broadcast_to(rng.host_key(seed), ks.shape + (2,)), ks)
    k0kg = rng.host_split(run, 2)
    later = rng.host_split(k0kg[..., 1, :], settings.generations)
    data = np.concatenate([k0kg[..., :1, :], later], axis=-2)
    return jax.random.wrap_key_data(data, impl=rng.IMPL)


@fixed_stream
def run(key, problem: ScenarioArrays, settings: GASettings):
    """One whole run: ``(final GAState, Record of arrays shaped (G + 1,))``."""
    return steps(generation_keys(key, settings), blank(problem, settings))


def run_indices(ks):
    """``ks`` (a sequence or array of run indices) as a 1-D int32 array, checked."""
    ks = jnp.asarray(ks)
    if ks.ndim != 1 or not jnp.issubdtype(ks.dtype, jnp.integer):
        raise TypeError(f"ks: expected a 1-D sequence of integer run indices, got shape "
                        f"{tuple(ks.shape)} of {ks.dtype}")
    return ks.astype(jnp.int32)


compiled_step = jax.jit(step)
"""One generation as one compiled function: ``compiled_step(key, state)``."""


def run_batch(seed, ks, problem: ScenarioArrays, settings: GASettings):
    """Runs ``ks`` of ``seed`` (a sequence or 1-D integer array of run indices), vmapped:
    ``(Best, Record)`` with a leading run axis; the history is (runs, G + 1)."""
    def one(k):
        state, history = run(run_key(seed, k), problem, settings)
        return state.best, history

    return jax.vmap(one, axis_name=RUNS)(run_indices(ks))
