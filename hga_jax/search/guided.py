"""The guided path move: the best of several candidate moves, judged by their legs.

``path_mutation = "guided"`` draws :data:`PER_MOVE` candidates from each move of
:mod:`hga_jax.search.path_ops` (flip, drop, insert, shift, repair: ten in all) and
keeps the one with the smallest :func:`leg_score`: the summed lengths of its legs
plus the fitness's penalty ``delta`` for every leg with a violation of its own (the
first leg carries the start arc and the last the goal arc, which depend on that leg
alone). That is the penalised length ``Dist_m`` without the arcs on obstacles'
circles, read from the per-leg table (:mod:`hga_jax.model.legs`) the way a TSP move
reads a distance matrix.

A candidate is scored by the change it makes (:func:`change`), as a 2-opt move is
scored in a TSP: a move relocates one obstacle (or flips one end), so it removes at
most three legs and adds at most three, whatever the length of the path; the
candidates are plans (:class:`~hga_jax.search.path_ops.Plan`), and only the chosen
one is made. The change is a fixed sum of at most six table entries, so a run scores
alike alone and in any batch.

Nothing is decoded: a guided move costs no evaluation, and the GA then evaluates
the child it made, as every child (a run still evaluates ``population x
(generations + 1)`` chromosomes). The arcs on obstacles' circles depend on the legs on
both sides of them: their lengths the score leaves out. Their violations it may read
(``guided_arcs``, :func:`change`): an arc runs into another obstacle only where the
two model circles overlap (a barrier, a clump), and the turn table says which turns
do, as the leg table says which legs do; the score then counts the moved obstacle's
own arc where it leaves and where it enters (its neighbours' arcs, which change too,
it does not read). Otherwise a candidate whose legs are short and clear may still
collide on an arc, and only its evaluation tells.

Conventions as :mod:`hga_jax.search.path_ops`: one chromosome, ``perm`` (n,) and
positional labels (n + 2,), or a population laid out after the positions (the GA's
form, :func:`guided_from_words`), a key and the scenario's ``Legs`` (with ``length``,
``bad`` and ``penalty``); pure, jit- and vmap-able. Ties go to the first candidate
in the order above.
"""
from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
from jax import Array

from hga_jax.model import circle_ids

from . import path_ops
from .path_ops import Plan
from .permutation import pick, take

MOVES = (path_ops.flip, path_ops.drop, path_ops.insert, path_ops.shift, path_ops.repair)
PLANS = path_ops.PLANS
"""The plans of :data:`MOVES`, in their order."""
PER_MOVE = 2
"""Candidates drawn from each move (measured: one each found the optimum less often on
held-out scenes, four each no more often for twice the time; docs/operators.md)."""


def weights(legs) -> Array:
    """The score of every leg (C, C): its tangent length (m) plus ``legs.penalty`` if
    it has a violation of its own."""
    return jnp.asarray(legs.length) + jnp.where(jnp.asarray(legs.bad), legs.penalty, 0.0)


def leg_score(perm: Array, labels: Array, legs) -> Array:
    """Summed tangent lengths (m) of the legs of a chromosome's path, plus
    ``legs.penalty`` for each leg with a violation of its own (the start and goal arcs
    counted in the first and last legs, the arcs on obstacles' circles left out)."""
    s = labels.shape[-1]
    ids, touched = path_ops.path_circles(perm, labels)
    nid = take(ids, path_ops.next_touched(touched))
    on = touched & (jnp.arange(s) < s - 1)
    per_leg = jnp.where(on, weights(legs)[ids, nid], 0.0)
    # Added in position order, one add at a time: a reduction's order may depend on how
    # XLA vectorises the batch, and a run must score alike alone and in any batch (the
    # search scores moves by :func:`change`; this whole sum is their definition).
    total = per_leg[0]
    for k in range(1, s):
        total = total + per_leg[k]
    return total


class Places(NamedTuple):
    """Where a plan's obstacle (at chromosome position ``r``) leaves and enters, as
    chromosome positions of the path before the plan (int32, one per candidate and
    chromosome): its touched neighbours ``p`` and ``q`` where it leaves (if it ``was``
    touched), and ``p2`` and ``q2``, the touched circles other than it that it enters
    between (if it ``enters``, with circle ``c_new``); and the circles at ``r``, ``p``,
    ``q``, ``p2`` and ``q2`` (``c_old``, ``cp``, ``cq``, ``c2p``, ``c2q``)."""

    r: Array
    was: Array
    p: Array
    q: Array
    p2: Array
    q2: Array
    enters: Array
    c_new: Array
    c_old: Array
    cp: Array
    cq: Array
    c2p: Array
    c2q: Array


