"""Moves on the touched sequence: mutations of a whole chromosome, path by path.

The paper's operators change the permutation and the labels apart, blind to the
path they stand for. The moves here act on the *touched sequence* (the start
circle, the obstacles with a non-zero label in permutation order, the goal
circle), the way TSP moves act on a tour:

- ``flip``: reverse the turning direction of one touched circle (start and goal
  included, but for a reversing car, whose ends are moved with their gears:
  :mod:`hga_jax.search.end_ops`);
- ``drop``: stop touching one touched obstacle;
- ``insert``: touch one untouched obstacle, in a random direction, at a random
  place of the sequence;
- ``shift`` (or-opt): move one touched obstacle, with its label, to a random place;
- ``repair``: pick one leg of the path that runs through an obstacle (per-leg
  information, :mod:`hga_jax.model.legs`: the first leg's start arc and the last
  leg's goal arc count with them) and wrap that obstacle, in a random direction,
  between the leg's two circles; without a blocked leg, an ``insert``;
- :func:`wrap_blockers` builds a whole path that way from the direct one (the
  GA's ``seeding``);
- ``mixed``: one of the five above, uniformly.

Conventions (as :mod:`hga_jax.search.perm_crossover`): every move works on ONE chromosome,
``perm`` (n,) and *positional* labels (n + 2,) (docs/model.md), and returns the
pair (the plans, :func:`view`, :func:`wrap_from_words` and the guided move also take a
population laid out after the positions, ``perm`` (n, ...), labels (n + 2, ...): then
every step is vector work across it; the GA uses that form); it takes a key and the
scenario's :class:`~hga_jax.model.legs.Legs` (only
``repair`` reads it); shapes depend on ``n`` only; pure, jit- and vmap-able. A
move that has nothing to act on (``drop`` with no touched obstacle, say) returns
the chromosome unchanged (so does :func:`keep`, ``path_mutation = "none"``). Moving an obstacle from position ``j`` to position
``i`` shifts the positions between them by one, labels travelling with their
obstacles.
"""
from __future__ import annotations

from typing import Any, Callable, NamedTuple

import jax
import jax.numpy as jnp
from jax import Array

from hga_jax.jax_compat import any_run
from hga_jax.model import circle_ids
from hga_jax.model.decode import circles_along
from .permutation import ONEHOT_MAX_N, int_from_words, lift, pick, take
from .rng import unit

Move = Callable[[Array, Array, Array, Any], tuple[Array, Array]]


def _words(key: Array, count: int) -> Array:
    return jax.random.bits(key, (count,), dtype=jnp.uint32)


def along(x: Array, m: int | None = None) -> Array:
    """The positions ``0..m-1`` (int32; ``m`` defaults to ``x``'s first axis), shaped to
    broadcast against ``x`` (positions first, any batch after)."""
    m = x.shape[0] if m is None else m
    return jnp.arange(m, dtype=jnp.int32).reshape((m,) + (1,) * (x.ndim - 1))


def _choose(mask: Array | None, word: Array, counts: Array | None = None
            ) -> tuple[Array, Array]:
    """A position uniform among the True entries of ``mask`` (along its first axis) and
    whether there is one; ``counts``: its :func:`prefix_count`, if made already (then
    ``mask`` is not read). The ``r``-th True entry is the first whose running count
    exceeds ``r``: as many positions as have a count of ``r`` or less."""
    counts = prefix_count(mask) if counts is None else counts
    count = counts[-1]
    r = int_from_words(word, 0, jnp.maximum(count, 1))
    idx = jnp.sum(lift(counts, r) <= r, axis=0, dtype=jnp.int32)
    return jnp.where(count > 0, idx, 0), count > 0


