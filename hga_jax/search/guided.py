"""The guided path move: the best of several candidate moves, judged by their legs.

``path_mutation = "guided"`` draws :data:`PER_MOVE` candidates from each move of
:mod:`hga_jax.search.path_ops` (flip, drop, insert, shift, repair: ten in all) and
keeps the one with the smallest :func:`leg_score`: the summed lengths of its legs
plus the fitness's penalty ``delta`` for every leg with a violation of its own. That
is the penalised length ``Dist_m`` without the arcs, read from the per-leg table
(:mod:`hga_jax.model.legs`) the way a TSP move reads a distance matrix.

Nothing is decoded: a guided move costs no evaluation, and the GA then evaluates
the child it made, as every child (a run still evaluates ``population x
(generations + 1)`` chromosomes). The score knows nothing of the arcs, whose length
and violations depend on the legs on both sides of them: a candidate whose legs are
short and clear may still collide on an arc, and only its evaluation tells.

Conventions as :mod:`hga_jax.search.path_ops`: one chromosome, ``perm`` (n,) and
positional labels (n + 2,), a key and the scenario's ``Legs`` (with ``length``,
``bad`` and ``penalty``); pure, jit- and vmap-able. Ties go to the first candidate
in the order above.
"""
from __future__ import annotations

import jax
import jax.numpy as jnp
from jax import Array

from . import path_ops
from .permutation import take

MOVES = (path_ops.flip, path_ops.drop, path_ops.insert, path_ops.shift, path_ops.repair)
PER_MOVE = 2
"""Candidates drawn from each move (measured: one each found the optimum less often on
held-out scenes, four each no more often for twice the time; docs/operators.md)."""


def leg_score(perm: Array, labels: Array, legs) -> Array:
    """Summed tangent lengths (m) of the legs of a chromosome's path, plus
    ``legs.penalty`` for each leg with a violation of its own (arcs left out)."""
    s = labels.shape[-1]
    ids, touched = path_ops.path_circles(perm, labels)
    nid = take(ids, path_ops.next_touched(touched))
    on = touched & (jnp.arange(s) < s - 1)
    length, bad = jnp.asarray(legs.length), jnp.asarray(legs.bad)
    per_leg = jnp.where(on, length[ids, nid] + jnp.where(bad[ids, nid], legs.penalty, 0.0), 0.0)
    # Added in position order, one add at a time: a reduction's order may depend on how
    # XLA vectorises the batch, and a run must score alike alone and in any batch.
    total = per_leg[0]
    for k in range(1, s):
        total = total + per_leg[k]
    return total


def guided(key: Array, perm: Array, labels: Array, legs) -> tuple[Array, Array]:
    """The candidate move (``PER_MOVE`` of each of :data:`MOVES`, each from its own key
    of ``split(key, 10)``, in that order) with the smallest :func:`leg_score`."""
    if legs.length is None:
        raise ValueError("the guided move needs Legs with lengths (Scenario.search_arrays)")
    keys = jax.random.split(key, len(MOVES) * PER_MOVE)
    cands = [MOVES[j // PER_MOVE](keys[j], perm, labels, legs) for j in range(len(keys))]
    best = jnp.argmin(jnp.stack([leg_score(p, lab, legs) for p, lab in cands]))
    # A select of the candidates, not a gather: 20% faster vmapped on the CPU.
    return (jax.lax.select_n(best, *[c[0] for c in cands]),
            jax.lax.select_n(best, *[c[1] for c in cands]))