def places(plan: Plan, perm: Array, v: path_ops.View) -> Places:
    """The :class:`Places` of ``plan`` (read from the view's running neighbours)."""
    n = perm.shape[0]
    # the obstacle leaves: position r between its touched neighbours p and q
    r = plan.j + 1
    was = pick(v.touched, r) & (n > 0)
    p, q = pick(v.prev, r), pick(v.nxt, r)
    # and enters between the touched circles that end up around permutation position
    # i: after the last touched one other than r among the permutation positions
    # before i (with r's obstacle taken out: up to i when it moves forward), and before
    # the first touched one other than r after that
    bound = jnp.where(plan.i > plan.j, plan.i + 1, plan.i) + 1  # as a chromosome position
    p2 = pick(v.prev, bound)
    p2 = jnp.where(p2 == r, p, p2)
    q2 = pick(v.nxt, p2)
    q2 = jnp.where(q2 == r, q, q2)
    o = pick(perm, plan.j) if n else jnp.int32(0)
    c_new = circle_ids.obstacle(o, circle_ids.side(plan.label))
    return Places(r, was, p, q, p2, q2, (plan.label != 0) & (n > 0), c_new,
                  *(pick(v.ids, x) for x in (r, p, q, p2, q2)))


def change(plan: Plan, perm: Array, labels: Array, v: path_ops.View, w: Array,
           arcs: Array | None = None, arc_penalty: Array | float = 0.0,
           at: Places | None = None) -> Array:
    """:func:`leg_score` of the chromosome ``plan`` makes minus that of ``(perm,
    labels)`` (``v``: its :func:`path_ops.view`; ``w``: :func:`weights`; ``at``: the
    plan's :func:`places`, if made already), from the legs the plan removes and adds:
    the obstacle at position ``j`` leaves its place between its touched neighbours (if
    it was touched) and enters its new one (if its label is not 0); a flipped end
    changes its one leg. Both sums are formed in one order, so a plan that changes
    nothing scores 0. Every place is read from the view's running neighbours, a few
    look-ups per candidate whatever the length of the path. ``plan`` may hold several
    candidates along leading axes of its own (scored side by side).

    With ``arcs`` (:func:`hga_jax.model.legs.arcs_from_turns`), the moved obstacle's
    arc counts too: ``arc_penalty`` more where its arc at the new place has a violation
    of its own, less where its arc at the old place had one (its neighbours' arcs,
    which change as well, are not read)."""
    at = places(plan, perm, v) if at is None else at

    def W(a, b, on=True):
        return jnp.where(on, w[a, b], 0.0)

    c_old, cp, cq, c2p, c2q = at.c_old, at.cp, at.cq, at.c2p, at.c2q
    was, enters, c_new = at.was, at.enters, at.c_new
    # an end flipped: its one leg (circles flip by their last bit); the four legs are
    # looked up once per chromosome, not per candidate (per candidate they cost 3.2 of
    # the 8.3 ms of view, plans and scores of 1,000 runs x 50 at 9 obstacles)
    flipped = plan.end >= 0
    first = plan.end <= 0
    before_goal = pick(v.ids, v.prev[-1])
    start_leg, goal_leg = (v.ids[0], v.nxt_id[0]), (before_goal, v.ids[-1])
    old_end = jnp.where(first, W(*start_leg), W(*goal_leg))
    new_end = jnp.where(first, W(start_leg[0] ^ 1, start_leg[1]), W(goal_leg[0], goal_leg[1] ^ 1))
    old_end, new_end = jnp.where(flipped, old_end, 0.0), jnp.where(flipped, new_end, 0.0)
    added = W(c2p, c_new, enters) + W(c_new, c2q, enters) + W(cp, cq, was) + new_end
    removed = W(cp, c_old, was) + W(c_old, cq, was) + W(c2p, c2q, enters) + old_end
    if arcs is not None:
        a = jnp.asarray(arcs)
        added = added + jnp.where(enters & a[c2p, c_new, c2q], arc_penalty, 0.0)
        removed = removed + jnp.where(was & a[cp, c_old, cq], arc_penalty, 0.0)
    return added - removed


