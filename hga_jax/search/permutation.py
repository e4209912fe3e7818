"""Permutation helpers of the upper module: random permutations and integers from
words, cut draws, and the look-ups the operators are made of.

Conventions:

- A permutation is a 1-D ``int32`` array holding each of ``0..n-1`` once
  (``n >= 1``; the fixed start and goal genes are not part of it).
- Random integers come from :func:`uniform_int` / :func:`int_from_words`: one
  32-bit word each, its top 24 bits scaled to the range (:func:`hga_jax.search.rng.unit`).
- Cut points: ``0 <= lo < hi <= n``, drawn uniformly over all such pairs; the
  segment is the half-open position range ``[lo, hi)`` (:func:`segment`).
- Gathers and scatters run element by element on the XLA CPU backend, so for
  small ``n`` (up to :data:`ONEHOT_MAX_N`) look-ups are one-hot comparisons
  (``O(n^2)`` vector work, :func:`take`, :func:`place`); for larger ``n`` they
  are gathers and scatters. Chains of look-ups use pointer jumping
  (:func:`chain`, ``ceil(log2 n)`` rounds).

Pure functions; shapes depend on ``n`` only, so everything jits and vmaps.
"""
from __future__ import annotations

from typing import Callable

import jax
import jax.numpy as jnp
from jax import Array

from .rng import unit


# Up to this n, look-ups are one-hot selects; above it, gathers and scatters.
# Read at trace time. Measured on the XLA CPU backend (batches of 5,000 pairs):
# one-hot was up to 2x faster for n <= 20 and about even at n = 25; at n = 50
# it was 7-12x slower, its (n, n) intermediates no longer fitting the cache.
ONEHOT_MAX_N = 20


def rounds(n: int) -> int:
    """Pointer-jumping rounds so that ``2**rounds >= n``."""
    return max(0, (n - 1).bit_length())


def take(x: Array, idx: Array) -> Array:
    """``x[idx]`` for 1-D ``x`` and in-range ``idx``; for ``x`` (m, ...) with a batch
    after its first axis, ``x[idx[k, ...], ...]`` along that axis (``idx`` (k, ...)).

    1-D, small ``n``: a one-hot select (vector work only); larger ``n`` and batches
    laid out after the positions (one look-up per chromosome, across the batch): a
    gather. The gather clamps (``mode="clip"``) rather than fill: for in-range indices
    the two agree bit for bit, and the fill's range test and select on every look-up
    cost a tenth of the recommended preset's search at 28 obstacles (3.69-3.78 against
    4.19-4.20 s for 200 runs; no index out of range over runs of every car model,
    docs/performance.md).
    """
    if x.ndim > 1:
        m = x.shape[0]
        if m > ONEHOT_MAX_N + 2:
            return jnp.take_along_axis(x, idx, axis=0, mode="clip")
        rows = jnp.arange(m, dtype=idx.dtype).reshape((m,) + (1,) * (x.ndim - 1))
        hit = idx[:, None] == rows  # (k, m, ...)
        if x.dtype == jnp.bool_:
            return jnp.any(hit & x, axis=1)
        return jnp.sum(jnp.where(hit, x, 0), axis=1, dtype=x.dtype)
    n = x.shape[-1]
    if n > ONEHOT_MAX_N:
        return x[idx]
    hit = idx[:, None] == jnp.arange(n, dtype=idx.dtype)
    if x.dtype == jnp.bool_:
        return jnp.any(hit & x, axis=-1)
    return jnp.sum(jnp.where(hit, x, 0), axis=-1, dtype=x.dtype)


def lift(x: Array, like: Array) -> Array:
    """``x`` (m, ...) with axes of length 1 put after its first, so that its positions
    broadcast against ``like``'s leading axes of candidates (several moves drawn for each
    chromosome side by side: ``like`` has more axes than ``x`` after the positions)."""
    extra = jnp.ndim(like) - (x.ndim - 1)
    return x.reshape((x.shape[0],) + (1,) * extra + x.shape[1:]) if extra > 0 else x