def prefix_count(mask: Array) -> Array:
    """``cumsum(mask)`` (int32) along the first axis. A short bool vector (one
    chromosome, vmapped or not): a product with a triangular matrix, exact (counts of
    ones, HIGHEST precision) and, vmapped over chromosomes on the CPU, about twice as
    fast as ``cumsum`` (a reduce-window) at n = 25. A batch after the positions: a
    running sum over the positions, vector adds across the batch (``cumsum`` over that
    leading axis, a reduce-window, took 20 times as long at 40 obstacles)."""
    if mask.ndim > 1:
        def add(total, row):
            total = total + row.astype(jnp.int32)
            return total, total

        return jax.lax.scan(add, jnp.zeros(mask.shape[1:], jnp.int32), mask)[1]
    s = mask.shape[-1]
    lower = jnp.tril(jnp.ones((s, s), jnp.float32))
    counts = jnp.matmul(lower, mask.astype(jnp.float32), precision=jax.lax.Precision.HIGHEST)
    return counts.astype(jnp.int32)


def move_apply(perm: Array, labels: Array, j: Array, i: Array, label: Array) -> tuple[Array, Array]:
    """The obstacle at position ``j`` moved to position ``i`` (0-based positions of
    the permutation), with label ``label``; the positions between shift by one."""
    p = along(perm)
    up = (j < i) & (p >= j) & (p < i)  # take position p + 1's
    down = (j > i) & (p > i) & (p <= j)  # take position p - 1's

    def moved(x, at_i):  # x[src] for src = j at i, p + 1 where up, p - 1 where down, p
        shift = jnp.where(up, jnp.concatenate([x[1:], x[-1:]]),
                          jnp.where(down, jnp.concatenate([x[:1], x[:-1]]), x))
        return jnp.where(p == i, at_i, shift)

    mid = labels[1:-1]
    return (moved(perm, pick(perm, j)),
            jnp.concatenate([labels[:1], moved(mid, label), labels[-1:]]))


class Plan(NamedTuple):
    """A move as data (int32 scalars): the obstacle at permutation position ``j`` moved
    to position ``i`` with label ``label`` (0: untouched; ``j = i`` and the same label:
    nothing), then the label at chromosome position ``end`` negated (the start's, 0, or
    the goal's, ``n + 1``; -1: none). :func:`apply` makes the chromosome, and
    :mod:`hga_jax.search.guided` scores a plan by the legs it changes, before making it."""

    j: Array
    i: Array
    label: Array
    end: Array


def _plan(j, i, label, end=-1) -> Plan:
    return Plan(*(jnp.asarray(v, jnp.int32) for v in (j, i, label, end)))


def apply(perm: Array, labels: Array, plan: Plan) -> tuple[Array, Array]:
    """The chromosome ``plan`` makes of ``(perm, labels)`` (one chromosome)."""
    if perm.shape[0]:
        perm, labels = move_apply(perm, labels, plan.j, plan.i, plan.label)
    return perm, jnp.where(along(labels) == plan.end, -labels, labels)


def _moves(plans):
    """A move ``(key, perm, labels, legs) -> (perm, labels)`` from its plan."""
    def move(key: Array, perm: Array, labels: Array, legs: Any = None) -> tuple[Array, Array]:
        return apply(perm, labels, plans(key, perm, labels, legs))

    move.__name__ = plans.__name__.removeprefix("plan_")
    move.__qualname__ = move.__name__
    move.__doc__ = plans.__doc__
    return move


def keep(key: Array, perm: Array, labels: Array, legs: Any = None) -> tuple[Array, Array]:
    """No move (``path_mutation = "none"``): the chromosome unchanged."""
    return perm, labels


# Each plan is written once, on its random words (uint32, as many as PLAN_WORDS says);
# the plan of a key reads the words ``_words(key, count)`` (repair: two keys split from it).

def _flip(w: Array, perm: Array, labels: Array, legs: Any = None, v=None) -> Plan:
    counts = _touched_counts(labels, v)
    if legs is not None and getattr(legs, "ends", None) is not None:  # neither end movable
        touched = labels != 0
        counts = counts - touched[0] - jnp.where(along(labels) == labels.shape[0] - 1,
                                                 touched[-1], 0)
    k, _ = _choose(None, w[0], counts)
    end = (k == 0) | (k == labels.shape[0] - 1)
    return _plan(jnp.where(end, 0, k - 1), jnp.where(end, 0, k - 1),
                 jnp.where(end, labels[1], -pick(labels, k)), jnp.where(end, k, -1))


