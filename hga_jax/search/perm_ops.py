"""Genetic operators on the upper module: permutations of obstacle indices.

Conventions:

- A permutation is a 1-D ``int32`` array holding each of ``0..n-1`` once
  (``n >= 1``; the fixed start and goal genes are not part of it).
- Every operator works on ONE individual or ONE pair of parents; the GA maps it
  over pairs and runs with :func:`jax.vmap`. Shapes depend on ``n`` only, so
  everything jits; there is no data-dependent Python control flow.
- Each operator is split into a random ``*_draw`` step (the only place a key is
  used) and a deterministic ``*_apply`` step, so worked examples can be tested;
  ``op(key, ...)`` is ``op_apply(..., *op_draw(key, n))``.
- Random integers come from :func:`uniform_int` (one 32-bit word each).
- Cut points: ``0 <= lo < hi <= n``, drawn uniformly over all such pairs; the
  segment is the half-open position range ``[lo, hi)``.
- Gathers and scatters run element by element on the XLA CPU backend, so for
  small ``n`` (up to :data:`ONEHOT_MAX_N`) look-ups are one-hot comparisons
  (``O(n^2)`` vector work); for larger ``n`` they are gathers and scatters.
  Chains of look-ups use pointer jumping (``ceil(log2 n)`` rounds); the cycle
  crossover walks its one cycle instead (``n - 1`` scalar look-ups).

Crossovers return two children; mutations return one permutation.
"""
from __future__ import annotations

from typing import Callable

import jax
import jax.numpy as jnp
from jax import Array

from .rng import unit

Crossover = Callable[[Array, Array, Array], tuple[Array, Array]]
Mutation = Callable[[Array, Array], Array]


# Up to this n, look-ups are one-hot selects; above it, gathers and scatters.
# Read at trace time. Measured on the XLA CPU backend (batches of 5,000 pairs):
# one-hot was up to 2x faster for n <= 20 and about even at n = 25; at n = 50
# it was 7-12x slower, its (n, n) intermediates no longer fitting the cache.
ONEHOT_MAX_N = 20


def _rounds(n: int) -> int:
    """Pointer-jumping rounds so that ``2**rounds >= n``."""
    return max(0, (n - 1).bit_length())


def _take(x: Array, idx: Array) -> Array:
    """``x[idx]`` for 1-D ``x`` and in-range ``idx``.

    Small ``n``: a one-hot select (vector work only); large ``n``: a gather.
    """
    n = x.shape[-1]
    if n > ONEHOT_MAX_N:
        return x[idx]
    hit = idx[:, None] == jnp.arange(n, dtype=idx.dtype)
    if x.dtype == jnp.bool_:
        return jnp.any(hit & x, axis=-1)
    return jnp.sum(jnp.where(hit, x, 0), axis=-1, dtype=x.dtype)


def _place(values: Array, targets: Array) -> Array:
    """``out[targets[k]] = values[k]``; targets outside ``0..n-1`` are dropped,
    positions no target names hold 0. Targets must not repeat."""
    n = values.shape[-1]
    if n > ONEHOT_MAX_N:
        return jnp.zeros_like(values).at[targets].set(values, mode="drop")
    hit = targets[None, :] == jnp.arange(n, dtype=targets.dtype)[:, None]
    return jnp.sum(jnp.where(hit, values, 0), axis=-1, dtype=values.dtype)


def _chain(steps: int, body: Callable, init):
    """``init`` after ``steps`` dependent look-up steps ``body(i, carry)``.

    Small ``n``: unrolled. Large ``n``: a ``fori_loop``, which XLA cannot fuse into
    the consumers; fused, a chain of gathers was recomputed for every element that
    uses it (cycle crossover at n = 100: 83 ms against 12 ms per generation of
    5,000 pairs).
    """
    if len(jax.tree.leaves(init)) and jax.tree.leaves(init)[0].shape[-1:] and \
            jax.tree.leaves(init)[0].shape[-1] > ONEHOT_MAX_N:
        return jax.lax.fori_loop(0, steps, body, init)
    for i in range(steps):
        init = body(i, init)
    return init


def _inverse(p: Array) -> Array:
    """The inverse permutation: ``_inverse(p)[p[i]] == i``."""
    return _place(jnp.arange(p.shape[-1], dtype=p.dtype), p)


def uniform_int(key: Array, shape: tuple[int, ...], low: int | Array, high: int | Array) -> Array:
    """Integers uniform in ``[low, high)`` (``int32``; ``high - low`` at most ~2**20).

    One 32-bit random word per integer (``jax.random.randint`` spends two):
    its top 24 bits scale the range, so the bias is below ``(high - low) / 2**24``.
    """
    return int_from_words(jax.random.bits(key, shape, dtype=jnp.uint32), low, high)


