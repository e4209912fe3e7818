"""The guided move with paired flips: each candidate also tried with a neighbour turned.

``path_mutation = "guided_pairs"`` is :mod:`hga_jax.search.guided`'s move (ten
candidate moves from the same words, scored by the change they make to the leg
score) with two more versions of each candidate: the candidate made, then the
direction (label) of one touched circle beside the moved obstacle reversed, the one
before its new place or the one after it (for a candidate that only drops its
obstacle, before or after the place it left; start and goal circles included). The
best of the thirty is made; ties go to the candidate alone, then to the circle
before. For a reversing car (legs with ``ends``, its tangents' legs too) the move is
the guided move's (:func:`guided_pairs_one`): its runs are those of ``guided``.

Why: where an obstacle enters or leaves a path, the best way round its neighbour
often changes with it. On development scenes the runs that missed the optimum ended
on feasible paths one such pair away from it (insert an obstacle and turn its next
neighbour the other way; drop one and turn its previous neighbour), where each half
alone makes the path longer or blocked, so neither a single move nor selection
crosses over (docs/results.md).

A turn changes the two legs at the turned circle (a start or goal circle: its one
leg, with its end arc), read from the moved obstacle's places and one look-up of the
circle's far neighbour, so a version costs a few look-ups more than its candidate,
whatever the length of the path; with the arcs table (``guided_arcs``) the turned
circle's own arc counts too, and the moved obstacle's arc is read beside it. Nothing
is decoded (no evaluation is spent); the GA evaluates the child it made. Conventions
as :mod:`hga_jax.search.guided`; pure, jit- and vmap-able.
"""
from __future__ import annotations

import jax.numpy as jnp
from jax import Array

from . import guided, path_ops
from .guided import Places
from .path_ops import Plan
from .permutation import pick, take

WORDS = guided.WORDS
"""Random words one move reads: the guided move's (the versions draw none)."""
SIDES = ("before", "after")
"""The neighbours that a candidate's versions turn, in their order: the touched circle
before the moved obstacle's new place and the one after it (for a candidate that only
drops its obstacle, before and after the place it left)."""


def flips(plan: Plan, at: Places, labels: Array, v: path_ops.View, w: Array,
          arcs: Array | None = None, arc_penalty: Array | float = 0.0) -> tuple[Array, Array]:
    """For each candidate and each of :data:`SIDES`: the change of the leg score that
    turning that neighbour adds to the candidate's own (``inf`` for a candidate that
    moves nothing or flips an end itself), and the chromosome position that neighbour
    takes in the candidate's chromosome (the plan's ``end``): two arrays (2,
    candidates, ...)."""
    s = labels.shape[0]
    before = take(v.ids, v.prev)  # per position the circle of the last touched one before it
    enters = at.enters
    x0, x1 = jnp.where(enters, at.p2, at.p), jnp.where(enters, at.q2, at.q)
    c0, c1 = jnp.where(enters, at.c2p, at.cp), jnp.where(enters, at.c2q, at.cq)
    # the circles beside them once the plan is made: the moved obstacle between them
    # (where it enters), each other (where it only leaves), and on their far sides
    # their own neighbours, the moved obstacle's old ones where it stood there
    mid0 = jnp.where(enters, at.c_new, c1)
    mid1 = jnp.where(enters, at.c_new, c0)
    far0 = pick(before, x0)
    far0 = jnp.where(far0 == at.c_old, at.cp, far0)
    far1 = pick(v.nxt_id, x1)
    far1 = jnp.where(far1 == at.c_old, at.cq, far1)
    start, goal = x0 == 0, x1 == s - 1

    def turned(b, c, a, no_b, no_a):  # the legs b -> c and c -> a with c turned
        return (jnp.where(no_b, 0.0, w[b, c ^ 1] - w[b, c])
                + jnp.where(no_a, 0.0, w[c ^ 1, a] - w[c, a]))

    d0 = turned(far0, c0, mid0, start, False)
    d1 = turned(mid1, c1, far1, False, goal)
    if arcs is not None:  # the turned circle's own arc, and the moved obstacle's beside it
        t = jnp.asarray(arcs)

        def arc(b, c, a):
            return t[b, c, a].astype(w.dtype)

        moved = arc(at.c2p, at.c_new, at.c2q)
        d0 = d0 + arc_penalty * (jnp.where(start, 0.0, arc(far0, c0 ^ 1, mid0) - arc(far0, c0, mid0))
                                 + jnp.where(enters, arc(at.c2p ^ 1, at.c_new, at.c2q) - moved, 0.0))
        d1 = d1 + arc_penalty * (jnp.where(goal, 0.0, arc(mid1, c1 ^ 1, far1) - arc(mid1, c1, far1))
                                 + jnp.where(enters, arc(at.c2p, at.c_new, at.c2q ^ 1) - moved, 0.0))
    ok = (enters | at.was) & (plan.end < 0)
    return (jnp.stack([jnp.where(ok, d0, jnp.inf), jnp.where(ok, d1, jnp.inf)]),
            jnp.stack([_after(plan, x0, s), _after(plan, x1, s)]))


def _after(plan: Plan, x: Array, s: int) -> Array:
    """Chromosome position ``x`` (not the moved obstacle's) once ``plan`` is made: the
    positions between the moved obstacle's old and new place shift by one."""
    m = x - 1  # as a permutation position
    m = jnp.where((plan.j < plan.i) & (m > plan.j) & (m <= plan.i), m - 1,
                  jnp.where((plan.j > plan.i) & (m >= plan.i) & (m < plan.j), m + 1, m))
    return jnp.where((x == 0) | (x == s - 1), x, m + 1)


def guided_pairs_one(w: Array, perm: Array, labels: Array, legs) -> tuple[Array, Array]:
    """The best of the guided move's candidates (:func:`guided.candidates`) and their
    :func:`flips` versions (the first of equals: the candidates alone first), made.
    For a car whose ends are the end move's (``legs.ends``: a reversing car) this is
    the guided move itself: on the Reeds-Shepp study's `obstructed` scenes at 9
    obstacles the versions took two scenes from 100 and 95 % of runs to 82 and 77 %
    (docs/results.md)."""
    if getattr(legs, "ends", None) is not None:
        return guided.guided_one(w, perm, labels, legs)
    stacked, at, scores, v, wt = guided.candidates(w, perm, labels, legs)
    arcs, charge = guided.arc_terms(legs)
    extra, ends = flips(stacked, at, labels, v, wt, arcs, charge)
    k = scores.shape[0]
    best = guided.first_min(jnp.concatenate([scores, (scores[None] + extra).reshape(
        (-1,) + scores.shape[1:])]))
    base, side = best % k, best // k
    plan = Plan(*(pick(field, base) for field in stacked))
    end = pick(jnp.concatenate([plan.end[None], pick(ends.swapaxes(0, 1), base)]), side)
    return path_ops.apply(perm, labels, plan._replace(end=end))


def guided_pairs(key: Array, perm: Array, labels: Array, legs) -> tuple[Array, Array]:
    """:func:`guided_pairs_one` on :data:`WORDS` words drawn from ``key``."""
    return guided_pairs_one(path_ops._words(key, WORDS), perm, labels, legs)


def guided_pairs_from_words(words: Array, perm: Array, labels: Array, legs
                            ) -> tuple[Array, Array]:
    """The GA's form (:func:`guided.guided_from_words`'s layout)."""
    perm, labels = guided_pairs_one(words.T, perm.T, labels.T, legs)
    return perm.T, labels.T