def _drop(w: Array, perm: Array, labels: Array, legs: Any = None, v=None) -> Plan:
    k, any_ = _choose(None, w[0], _inner_counts(labels, v))
    return _plan(k, k, jnp.where(any_, 0, labels[1]))


def _sign(word: Array) -> Array:
    return jnp.where((word >> 31) == 0, -1, 1).astype(jnp.int32)


def _relocation(j, i, label, ok, labels) -> Plan:
    """Move ``j`` to ``i`` with ``label`` where ``ok``, else nothing."""
    return _plan(jnp.where(ok, j, 0), jnp.where(ok, i, 0), jnp.where(ok, label, labels[1]))


def _insert(w: Array, perm: Array, labels: Array, legs: Any = None, v=None) -> Plan:
    n = perm.shape[0]
    untouched = along(perm) + 1 - _inner_counts(labels, v)  # running count of label 0
    j, any_ = _choose(None, w[0], untouched)
    return _relocation(j, int_from_words(w[1], 0, n), _sign(w[2]), any_, labels)


def _shift(w: Array, perm: Array, labels: Array, legs: Any = None, v=None) -> Plan:
    n = perm.shape[0]
    j, any_ = _choose(None, w[0], _inner_counts(labels, v))
    return _relocation(j, int_from_words(w[1], 0, n), pick(labels[1:-1], j), any_, labels)


def _touched_counts(labels: Array, v=None) -> Array:
    """Running count of touched positions (start and goal included)."""
    return prefix_count(labels != 0) if v is None else v.counts


def _inner_counts(labels: Array, v=None) -> Array:
    """Running count of touched obstacles, over the permutation's positions (n, ...)."""
    if v is None:
        return prefix_count(labels[1:-1] != 0)
    return v.counts[1:-1] - v.touched[0]


def plan_flip(key: Array, perm: Array, labels: Array, legs: Any = None) -> Plan:
    """Reverse the label of one touched circle (start and goal included, unless the
    legs hold the ends: a reversing car's ends are the end move's)."""
    return _flip(_words(key, 1), perm, labels, legs)


def plan_drop(key: Array, perm: Array, labels: Array, legs: Any = None) -> Plan:
    """Set the label of one touched obstacle to 0."""
    return _drop(_words(key, 1), perm, labels, legs)


def plan_insert(key: Array, perm: Array, labels: Array, legs: Any = None) -> Plan:
    """Touch one untouched obstacle (random direction), moved to a random position."""
    return _insert(_words(key, 3), perm, labels, legs)


def plan_shift(key: Array, perm: Array, labels: Array, legs: Any = None) -> Plan:
    """Move one touched obstacle, with its label, to a random position (or-opt)."""
    return _shift(_words(key, 2), perm, labels, legs)


flip, drop, insert, shift = (_moves(f) for f in (plan_flip, plan_drop, plan_insert, plan_shift))


def path_circles(perm: Array, labels: Array) -> tuple[Array, Array]:
    """Circle ids (:mod:`hga_jax.model.tangents`) of the positions (n + 2, ...) and touched
    mask: :func:`hga_jax.model.decode.position_circles` for one chromosome (or a batch
    after the positions)."""
    return circles_along(perm, labels)


class View(NamedTuple):
    """What the moves read of a chromosome's path, per position (n + 2, ...): its circle
    id (``ids``), whether it is ``touched`` and the running count of touched positions
    (``counts``), the last touched position before it (``prev``, 0 if none) and the
    first after it (``nxt``, ``n + 1`` if none), that circle's id (``nxt_id``), whether
    the leg from it runs through an obstacle (``blocked``, False from untouched
    positions and the goal) and the running count of such legs (``blocked_counts``).
    Made once per chromosome (:func:`view`) for all the candidates of a guided move."""

    ids: Array
    touched: Array
    counts: Array
    prev: Array
    nxt: Array
    nxt_id: Array
    blocked: Array
    blocked_counts: Array


