"""Variation of a generation: its one draw of words, the parents' selection and
the operators of both modules and of the path, and the fresh chromosomes of
generation 0 and of restarts.

Operators come from :mod:`hga_jax.search.registry` (a built-in may read its rows
of words directly; a registered one takes keys made from two rows each).
Chromosomes: ``perm`` (P, n) int32 permutations of the obstacle indices,
``labels`` (P, n + 2) int32 in {-1, 0, +1} (+1 clockwise), in the population's
label binding (:func:`positional` gives the decoder's order), and under free turns
``legs`` (P, n + 2) int32 in {0, 1, 2} (:mod:`hga_jax.search.leg_ops`), bound as the
labels are; None otherwise.
"""
from __future__ import annotations

import jax
import jax.numpy as jnp
from jax import Array

from hga_jax.model.scenario import ScenarioArrays

from . import islands, label_ops, leg_ops, path_ops, permutation, registry, rng
from .settings import GASettings
from .state import Population


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


def _legs(sa: ScenarioArrays, settings: GASettings | None = None, tight: bool = False):
    """The scenario's legs, their penalty per bad leg scaled as the fitness's delta, and
    the share of wraps that take the side with fewer blockers (``wrap_clearer``; the
    tight rope only). ``tight``: the tangents' legs of a model with leg genes
    (``sa.tight_legs``), read as the tight rope reads its legs (``tight_of_best``)."""
    legs = sa.tight_legs if tight else sa.legs
    if legs is None:
        raise ValueError("these settings use path moves or seeding: pass scenario arrays "
                         "from Scenario.search_arrays(..., with_legs=True)")
    if settings is not None and legs.penalty is not None:  # x 1 is exact
        legs = legs._replace(penalty=legs.penalty * settings.penalty_weight)
    if settings is not None and (tight or settings.counts_wrap_sides):  # data: 0: random
        # The tight rope's legs only (and so the tight_of_best children's). Under free
        # turns the model's own legs count a blocked tangent that a free leg gets round
        # as clear, and the Reeds-Shepp car's legs reverse: with the share, free turns
        # hit 85.8 % instead of 97.2 % on the bundled scene, and the Reeds-Shepp
        # study's clutter 25 fell from 99.7 to 94.0 % (docs/results.md).
        legs = legs._replace(clearer=settings.wrap_clearer)
    if settings is not None and legs.arcs is not None:  # data: 0: legs only
        legs = legs._replace(arc_share=settings.guided_arcs)
    return legs



# --- One draw of random words per generation ----------------------------------------
#
# Generation g of a run draws ``bits(key_g, (draw_rows(n, settings), P))`` once (P the
# population, innermost) and every part of the generation reads its own rows:
# generation 0 the words of its permutations (n rows) and labels (n + 2 rows); a later
# generation its selection's words (built-ins: 1 row, or ``tournament_size``), then a
# do-word and two key words per pair (crossovers) or individual (mutations), then the
# label mutation's words (the built-in redraw: one word per label gene), then the path
# move's do-word and its words (the guided move: 26, its ten candidates' own; the other
# moves: two key words). Pair rows use
# their first P // 2 columns. Free turns add rows after all of these: generation 0 the
# words of its leg genes (n + 2), a later generation the leg crossover's (3) and the leg
# mutation's (one word per gene); the tight rope draws the words it always did. Operators without a word-reading form (registry.Operator)
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
        parts += (("mutate_path", 1 + _word_rows("path_mutation", n, settings)),)
    for genes in _genes(settings):
        parts += ((f"cross_{genes.name}", 3),
                  (f"mutate_{genes.name}", _word_rows(genes.mutation, n, settings)))
        if genes.ends and getattr(settings, genes.ends) != "none":
            parts += (("mutate_ends", 3),)
    out, row = {}, 0
    for name, rows in parts:
        out[name], row = (row, rows), row + rows
    return out


