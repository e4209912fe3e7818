"""Crossovers of the upper module: cycle (cx), partially mapped (pmx), order (ox1).

Conventions (permutations and cut points as :mod:`hga_jax.search.permutation`):

- Every crossover works on ONE pair of parents ``a, b`` (int32 permutations
  (n,) of ``0..n-1``) and returns two children; the GA maps it over pairs and
  runs with :func:`jax.vmap`. Shapes depend on ``n`` only, so everything jits;
  there is no data-dependent Python control flow.
- Each is split into a random ``*_draw`` step (the only place a key is used) and
  a deterministic ``*_apply`` step, so worked examples can be tested;
  ``op(key, a, b)`` is ``op_apply(a, b, *op_draw(key, n))``.
- The cycle crossover walks its one cycle (``n - 1`` scalar look-ups); PMX
  follows its mapping by pointer jumping.

The settings' names are those of :mod:`hga_jax.search.registry` (``perm_crossover``).
"""
from __future__ import annotations

import jax
import jax.numpy as jnp
from jax import Array

from . import permutation as pm


# --- Cycle crossover ---------------------------------------------------------

def cx_draw(key: Array, n: int) -> Array:
    """The cycle start: a position uniform in ``0..n-1``."""
    return pm.uniform_int(key, (), 0, n)


def cx_apply(a: Array, b: Array, start: Array) -> tuple[Array, Array]:
    """Cycle crossover (Oliver et al.) of the one cycle through ``start``.

    The position map ``i -> position in a of b[i]`` splits the positions into
    cycles. ``c1`` takes the cycle containing position ``start`` from ``a`` and
    every other position from ``b``; ``c2`` is the mirror (the cycle from ``b``,
    the rest from ``a``). Every child position therefore holds the value of one
    parent at that position, and ``c1[start] == a[start]``.
    """
    n = a.shape[-1]
    step = pm.take(pm.inverse(a), b)  # next position along the cycle
    pos = jnp.arange(n, dtype=jnp.int32)
    # Walk the cycle from start: n - 1 scalar look-ups (a cycle has at most n
    # positions). Pointer jumping over whole vectors (2 log2 n vector look-ups)
    # measured twice as slow at n = 9, and does n times more work at any n.
    if n > pm.ONEHOT_MAX_N:
        # The walk's positions in a scan, marked afterwards by one scatter: marking
        # them inside the loop cost an (n,) vector operation per step (cycle
        # crossover at n = 100, 5,000 pairs: 6.4 instead of 9.3 ms of CPU).
        def visit(cur, _):
            cur = step[cur]
            return cur, cur

        seq = jax.lax.scan(visit, start, None, length=n - 1)[1]
        hit = jnp.zeros((n,), jnp.bool_).at[seq].set(True).at[start].set(True)
        return jnp.where(hit, a, b), jnp.where(hit, b, a)

    def walk(_, carry):
        hit, cur = carry
        cur = step[cur]
        return hit | (pos == cur), cur

    hit = pm.chain(n - 1, walk, (pos == start, start))[0]
    return jnp.where(hit, a, b), jnp.where(hit, b, a)


def cx(key: Array, a: Array, b: Array) -> tuple[Array, Array]:
    """Cycle crossover with a random cycle start (see :func:`cx_apply`)."""
    return cx_apply(a, b, cx_draw(key, a.shape[-1]))


# --- Partially mapped crossover ------------------------------------------------

def pmx_draw(key: Array, n: int) -> tuple[Array, Array]:
    """PMX segment ``[lo, hi)``, uniform over ``0 <= lo < hi <= n``."""
    return pm.cut_draw(key, n)


def _pmx_child(a: Array, b: Array, seg: Array) -> Array:
    """Child with ``a``'s segment, the rest from ``b`` through the PMX mapping."""
    n = a.shape[-1]
    # m[v]: for v in a's segment at position p, b[p]; otherwise v itself.
    # A value of b outside the segment that a's segment already holds is
    # replaced by following m until it leaves a's segment (at most n steps).
    m = pm.take(jnp.where(seg, b, a), pm.inverse(a))
    m = pm.chain(pm.rounds(n), lambda _, m: pm.take(m, m), m)
    return jnp.where(seg, a, pm.take(m, b))


def pmx_apply(a: Array, b: Array, lo: Array, hi: Array) -> tuple[Array, Array]:
    """Partially mapped crossover (Eiben & Smith) with segment ``[lo, hi)``.

    ``c1`` copies ``a[lo:hi]``; each other position takes ``b``'s value, and a
    value of ``b`` that the copied segment already holds is mapped through the
    segment's value pairs ``a[p] -> b[p]`` until it is free (the textbook
    placement of ``b``'s segment values, written position by position).
    ``c2`` is the mirror.
    """
    seg = pm.segment(a.shape[-1], lo, hi)
    return _pmx_child(a, b, seg), _pmx_child(b, a, seg)


def pmx(key: Array, a: Array, b: Array) -> tuple[Array, Array]:
    """PMX with a random segment (see :func:`pmx_apply`)."""
    return pmx_apply(a, b, *pmx_draw(key, a.shape[-1]))


# --- Order crossover -----------------------------------------------------------

def ox1_draw(key: Array, n: int) -> tuple[Array, Array]:
    """OX1 segment ``[lo, hi)``, uniform over ``0 <= lo < hi <= n``."""
    return pm.cut_draw(key, n)


def _ox1_child(a: Array, b: Array, lo: Array, hi: Array) -> Array:
    n = a.shape[-1]
    seg = pm.segment(n, lo, hi)
    # b read from position hi on, wrapping; keep the values a's segment lacks.
    b_rot = jnp.roll(b, -hi)
    taken = pm.take(pm.take(seg, pm.inverse(a)), b_rot)
    rank = jnp.cumsum(~taken, dtype=jnp.int32) - 1
    # The kept value of rank r goes to free position (hi + r) mod n.
    filled = pm.place(b_rot, jnp.where(taken, n, (hi + rank) % n))
    return jnp.where(seg, a, filled)


def ox1_apply(a: Array, b: Array, lo: Array, hi: Array) -> tuple[Array, Array]:
    """Order crossover OX1 (Eiben & Smith) with segment ``[lo, hi)``.

    ``c1`` keeps ``a[lo:hi]``; the other positions, from ``hi`` on and wrapping
    around, receive ``b``'s values in ``b``'s order read from position ``hi``
    (wrapping), skipping values already in the segment. ``c2`` is the mirror.
    """
    return _ox1_child(a, b, lo, hi), _ox1_child(b, a, lo, hi)


def ox1(key: Array, a: Array, b: Array) -> tuple[Array, Array]:
    """OX1 with a random segment (see :func:`ox1_apply`)."""
    return ox1_apply(a, b, *ox1_draw(key, a.shape[-1]))