def int_from_words(words: Array, low: int | Array, high: int | Array) -> Array:
    """:func:`uniform_int` from given uint32 words (one integer per word)."""
    span = jnp.asarray(high - low, jnp.float32)
    k = jnp.floor(unit(words) * span).astype(jnp.int32)
    return low + jnp.minimum(k, (high - low) - 1)


def random_permutation(key: Array, n: int, shape: tuple[int, ...] = ()) -> Array:
    """Uniformly random permutations of ``0..n-1`` (``int32``, shape ``shape + (n,)``).

    Each is the stable argsort of ``n`` random 32-bit words (a tie, below
    ``n**2 / 2**33`` in probability, keeps the lower index first). A whole
    population is one draw and one sort: cheap to compile and run.
    """
    return permutation_from_words(jax.random.bits(key, tuple(shape) + (n,), dtype=jnp.uint32))


RANK_MAX_N = 32  # up to here permutations are ranked by comparisons rather than sorted


def permutation_from_words(words: Array) -> Array:
    """:func:`random_permutation` from given uint32 words (``n`` per permutation, last axis).

    Up to ``RANK_MAX_N`` genes the stable argsort is computed by counting, for
    each word, the words that come before it (smaller, or equal at a lower index)
    and inverting those ranks by comparison: the same permutation, and on the CPU
    8-18x faster than XLA's sort (50,000 permutations of 9: 25.8 -> 1.5 ms; of 32:
    29 -> 2 ms). Beyond that the (n, n) comparisons leave the cache (36 genes:
    43 ms against the sort's 34) and the sort is used."""
    n = words.shape[-1]
    if n > RANK_MAX_N:
        return jnp.argsort(words, axis=-1, stable=True).astype(jnp.int32)
    i = jnp.arange(n, dtype=jnp.int32)
    wi, wj = words[..., :, None], words[..., None, :]
    before = (wj < wi) | ((wj == wi) & (i[None, :] < i[:, None]))
    rank = jnp.sum(before, axis=-1, dtype=jnp.int32)  # where each gene goes
    return jnp.sum(jnp.where(rank[..., :, None] == i, i[:, None], 0), axis=-2, dtype=jnp.int32)


def cut_draw(key: Array, n: int) -> tuple[Array, Array]:
    """Cut points ``(lo, hi)``, uniform over ``0 <= lo < hi <= n`` (``n >= 1``).

    Two distinct points of ``0..n`` are drawn and sorted; every unordered pair
    is equally likely, so every segment ``[lo, hi)`` is too.
    """
    r = uniform_int(key, (2,), jnp.array([0, 1], jnp.int32), n + 1)
    i, j = r[0], (r[0] + r[1]) % (n + 1)
    return jnp.minimum(i, j), jnp.maximum(i, j)


def _segment(n: int, lo: Array, hi: Array) -> Array:
    pos = jnp.arange(n, dtype=jnp.int32)
    return (pos >= lo) & (pos < hi)


# --- Cycle crossover ---------------------------------------------------------

def cx_draw(key: Array, n: int) -> Array:
    """The cycle start: a position uniform in ``0..n-1``."""
    return uniform_int(key, (), 0, n)


def cx_apply(a: Array, b: Array, start: Array) -> tuple[Array, Array]:
    """Cycle crossover (Oliver et al.) of the one cycle through ``start``.

    The position map ``i -> position in a of b[i]`` splits the positions into
    cycles. ``c1`` takes the cycle containing position ``start`` from ``a`` and
    every other position from ``b``; ``c2`` is the mirror (the cycle from ``b``,
    the rest from ``a``). Every child position therefore holds the value of one
    parent at that position, and ``c1[start] == a[start]``.
    """
    n = a.shape[-1]
    step = _take(_inverse(a), b)  # next position along the cycle
    pos = jnp.arange(n, dtype=jnp.int32)
    # Walk the cycle from start: n - 1 scalar look-ups (a cycle has at most n
    # positions). Pointer jumping over whole vectors (2 log2 n vector look-ups)
    # measured twice as slow at n = 9, and does n times more work at any n.
    if n > ONEHOT_MAX_N:
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

    hit = _chain(n - 1, walk, (pos == start, start))[0]
    return jnp.where(hit, a, b), jnp.where(hit, b, a)


def cx(key: Array, a: Array, b: Array) -> tuple[Array, Array]:
    """Cycle crossover with a random cycle start (see :func:`cx_apply`)."""
    return cx_apply(a, b, cx_draw(key, a.shape[-1]))


# --- Partially mapped crossover ------------------------------------------------

def pmx_draw(key: Array, n: int) -> tuple[Array, Array]:
    """PMX segment ``[lo, hi)``, uniform over ``0 <= lo < hi <= n``."""
    return cut_draw(key, n)