def _genes(settings: GASettings):
    """The gene modules the settings' car model adds to a chromosome (at most one: the
    population holds it as ``legs``)."""
    genes = settings.model.genes
    if len(genes) > 1:
        raise NotImplementedError(f"car model {settings.turns!r}: the GA holds one module of "
                                  "added genes")
    return genes


def _fresh_rows(n: int, settings: GASettings) -> int:
    """Rows before generation 0's leg words: ``2n + 2``, and 2 more with seeding."""
    return 2 * n + 2 + (2 if settings.seeds else 0)


def draw_rows(n: int, settings: GASettings) -> int:
    """Rows of words (of P each) every generation draws: enough for generation 0
    (``2n + 2``, 2 more with seeding, ``n + 2`` more under free turns) and for the
    later ones."""
    last = max(start + rows for start, rows in _layout(n, settings).values())
    first = _fresh_rows(n, settings) + (n + 2) * len(_genes(settings))
    return max(first, last)


def _draw(key, n: int, settings: GASettings):
    return jax.random.bits(key, (draw_rows(n, settings), settings.population), dtype=jnp.uint32)


unit = rng.unit  # floats uniform on k / 2**24 from words (the one rule, in rng)


def _keys(rows):
    """Keys (of :mod:`hga_jax.search.rng`) from two rows of words: ``(count,)`` keys."""
    return rng.wrap(jnp.stack([rows[0], rows[1]], axis=-1))


def _fresh(words, n: int, settings: GASettings | None = None, sa: ScenarioArrays | None = None,
           colliding=False):
    """Generation 0's chromosomes from its words: random permutations and labels (and
    leg genes under free turns); with ``seeding``, the first ``round(seeding * P)`` are
    then built by :func:`hga_jax.search.path_ops.wrap_blockers` from their start and
    goal labels (keys from rows ``2n + 2`` and ``2n + 3``), keeping their random leg
    genes (straight ones lost a third of the hits on scenes where free turns win); the
    ``seeding_via`` share of them (spread over the population: :func:`spread`) start
    from a path through the first obstacle of their permutation, with its drawn label,
    and where ``colliding`` (a bool: the run restarts with a colliding best so far) the
    ``restart_via`` share too (each spread by :func:`spread`; a seed in either goes);
    there the ``restart_arcs`` share also wraps the overlapping neighbours of its
    colliding arcs (:func:`hga_jax.search.path_ops.wrap_from_words`).
    Returns ``(perm, labels, legs)``, legs None under the tight rope."""
    perm = permutation.permutation_from_words(words[:n].T)
    labels = label_ops.labels_from_words(words[n:2 * n + 2].T)
    genes = None
    for module in () if settings is None else _genes(settings):
        first = _fresh_rows(n, settings)
        genes = leg_ops.genes_from_words(words[first:first + n + 2].T, module.weights)
    if settings is None or not settings.seeds or n == 0:
        return perm, labels, genes
    legs = _legs(sa, settings)
    pos = positional(perm, labels, settings)
    # each seed's 3n words from its key (rows 2n + 2 and 2n + 3): (3n, P)
    wrap_words = rng.words_of_keys(words[2 * n + 2], words[2 * n + 3], 3 * n)
    via = spread(perm.shape[0], settings.seeding_via) | (
        jnp.asarray(colliding) & spread(perm.shape[0], settings.restart_via))
    arc_rule = None
    if settings.counts_wrap_sides and legs.arcs is not None:  # the tight rope's turn table
        # restart_arcs (data: a share of 0 changes no seed)
        arcs = jnp.asarray(colliding) & spread(perm.shape[0], settings.restart_arcs)
        arc_rule = (overlapping(sa.centres, sa.model_radii), arcs)
    sp, sl = path_ops.wrap_from_words(wrap_words, perm.T, pos.T, legs, via, arc_rule)  # population last
    sp, sl = sp.T, sl.T
    sl = bound(sp, sl, settings)
    on = (jnp.arange(perm.shape[0]) < settings.seeded_count())[:, None]  # each from its own column
    return jnp.where(on, sp, perm), jnp.where(on, sl, labels), genes