def view(perm: Array, labels: Array, legs) -> View:
    """The :class:`View` of one chromosome, or of a batch laid out after the positions."""
    ids, touched = path_circles(perm, labels)
    nxt, nxt_id = _following(ids, touched)
    blocked = _blocked(ids, touched, nxt_id, legs)
    if touched.ndim == 1:
        counts, prev, blocked_counts = (prefix_count(touched), prev_touched(touched),
                                        prefix_count(blocked))
    else:  # one pass from the start for all three
        counts, prev, blocked_counts = _running(touched, blocked)
    return View(ids, touched, counts, prev, nxt, nxt_id, blocked, blocked_counts)


def _running(touched: Array, blocked: Array) -> tuple[Array, Array, Array]:
    """:func:`prefix_count` of ``touched`` and of ``blocked`` and :func:`prev_touched`
    of a batch laid out after the positions, in one pass from the start."""
    zero = jnp.zeros(touched.shape[1:], jnp.int32)

    def ahead(carry, k):  # counts up to k - 1, the last touched position before k
        count, last, nblocked = carry
        count = count + touched[k].astype(jnp.int32)
        nblocked = nblocked + blocked[k].astype(jnp.int32)
        out = (count, last, nblocked)
        return (count, jnp.where(touched[k], k, last), nblocked), out

    _, out = jax.lax.scan(ahead, (zero, zero, zero), jnp.arange(touched.shape[0]))
    return out


def _following(ids: Array, touched: Array) -> tuple[Array, Array]:
    """Per position the first touched position after it (:func:`next_touched`) and
    that circle's id."""
    if touched.ndim > 1:
        return _next_after(touched, ids)
    nxt = next_touched(touched)
    return nxt, take(ids, nxt)


def _blocked(ids: Array, touched: Array, nxt_id: Array, legs) -> Array:
    """Whether the leg from each position to the next touched circle (``nxt_id``) runs
    through an obstacle (False from untouched positions and the goal)."""
    s = ids.shape[0]
    return jnp.asarray(legs.blocked)[ids, nxt_id] & touched & (along(ids) < s - 1)


def blocked_legs(perm: Array, labels: Array, legs) -> tuple[Array, Array, Array]:
    """Per position ``k`` (n + 2,): its circle id, the position of the next touched
    circle, and whether the leg from ``k`` to it passes through an obstacle (False
    from untouched positions and the goal)."""
    ids, touched = path_circles(perm, labels)
    nxt_id = _following(ids, touched)[1]
    return ids, nxt_id, _blocked(ids, touched, nxt_id, legs)


def next_touched(touched: Array) -> Array:
    """Per position ``k`` (n + 2, ...) the first touched position after ``k`` (the goal's,
    ``n + 1``, for the goal itself). One chromosome (vmapped or not): up to
    :data:`~hga_jax.search.permutation.ONEHOT_MAX_N` obstacles, O(n^2) comparisons
    (vmapped on the CPU, 4 times faster than a reversed running minimum, ``cummin``, at
    n = 25); beyond, a suffix minimum in log2(n + 2) steps of shifted minima (the
    recommended preset's search 10 % faster at 25 obstacles and 30 % at 40, the same
    bits; at 9 the comparisons are faster). A batch after the positions: one pass from
    the goal back, a select across the batch per position (at 40 obstacles 30 times
    faster than the shifted minima on such a layout)."""
    s = touched.shape[0]
    pos = along(touched)
    if touched.ndim > 1:
        return _next_after(touched, jnp.broadcast_to(pos, touched.shape))[0]
    if s - 2 <= ONEHOT_MAX_N:
        later = touched[None, :] & (pos[None, :] > pos[:, None])  # (s, s)
        return jnp.min(jnp.where(later, pos[None, :], s - 1), axis=1)
    last = jnp.full((s,), s - 1, jnp.int32)
    after = jnp.where(touched, pos, s - 1)[1:]  # position k + 1's own, if touched
    v = jnp.concatenate([after, last[:1]])
    d = 1
    while d < s:  # v[k] = min(v[k], v[k + d]): then it covers k + 1 .. k + 2d
        v = jnp.minimum(v, jnp.concatenate([v[d:], last[:d]]))
        d *= 2
    return v