def _pmx_child(a: Array, b: Array, seg: Array) -> Array:
    """Child with ``a``'s segment, the rest from ``b`` through the PMX mapping."""
    n = a.shape[-1]
    # m[v]: for v in a's segment at position p, b[p]; otherwise v itself.
    # A value of b outside the segment that a's segment already holds is
    # replaced by following m until it leaves a's segment (at most n steps).
    m = _take(jnp.where(seg, b, a), _inverse(a))
    m = _chain(_rounds(n), lambda _, m: _take(m, m), m)
    return jnp.where(seg, a, _take(m, b))


def pmx_apply(a: Array, b: Array, lo: Array, hi: Array) -> tuple[Array, Array]:
    """Partially mapped crossover (Eiben & Smith) with segment ``[lo, hi)``.

    ``c1`` copies ``a[lo:hi]``; each other position takes ``b``'s value, and a
    value of ``b`` that the copied segment already holds is mapped through the
    segment's value pairs ``a[p] -> b[p]`` until it is free (the textbook
    placement of ``b``'s segment values, written position by position).
    ``c2`` is the mirror.
    """
    seg = _segment(a.shape[-1], lo, hi)
    return _pmx_child(a, b, seg), _pmx_child(b, a, seg)


def pmx(key: Array, a: Array, b: Array) -> tuple[Array, Array]:
    """PMX with a random segment (see :func:`pmx_apply`)."""
    return pmx_apply(a, b, *pmx_draw(key, a.shape[-1]))


# --- Order crossover -----------------------------------------------------------

def ox1_draw(key: Array, n: int) -> tuple[Array, Array]:
    """OX1 segment ``[lo, hi)``, uniform over ``0 <= lo < hi <= n``."""
    return cut_draw(key, n)


def _ox1_child(a: Array, b: Array, lo: Array, hi: Array) -> Array:
    n = a.shape[-1]
    seg = _segment(n, lo, hi)
    # b read from position hi on, wrapping; keep the values a's segment lacks.
    b_rot = jnp.roll(b, -hi)
    taken = _take(_take(seg, _inverse(a)), b_rot)
    rank = jnp.cumsum(~taken, dtype=jnp.int32) - 1
    # The kept value of rank r goes to free position (hi + r) mod n.
    filled = _place(b_rot, jnp.where(taken, n, (hi + rank) % n))
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


# --- Mutations -----------------------------------------------------------------

def inversion_draw(key: Array, n: int) -> tuple[Array, Array]:
    """Inversion segment ``[lo, hi)``, uniform over ``0 <= lo < hi <= n``."""
    return cut_draw(key, n)


def inversion_apply(p: Array, lo: Array, hi: Array) -> Array:
    """``p`` with ``p[lo:hi]`` reversed."""
    n = p.shape[-1]
    # reversed(p)[k + n - lo - hi] == p[lo + hi - 1 - k]: a flip and a roll.
    mirrored = jnp.roll(jnp.flip(p, -1), lo + hi - n)
    return jnp.where(_segment(n, lo, hi), mirrored, p)


def inversion(key: Array, p: Array) -> Array:
    """Inversion mutation: reverse a random segment (see :func:`cut_draw`)."""
    return inversion_apply(p, *inversion_draw(key, p.shape[-1]))


def exchange_draw(key: Array, n: int) -> tuple[Array, Array]:
    """Two positions ``(i, j)``, distinct when ``n >= 2``, uniform over such pairs."""
    if n < 2:
        zero = jnp.zeros((), jnp.int32)
        return zero, zero
    r = uniform_int(key, (2,), jnp.array([0, 1], jnp.int32), n)
    return r[0], (r[0] + r[1]) % n


def exchange_apply(p: Array, i: Array, j: Array) -> Array:
    """``p`` with the values at positions ``i`` and ``j`` swapped."""
    pos = jnp.arange(p.shape[-1], dtype=jnp.int32)
    pi, pj = jnp.sum(jnp.where(pos == i, p, 0)), jnp.sum(jnp.where(pos == j, p, 0))
    return jnp.where(pos == i, pj, jnp.where(pos == j, pi, p)).astype(p.dtype)


def exchange(key: Array, p: Array) -> Array:
    """Reciprocal exchange mutation: swap two random positions."""
    return exchange_apply(p, *exchange_draw(key, p.shape[-1]))


CROSSOVERS: dict[str, Crossover] = {"cx": cx, "pmx": pmx, "ox1": ox1}
MUTATIONS: dict[str, Mutation] = {"inversion": inversion, "exchange": exchange}


def register_crossover(name: str, fn: Crossover) -> None:
    """``registry.register("perm_crossover", name, fn)`` (kept for older code)."""
    from .registry import register

    register("perm_crossover", name, fn)


def register_mutation(name: str, fn: Mutation) -> None:
    """``registry.register("perm_mutation", name, fn)`` (kept for older code)."""
    from .registry import register

    register("perm_mutation", name, fn)