def overlapping(centres, model_radii) -> Array:
    """(n, n) bools: obstacles ``i != j`` whose model circles overlap (centres closer
    than the sum of their model radii)."""
    gap = centres[:, None] - centres[None]
    near = jnp.sum(gap * gap, axis=-1) < (model_radii[:, None] + model_radii[None]) ** 2
    return near & ~jnp.eye(centres.shape[0], dtype=bool)


def spread(count: int, share) -> Array:
    """``count`` bools, True for about ``share`` of them, spread evenly: entry ``i`` is
    True when ``floor((i + 1) share) > floor(i share)`` (share 0.5: the odd entries;
    ``share`` a float or a float32 scalar of the program's rates)."""
    i = jnp.arange(count, dtype=jnp.float32)
    share = jnp.asarray(share, jnp.float32)
    return jnp.floor((i + 1) * share) > jnp.floor(i * share)


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
    """Select parents from ``old`` and vary both modules (and the leg genes under free
    turns): the children's ``(perm, labels, legs)``, from the generation's words (see
    the layout above)."""
    n = old.perm.shape[1]
    at = _layout(n, settings)

    def rows(name):
        start, count = at[name]
        return words[start:start + count]

    sel = registry.entry("selection", settings.selection)
    k = settings.island_count  # each island selects among its own (one key each, from its column)
    if sel.from_words is not None:
        pick = sel.from_words
    else:
        def pick(w, fitness):
            return sel.fn(_keys(w[:1].T)[0], fitness, **sel.options(settings))
    idx = islands.select(pick, rows("select").T, old.fitness, k)
    perm, labels = old.perm[idx], old.labels[idx]
    genes = None if old.legs is None else _vary_genes(rows, old.legs[idx], settings)
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
    ends = None
    if genes is not None and "mutate_ends" in at:
        (module,) = _genes(settings)
        ends = (unit(rows("mutate_ends")[0]) < getattr(settings, module.pe))[:, None]
        k = settings.ends_of_best
        if k:  # the last k children: the parents' best, moved at its ends
            (perm, labels, genes), tail = _best_copies(old, (perm, labels, genes), 0, k)
            ends = ends | tail
    moves = settings.path_mutation != "none" and n >= 1
    if moves:
        mp, ml, do = _path_move(rows("mutate_path"), perm, labels, _legs(sa, settings), settings)
        if ends is not None:  # a child moved at its ends gets no path move
            do = do & ~ends
        perm, labels = jnp.where(do, mp, perm), jnp.where(do, ml, labels)
    if ends is not None:
        labels, genes = _ends(rows("mutate_ends"), perm, labels, genes, settings, ends)
    if genes is not None:
        perm, labels, genes = _straight_of_best(old, perm, labels, genes, settings,
                                                rows("mutate_path") if moves else None, sa)
    return perm, labels, genes


def _path_move(m, perm, labels, legs, settings: GASettings):
    """The path move (``path_mutation``) of children ``perm``, ``labels`` (the
    population's binding) on ``legs``, from their rows ``m`` (its do-word, then the
    move's words): the moved ``(perm, labels)`` and whether each child takes the move
    ((P, 1) bools, the do-word against ``pm_path``)."""
    move = registry.entry("path_mutation", settings.path_mutation)
    pos = positional(perm, labels, settings)
    if move.from_words is not None:  # a built-in reads its own rows of words
        mp, ml = move.from_words(m[1:].T, perm, pos, legs)
    else:
        mp, ml = jax.vmap(lambda k, p, l: move.fn(k, p, l, legs))(_keys(m[1:]), perm, pos)
    return mp, bound(mp, ml, settings), (unit(m[0]) < settings.pm_path)[:, None]