WORDS = PER_MOVE * sum(count for _, count in path_ops.PLAN_WORDS)
"""Random words (uint32) one guided move reads: its candidates', in :data:`PLANS` order."""


def candidates(w: Array, perm: Array, labels: Array, legs):
    """The guided move's candidates and their scores: ``(plans, places, scores, view,
    weights)``, the plans (:class:`~hga_jax.search.path_ops.Plan`) stacked along a
    leading axis of candidates (``PER_MOVE`` of each of :data:`MOVES`, in that order,
    each from its own words of ``w``, :data:`WORDS` in all), scored by :func:`change`.

    The chromosome's :func:`~hga_jax.search.path_ops.view` is made once; a move's
    candidates are planned side by side (a leading axis of ``PER_MOVE``), and the ten
    plans are scored together by one :func:`change` (about a quarter less time and a
    smaller program than scoring them one after another in a loop)."""
    if legs.length is None:
        raise ValueError("the guided move needs Legs with lengths (Scenario.search_arrays)")
    v = path_ops.view(perm, labels, legs)  # made once, for every candidate
    plans, at, shape = [], 0, perm.shape[1:]
    for make, count in path_ops.PLAN_WORDS:  # a move's candidates side by side
        block = w[at:at + PER_MOVE * count].reshape((PER_MOVE, count) + w.shape[1:])
        plan = make(jnp.swapaxes(block, 0, 1), perm, labels, legs, v)
        plans.append(Plan(*(jnp.broadcast_to(x, (PER_MOVE,) + shape) for x in plan)))
        at += PER_MOVE * count
    wt = weights(legs)
    stacked = Plan(*(jnp.concatenate(field) for field in zip(*plans)))  # (candidates, ...)
    where = places(stacked, perm, v)
    arcs, charge = arc_terms(legs)
    return stacked, where, change(stacked, perm, labels, v, wt, arcs, charge, where), v, wt


def arc_terms(legs):
    """``(arcs, arc_penalty)`` of :func:`change` for ``legs``: the arcs table and the
    share of the penalty the GA set (``guided_arcs``), or ``(None, 0.0)``."""
    if legs.arc_share is None:
        return None, 0.0
    return legs.arcs, legs.penalty * legs.arc_share


def guided_one(w: Array, perm: Array, labels: Array, legs) -> tuple[Array, Array]:
    """The candidate move (:func:`candidates`) whose :func:`change` of the leg score is
    the smallest (the first of equals), made."""
    stacked, _, scores, _, _ = candidates(w, perm, labels, legs)
    best = first_min(scores)
    return path_ops.apply(perm, labels, Plan(*(pick(field, best) for field in stacked)))


def first_min(scores: Array) -> Array:
    """``argmin(scores, axis=0)`` (the first of equals) for scores without NaN (leg
    scores are finite), as a pass over the leading axis. XLA on the CPU fuses the
    scoring into an ``argmin`` (a reduce of value and index, element by element); the
    pass keeps the scoring vector work across the population (the guided move on
    1,000 runs x 50 at 9 obstacles: 9.1 -> 6.6 ms)."""
    def better(carry, row):
        value, at = carry
        score, k = row
        less = score < value
        return (jnp.where(less, score, value), jnp.where(less, k, at)), None

    init = (scores[0], jnp.zeros(scores.shape[1:], jnp.int32))
    (_, best), _ = jax.lax.scan(better, init, (scores[1:], jnp.arange(1, scores.shape[0],
                                                                     dtype=jnp.int32)))
    return best


def guided(key: Array, perm: Array, labels: Array, legs) -> tuple[Array, Array]:
    """:func:`guided_one` on :data:`WORDS` words drawn from ``key``."""
    return guided_one(path_ops._words(key, WORDS), perm, labels, legs)


def guided_from_words(words: Array, perm: Array, labels: Array, legs) -> tuple[Array, Array]:
    """The GA's form: :func:`guided_one` for a population, ``words`` (P, :data:`WORDS`)
    the rows of the generation's draw, ``perm`` (P, n), positional ``labels`` (P, n + 2).
    The population is laid out after the positions, so that every step is vector work
    across it (with the view and the candidates scored together: 19 -> 10 ms per
    generation of 1,000 runs at 9 obstacles against the move vmapped chromosome by
    chromosome; docs/performance.md)."""
    perm, labels = guided_one(words.T, perm.T, labels.T, legs)
    return perm.T, labels.T