def _next_after(touched: Array, ids: Array) -> tuple[Array, Array]:
    """:func:`next_touched` of a batch laid out after the positions, and the value of
    ``ids`` there (a circle id per position): one pass from the goal back, carrying the
    first touched position after the current one and its value across the batch."""
    s = touched.shape[0]
    last = jnp.full(touched.shape[1:], s - 1, jnp.int32)

    def back(after, k):  # after: the first touched position after k, and its id
        pos, id_ = after
        return (jnp.where(touched[k], k, pos), jnp.where(touched[k], ids[k], id_)), after

    _, (nxt, nxt_id) = jax.lax.scan(back, (last, ids[-1]), jnp.arange(s - 1, -1, -1))
    return nxt[::-1], nxt_id[::-1]


def prev_touched(touched: Array) -> Array:
    """Per position ``k`` (n + 2, ...) the last touched position before ``k`` (0 where
    there is none): :func:`next_touched` of the positions read backwards."""
    s = touched.shape[0]
    return s - 1 - next_touched(touched[::-1])[::-1]


def _wrap_one(w: Array, perm: Array, labels: Array, legs,
              v: View | None = None) -> tuple[Plan, Array]:
    """``repair`` without its fallback, from its three words: its plan and whether a leg
    was blocked (``v``: the chromosome's :func:`view`, if made already)."""
    if v is None:
        return _wrap(w, perm, labels, legs, *blocked_legs(perm, labels, legs))
    return _wrap(w, perm, labels, legs, v.ids, v.nxt_id, v.blocked, v.blocked_counts)


def _wrap(w: Array, perm: Array, labels: Array, legs, ids: Array, nxt_id: Array,
          blocked: Array, counts: Array | None = None) -> tuple[Plan, Array]:
    """The wrap's rule, given per position its circle, the next touched circle's and
    whether the leg between them is blocked: a blocked leg (word 0), one of its
    blockers (word 1), a direction (word 2), put right after the leg's first circle."""
    k, any_leg = _choose(blocked, w[0], counts)
    a, c = pick(ids, k), pick(nxt_id, k)
    o = _blocker(legs, a, c, w[1])
    # A random side (preferring the side away from the obstacle's centre, 3 in 4, found
    # the optimum less often on held-out obstructed scenes: 98.0 % against 99.7 % of
    # runs with flips, seeding and restarts), or where the settings say so the side
    # whose two new legs pass through fewer obstacles.
    label = _sign(w[2])
    if legs.clearer is not None:
        label = _clearer_side(legs, a, c, o, w[2], label)
    # o's position, where it is the one entry: a sum (an argmax, a reduce of value and
    # index, XLA on the CPU ran element by element: seeding wraps at 40 obstacles 15 %
    # slower)
    at = lift(perm, o) == o
    j = jnp.sum(jnp.where(at, along(at), 0), axis=0, dtype=jnp.int32)
    q = k - 1  # the leg's first circle, as a permutation position (-1: the start)
    ok = any_leg & (j != q)
    return _relocation(j, jnp.where(j > q, q + 1, q), label, ok, labels), ok


def _clearer_side(legs, a: Array, c: Array, o: Array, word: Array, label: Array) -> Array:
    """The side (+1 clockwise, -1 counter-clockwise) to wrap obstacle ``o`` between
    circles ``a`` and ``c``: with probability ``legs.clearer`` (``word``'s lowest 8 bits,
    independent of the random side ``label`` it drew from the top bit) the side whose
    two new legs ``a -> o`` and ``o -> c`` pass through fewer obstacles (``legs.count``);
    else, and where both sides pass through as many, ``label``."""
    count = jnp.asarray(legs.count)
    ccw, cw = circle_ids.obstacle(o, 0), circle_ids.obstacle(o, 1)
    via_ccw = count[a, ccw].astype(jnp.int32) + count[ccw, c].astype(jnp.int32)
    via_cw = count[a, cw].astype(jnp.int32) + count[cw, c].astype(jnp.int32)
    # the uniform of the word's lowest 8 bits (k / 256), by the one rule of rng.unit
    on = unit(word << jnp.uint32(24)) < jnp.asarray(legs.clearer, jnp.float32)
    return jnp.where(on & (via_cw != via_ccw), jnp.where(via_cw < via_ccw, 1, -1),
                     label).astype(jnp.int32)