def _straight_of_best(old: Population, perm, labels, genes, settings: GASettings,
                      m=None, sa: ScenarioArrays | None = None):
    """The model's ``straight`` and ``tight`` children (free turns, the Reeds-Shepp
    car), the last before the ends' (``ends_of_best``): copies of the parents' best
    with every gene 0, so each leg the tangent to its next circle (or the free leg that
    gets round a blocked one, as gene 0 reads; the Reeds-Shepp car's driven forward):
    the tight-rope path of the best's touched sequence, which the search otherwise
    reaches only gene by gene. The ``straight_of_best`` ones (last) stay so and read no
    words (the bundled scene under free turns: 96.8 -> 98.7 % of 3,000 runs). The
    ``tight_of_best`` ones before them then take the path move as the tight rope
    scores it (``sa.tight_legs``: a blocked tangent counts as blocked although gene 0
    gets round it by a free leg), from their own rows ``m`` of the path move's words
    (the moves of the children they replace are dropped), so that the wrap of such a
    blocker, which the model's own legs score as no shorter, is still tried (free
    turns: one held-out scene 45 -> 100 % of runs; docs/results.md). All are evaluated
    as every child."""
    (module,) = _genes(settings)
    k = getattr(settings, module.straight) if module.straight else 0
    t = getattr(settings, module.tight) if module.tight else 0
    if not (k or t):
        return perm, labels, genes
    skip = settings.ends_of_best if module.ends else 0
    (perm, labels, genes), on = _best_copies(old, (perm, labels, genes), skip, k + t)
    genes = jnp.where(on, 0, genes)
    if t and m is not None:
        lo = perm.shape[0] - skip - k - t
        at = slice(lo, lo + t)
        mp, ml, do = _path_move(m[:, at], perm[at], labels[at], _legs(sa, settings, tight=True),
                                settings)
        perm = perm.at[at].set(jnp.where(do, mp, perm[at]))
        labels = labels.at[at].set(jnp.where(do, ml, labels[at]))
    return perm, labels, genes


def _best_copies(old: Population, children, skip: int, k: int):
    """``children`` (perm, labels, genes) with the k before the last ``skip`` replaced by
    copies of the parents' best (the first best of equal fitness), and which they are
    (P, 1) bools."""
    p = children[0].shape[0]
    off = p - 1 - skip - jnp.arange(p)  # 0: the last child before the skipped ones
    on = ((off >= 0) & (off < k))[:, None]
    b = jnp.argmax(old.fitness)
    best = (old.perm[b], old.labels[b], old.legs[b])
    return tuple(jnp.where(on, x, c) for x, c in zip(best, children)), on


def _ends(rows, perm, labels, genes, settings: GASettings, do):
    """The end move of a reversing car's model on the children where ``do`` (P, 1) says
    (rows: the do-word, drawn against its rate, and two key words per child); labels
    and genes in the population's binding."""
    (module,) = _genes(settings)
    move = registry.entry("end_mutation", getattr(settings, module.ends))
    values = len(module.weights)
    pos, legs = positional(perm, labels, settings), positional(perm, genes, settings)
    if move.from_words is not None:  # a built-in reads the two words itself
        ml, mg = move.from_words(rows[1], rows[2], pos, legs, values)
    else:
        ml, mg = jax.vmap(lambda k, l, g: move.fn(k, l, g, values))(_keys(rows[1:]), pos, legs)
    return (jnp.where(do, bound(perm, ml, settings), labels),
            jnp.where(do, bound(perm, mg, settings), genes))


def _vary_genes(rows, genes, settings: GASettings):
    """The added genes of the selected parents (the car model's gene module: leg genes
    under free turns), crossed over and mutated by the operators and rates it names."""
    (module,) = _genes(settings)
    name, pc, pm = module.name, getattr(settings, module.pc), getattr(settings, module.pm)
    cross = registry.get(module.crossover, getattr(settings, module.crossover))
    genes = _crossover(rows(f"cross_{name}"), cross, pc, genes)
    mut = registry.entry(module.mutation, getattr(settings, module.mutation))
    if mut.from_words is not None:  # a built-in: told how many values the genes take
        return mut.from_words(rows(f"mutate_{name}").T, genes, pm, values=len(module.weights))
    return jax.vmap(lambda k, g: mut.fn(k, g, pm))(_keys(rows(f"mutate_{name}")), genes)