def pick(x: Array, k: Array) -> Array:
    """``x[k]`` along the first axis: one entry per chromosome (``x`` (m, ...), ``k`` (...),
    which may add leading axes of its own: several look-ups per chromosome)."""
    x = lift(x, k)
    shape = jnp.broadcast_shapes(x.shape[1:], jnp.shape(k))
    x = jnp.broadcast_to(x, x.shape[:1] + shape)
    return take(x, jnp.broadcast_to(k, shape)[None])[0]


def place(values: Array, targets: Array) -> Array:
    """``out[targets[k]] = values[k]``; targets outside ``0..n-1`` are dropped,
    positions no target names hold 0. Targets must not repeat."""
    n = values.shape[-1]
    if n > ONEHOT_MAX_N:
        return jnp.zeros_like(values).at[targets].set(values, mode="drop")
    hit = targets[None, :] == jnp.arange(n, dtype=targets.dtype)[:, None]
    return jnp.sum(jnp.where(hit, values, 0), axis=-1, dtype=values.dtype)


def chain(steps: int, body: Callable, init):
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


def inverse(p: Array) -> Array:
    """The inverse permutation: ``inverse(p)[p[i]] == i``."""
    return place(jnp.arange(p.shape[-1], dtype=p.dtype), p)


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


SCAN_MAX_N = 256  # up to here larger permutations are ranked in passes over the genes


def _ranked_by_scan(w: Array) -> Array:
    """The stable argsort of each column of ``w`` (n, B): the rule of
    :func:`permutation_from_words`, with the genes first and the batch after them. One
    pass per gene counts, for every word, whether that gene's word comes before it; one
    pass per gene then puts each gene at its rank: vector work across the batch, and
    on the CPU 3-7x faster than XLA's sort (10,000 permutations of 40: 25 -> 3.6 ms; of
    100: 73 -> 17 ms; of 200: 158 -> 60 ms)."""
    n = w.shape[0]
    pos = jnp.arange(n, dtype=jnp.int32)[:, None]

    def count(rank, j):
        wj = w[j][None, :]
        return rank + ((wj < w) | ((wj == w) & (j < pos))).astype(jnp.int32), None

    genes = jnp.arange(n, dtype=jnp.int32)
    rank, _ = jax.lax.scan(count, jnp.zeros(w.shape, jnp.int32), genes)

    def place(perm, i):
        return jnp.where(rank[i][None, :] == pos, i, perm), None

    return jax.lax.scan(place, jnp.zeros(w.shape, jnp.int32), genes)[0]


def permutation_from_words(words: Array) -> Array:
    """:func:`random_permutation` from given uint32 words (``n`` per permutation, last axis).

    Up to ``RANK_MAX_N`` genes the stable argsort is computed by counting, for
    each word, the words that come before it (smaller, or equal at a lower index)
    and inverting those ranks by comparison: the same permutation, and on the CPU
    8-18x faster than XLA's sort (50,000 permutations of 9: 25.8 -> 1.5 ms; of 32:
    29 -> 2 ms). Beyond that the (n, n) comparisons leave the cache (36 genes:
    43 ms against the sort's 34), and up to ``SCAN_MAX_N`` genes the ranks are counted
    in passes over the genes (:func:`_ranked_by_scan`); beyond, the sort is used."""
    n = words.shape[-1]
    if n > SCAN_MAX_N:
        return jnp.argsort(words, axis=-1, stable=True).astype(jnp.int32)
    if n > RANK_MAX_N:
        flat = words.reshape(-1, n)
        return _ranked_by_scan(flat.T).T.reshape(words.shape)
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


def segment(n: int, lo: Array, hi: Array) -> Array:
    pos = jnp.arange(n, dtype=jnp.int32)
    return (pos >= lo) & (pos < hi)