def _blocker(legs, a: Array, c: Array, word: Array) -> Array:
    """An obstacle uniform among the blockers of the tangent ``a -> c`` (0 if none): the
    one ``word`` draws from the tangent's list (``legs.listed``, ``legs.count``), the
    True entry of ``legs.blockers[a, c]`` that a choice over that row would take, read
    in two look-ups instead of a pass over every obstacle."""
    count = jnp.asarray(legs.count)[a, c].astype(jnp.int32)
    r = int_from_words(word, 0, jnp.maximum(count, 1))
    return jnp.asarray(legs.listed)[a, c, r].astype(jnp.int32)


def _repair(w: Array, perm: Array, labels: Array, legs, v: View | None = None) -> Plan:
    """Six words: the wrap's three, then the fallback insert's three."""
    wrap, ok = _wrap_one(w[:3], perm, labels, legs, v)
    other = _insert(w[3:], perm, labels, None, v)
    return Plan(*(jnp.where(ok, a, b) for a, b in zip(wrap, other)))


def plan_repair(key: Array, perm: Array, labels: Array, legs) -> Plan:
    """Wrap an obstacle that blocks a leg between the leg's circles (see module doc)."""
    k1, k2 = jax.random.split(key)
    w = jnp.concatenate([_words(k1, 3), _words(k2, 3)])
    return _repair(w, perm, labels, legs)


repair = _moves(plan_repair)


def wrap_blockers(key: Array, perm: Array, labels: Array, legs, via=False) -> tuple[Array, Array]:
    """A constructive path: from the direct path between the start and goal circles
    of ``labels`` (every obstacle label set to 0), wrap a blocking obstacle of a
    blocked leg, ``n`` times or until no leg is blocked (:func:`repair`'s step; it
    reads legs only and decodes no path). ``via`` (a bool): start instead from the path
    through the permutation's first obstacle with its label in ``labels`` (the direct
    path if that label is 0), so the wraps follow another corridor.

    Each wrap puts its obstacle right after the leg's first circle, so the touched
    obstacles are always the first ``L`` of the permutation, in path order: a leg runs
    from position ``k`` to ``k + 1`` (from ``L`` to the goal), and a step costs O(n),
    not the O(n^2) of finding the next touched circle of any chromosome (the same
    chromosomes as :func:`_wrap_one` applied ``n`` times, step ``t`` reading words
    ``3t .. 3t + 2`` of ``3n`` drawn from ``key``: :func:`wrap_from_words`)."""
    return wrap_from_words(_words(key, 3 * perm.shape[0]), perm, labels, legs, via)


