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
  information, :mod:`hga_jax.model.legs`) and wrap that obstacle, in a random
  direction, between the leg's two circles; without a blocked leg, an ``insert``;
- :func:`wrap_blockers` builds a whole path that way from the direct one (the
  GA's ``seeding``);
- ``mixed``: one of the five above, uniformly.

Conventions (as :mod:`hga_jax.search.perm_crossover`): every move works on ONE chromosome,
``perm`` (n,) and *positional* labels (n + 2,) (docs/model.md), and returns the
pair; it takes a key and the scenario's :class:`~hga_jax.model.legs.Legs` (only
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

from hga_jax.model.decode import position_circles
from .permutation import ONEHOT_MAX_N, int_from_words, take

Move = Callable[[Array, Array, Array, Any], tuple[Array, Array]]


def _words(key: Array, count: int) -> Array:
    return jax.random.bits(key, (count,), dtype=jnp.uint32)


def _choose(mask: Array, word: Array) -> tuple[Array, Array]:
    """A position uniform among the True entries of ``mask`` and whether there is one."""
    count = jnp.sum(mask, dtype=jnp.int32)
    r = int_from_words(word, 0, jnp.maximum(count, 1))
    idx = jnp.argmax(prefix_count(mask) > r).astype(jnp.int32)
    return idx, count > 0


def prefix_count(mask: Array) -> Array:
    """``cumsum(mask)`` (int32) of a short bool vector, as a product with a triangular
    matrix: exact (counts of ones, HIGHEST precision) and, vmapped over chromosomes on
    the CPU, about twice as fast as ``cumsum`` (a reduce-window) at n = 25."""
    s = mask.shape[-1]
    lower = jnp.tril(jnp.ones((s, s), jnp.float32))
    counts = jnp.matmul(lower, mask.astype(jnp.float32), precision=jax.lax.Precision.HIGHEST)
    return counts.astype(jnp.int32)


def move_apply(perm: Array, labels: Array, j: Array, i: Array, label: Array) -> tuple[Array, Array]:
    """The obstacle at position ``j`` moved to position ``i`` (0-based positions of
    the permutation), with label ``label``; the positions between shift by one."""
    n = perm.shape[-1]
    p = jnp.arange(n, dtype=jnp.int32)
    up = (j < i) & (p >= j) & (p < i)  # take position p + 1's
    down = (j > i) & (p > i) & (p <= j)  # take position p - 1's

    def moved(x, at_i):  # x[src] for src = j at i, p + 1 where up, p - 1 where down, p
        shift = jnp.where(up, jnp.concatenate([x[1:], x[-1:]]),
                          jnp.where(down, jnp.concatenate([x[:1], x[:-1]]), x))
        return jnp.where(p == i, at_i, shift)

    mid = labels[1:-1]
    return (moved(perm, take(perm, j[None])[0]),
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
    if perm.shape[-1]:
        perm, labels = move_apply(perm, labels, plan.j, plan.i, plan.label)
    pos = jnp.arange(labels.shape[-1], dtype=jnp.int32)
    return perm, jnp.where(pos == plan.end, -labels, labels)


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

def _flip(w: Array, perm: Array, labels: Array, legs: Any = None) -> Plan:
    movable = labels != 0
    if legs is not None and getattr(legs, "ends", None) is not None:
        movable = movable.at[0].set(False).at[-1].set(False)
    k, _ = _choose(movable, w[0])
    end = (k == 0) | (k == labels.shape[-1] - 1)
    return _plan(jnp.where(end, 0, k - 1), jnp.where(end, 0, k - 1),
                 jnp.where(end, labels[1], -take(labels, k[None])[0]), jnp.where(end, k, -1))


def _drop(w: Array, perm: Array, labels: Array, legs: Any = None) -> Plan:
    k, any_ = _choose(labels[1:-1] != 0, w[0])
    return _plan(k, k, jnp.where(any_, 0, labels[1]))


def _sign(word: Array) -> Array:
    return jnp.where((word >> 31) == 0, -1, 1).astype(jnp.int32)


def _relocation(j, i, label, ok, labels) -> Plan:
    """Move ``j`` to ``i`` with ``label`` where ``ok``, else nothing."""
    return _plan(jnp.where(ok, j, 0), jnp.where(ok, i, 0), jnp.where(ok, label, labels[1]))


def _insert(w: Array, perm: Array, labels: Array, legs: Any = None) -> Plan:
    n = perm.shape[-1]
    j, any_ = _choose(labels[1:-1] == 0, w[0])
    return _relocation(j, int_from_words(w[1], 0, n), _sign(w[2]), any_, labels)


def _shift(w: Array, perm: Array, labels: Array, legs: Any = None) -> Plan:
    n = perm.shape[-1]
    j, any_ = _choose(labels[1:-1] != 0, w[0])
    return _relocation(j, int_from_words(w[1], 0, n), take(labels[1:-1], j[None])[0], any_,
                       labels)


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
    """Circle ids (:mod:`hga_jax.model.tangents`) of the positions (n + 2,) and touched mask:
    :func:`hga_jax.model.decode.position_circles` for one chromosome."""
    ids, touched = position_circles(perm[None], labels[None])
    return ids[:, 0], touched[:, 0]


def blocked_legs(perm: Array, labels: Array, legs) -> tuple[Array, Array, Array]:
    """Per position ``k`` (n + 2,): its circle id, the position of the next touched
    circle, and whether the leg from ``k`` to it passes through an obstacle (False
    from untouched positions and the goal)."""
    s = labels.shape[-1]
    ids, touched = path_circles(perm, labels)
    pos = jnp.arange(s, dtype=jnp.int32)
    nxt_id = take(ids, next_touched(touched))
    blocked = jnp.asarray(legs.blocked)[ids, nxt_id] & touched & (pos < s - 1)
    return ids, nxt_id, blocked


def next_touched(touched: Array) -> Array:
    """Per position ``k`` (n + 2,) the first touched position after ``k`` (the goal's,
    ``n + 1``, for the goal itself). Up to :data:`~hga_jax.search.permutation.ONEHOT_MAX_N`
    obstacles, O(n^2) comparisons (vmapped on the CPU, 4 times faster than a reversed
    running minimum, ``cummin``, at n = 25); beyond, a suffix minimum in log2(n + 2)
    steps of shifted minima (the recommended preset's search 10 % faster at 25
    obstacles and 30 % at 40, the same bits; at 9 the comparisons are faster)."""
    s = touched.shape[-1]
    pos = jnp.arange(s, dtype=jnp.int32)
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


def _wrap_one(w: Array, perm: Array, labels: Array, legs,
              found=None) -> tuple[Plan, Array]:
    """``repair`` without its fallback, from its three words: its plan and whether a leg
    was blocked (``found``: :func:`blocked_legs` of the chromosome, if made already)."""
    return _wrap(w, perm, labels, legs,
                 *(blocked_legs(perm, labels, legs) if found is None else found))


def _wrap(w: Array, perm: Array, labels: Array, legs, ids: Array, nxt_id: Array,
          blocked: Array) -> tuple[Plan, Array]:
    """The wrap's rule, given per position its circle, the next touched circle's and
    whether the leg between them is blocked: a blocked leg (word 0), one of its
    blockers (word 1), a direction (word 2), put right after the leg's first circle."""
    k, any_leg = _choose(blocked, w[0])
    a, c = ids[k], nxt_id[k]
    o, _ = _choose(jnp.asarray(legs.blockers)[a, c], w[1])  # the blocking obstacle
    # Both directions alike: preferring the side away from the obstacle's centre
    # (3 in 4) found the optimum less often on held-out obstructed scenes (98.0%
    # against 99.7% of runs with flips, seeding and restarts).
    label = _sign(w[2])
    j = jnp.argmax(perm == o).astype(jnp.int32)  # o's position
    q = k - 1  # the leg's first circle, as a permutation position (-1: the start)
    ok = any_leg & (j != q)
    return _relocation(j, jnp.where(j > q, q + 1, q), label, ok, labels), ok


def _repair(w: Array, perm: Array, labels: Array, legs, found=None) -> Plan:
    """Six words: the wrap's three, then the fallback insert's three."""
    wrap, ok = _wrap_one(w[:3], perm, labels, legs, found)
    other = _insert(w[3:], perm, labels)
    return Plan(*(jnp.where(ok, a, b) for a, b in zip(wrap, other)))


def plan_repair(key: Array, perm: Array, labels: Array, legs, found=None) -> Plan:
    """Wrap an obstacle that blocks a leg between the leg's circles (see module doc);
    ``found``: :func:`blocked_legs` of the chromosome, if made already."""
    k1, k2 = jax.random.split(key)
    w = jnp.concatenate([_words(k1, 3), _words(k2, 3)])
    return _repair(w, perm, labels, legs, found)


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
    ``3t .. 3t + 2`` of ``3n`` drawn from ``key``)."""
    n = perm.shape[-1]
    keep = jnp.asarray(via) & (labels[1] != 0)
    labels = labels.at[1:-1].set(0).at[1].set(jnp.where(keep, labels[1], 0))
    pos = jnp.arange(n + 2, dtype=jnp.int32)
    table = jnp.asarray(legs.blocked)
    words = _words(key, 3 * n)

    def body(t, carry):
        perm, labels, count = carry  # the touched obstacles: positions 1..count
        ids, _ = path_circles(perm, labels)
        nxt = jnp.where(pos < count, jnp.concatenate([ids[1:], ids[-1:]]), ids[-1])
        w = jax.lax.dynamic_slice_in_dim(words, 3 * t, 3)
        plan, ok = _wrap(w, perm, labels, legs, ids, nxt, table[ids, nxt] & (pos <= count))
        new = ok & (plan.j >= count)  # an untouched obstacle wrapped
        return (*apply(perm, labels, plan), count + new.astype(jnp.int32))

    perm, labels, _ = jax.lax.fori_loop(0, n, body, (perm, labels, keep.astype(jnp.int32)))
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