def wrap_from_words(words: Array, perm: Array, labels: Array, legs, via=False, arc_rule=None
                    ) -> tuple[Array, Array]:
    """:func:`wrap_blockers` from its ``3n`` words (3n, ...), for one chromosome or a
    batch after the positions (``perm`` (n, ...), ``labels`` (n + 2, ...), ``via`` a
    bool or one per chromosome). The steps stop once no chromosome has a blocked leg
    left: a later step would change nothing, so a chromosome ends alike alone and in
    any batch.

    ``arc_rule = (overlap, on)`` (``overlap`` (n, n) bools of obstacles whose model
    circles overlap, ``on`` a bool per chromosome; the legs' ``arcs`` table needed): a
    step of a chromosome that is ``on`` and has no blocked leg instead takes one of its
    arcs with a violation of its own (``legs.arcs``; word 0) and puts an untouched
    obstacle overlapping that arc's obstacle (word 1) right after it, with the same
    label, so that the path follows a chain of overlapping circles round; the steps go
    on while such an arc is left (at most ``n`` steps in all). Where no chromosome of the
    batch's runs is ``on`` (:func:`~hga_jax.jax_compat.any_run`: generation 0, a restart
    with no colliding run) the arc steps are skipped, a branch: they would change
    nothing (the recommended search 10-15 % faster at 9 to 40 obstacles)."""
    n = perm.shape[0]
    keep = jnp.asarray(via) & (labels[1] != 0)
    labels = labels.at[1:-1].set(0).at[1].set(jnp.where(keep, labels[1], 0))
    pos = along(labels)
    table = jnp.asarray(legs.blocked)
    following = None if arc_rule is None else any_run(jnp.any(arc_rule[1]))

    def body(carry):
        t, _, perm, labels, count = carry  # the touched obstacles: positions 1..count
        ids, _ = path_circles(perm, labels)
        nxt = jnp.where(pos < count, jnp.concatenate([ids[1:], ids[-1:]]), ids[-1])
        w = jax.lax.dynamic_slice_in_dim(words, 3 * t, 3)
        blocked = table[ids, nxt] & (pos <= count)
        plan, ok = _wrap(w, perm, labels, legs, ids, nxt, blocked)
        new = ok & (plan.j >= count)  # an untouched obstacle wrapped
        active = jnp.any(blocked)
        if arc_rule is not None:
            overlap, on = arc_rule

            def follow():
                prv = jnp.concatenate([ids[:1], ids[:-1]])  # the touched circle before
                inner = (pos >= 1) & (pos <= count)  # the touched obstacles' positions
                bad = (jnp.asarray(legs.arcs)[prv, ids, nxt] & inner & on
                       & ~jnp.any(blocked, axis=0))
                k, anybad = _choose(bad, w[0])
                b = circle_ids.obstacle_of(pick(ids, k))  # the arc's obstacle
                lab = pick(labels, k)
                cand = (along(perm) >= count) & jnp.asarray(overlap)[b, perm]  # (n, ...)
                # its permutation position is k - 1: the obstacle goes to k, right after it
                j, anyc = _choose(cand, w[1])
                arc_ok = anybad & anyc
                aplan = _relocation(j, k, lab, arc_ok, labels)
                return (Plan(*(jnp.where(arc_ok, x, y) for x, y in zip(aplan, plan))),
                        new | arc_ok, active | jnp.any(bad))

            # skipped where no chromosome of the batch's runs follows arcs (generation 0,
            # restarts without a colliding run): it would change nothing there
            plan, new, active = jax.lax.cond(following, follow, lambda: (
                Plan(*(jnp.broadcast_to(x, jnp.shape(new)) for x in plan)), new, active))
        return (t + 1, active, *apply(perm, labels, plan),
                count + new.astype(jnp.int32))

    init = (jnp.int32(0), jnp.asarray(True), perm, labels, keep.astype(jnp.int32))
    _, _, perm, labels, _ = jax.lax.while_loop(lambda c: c[1] & (c[0] < n), body, init)
    return perm, labels


def plan_mixed(key: Array, perm: Array, labels: Array, legs) -> Plan:
    """One of ``flip``, ``drop``, ``insert``, ``shift`` and ``repair``, uniformly.

    All five plans are made and one is kept (under ``vmap`` a ``switch`` computes them
    all anyway); the chromosome is made once."""
    which = int_from_words(_words(key, 1)[0], 0, len(PLANS))
    sub = jax.random.fold_in(key, 7)
    return select(which, [plan(sub, perm, labels, legs) for plan in PLANS])


def select(which: Array, plans) -> Plan:
    """Plan number ``which`` of ``plans`` (a select of int32 scalars)."""
    return Plan(*(jax.lax.select_n(which, *field) for field in zip(*plans)))


PLANS = (plan_flip, plan_drop, plan_insert, plan_shift, plan_repair)
"""The plans of the five moves, in the order ``mixed`` and ``guided`` draw them."""

PLAN_WORDS = ((_flip, 1), (_drop, 1), (_insert, 3), (_shift, 2), (_repair, 6))
"""The plans of :data:`PLANS` from their random words, and how many each reads."""

mixed = _moves(plan_mixed)
