"""The random stream of the GA: JAX's threefry2x32 stream, computed faster on the CPU.

Every random number of a run comes from JAX's default generator, threefry2x32
(Salmon et al., "Parallel random numbers: as easy as 1, 2, 3", SC 2011), in its
original (not "partitionable") layout; that stream is part of what a seed means
(:mod:`hga_jax.search.ga`). JAX's CPU lowering of the threefry hash runs its 20 rounds
as a rolled loop, which costs about 5 ns per 32-bit number; the GA draws about
1,500 numbers per run and generation, more than its fitness costs. This module
registers the same generator as a PRNG implementation of its own
(``define_prng_impl``, through :mod:`hga_jax.jax_compat`) whose hash is written out round by
round in ``jax.numpy``: XLA fuses it into the code around it at about 1.4 ns per
number. Keys, splits, ``fold_in`` and bits are bit for bit JAX's threefry ones
(tested against ``jax.random`` for many keys and shapes), so results do not
change; only the key type differs (:func:`key`, :func:`from_threefry`).

Pure functions of uint32 arrays; jit/vmap-able.
"""
from __future__ import annotations

import math

import jax
import jax.numpy as jnp
import numpy as np
from hga_jax.jax_compat import define_prng_impl

_PARITY = np.uint32(0x1BD11BDA)  # threefry's key-schedule constant
_ROTATIONS = ((13, 15, 26, 6), (17, 29, 16, 24))


def threefry2x32(k1, k2, x1, x2):
    """The threefry2x32 hash (20 rounds) of counter words ``x1, x2`` under key ``k1, k2``."""
    ks = (k1, k2, k1 ^ k2 ^ _PARITY)
    x1, x2 = x1 + ks[0], x2 + ks[1]
    for i in range(5):
        for r in _ROTATIONS[i % 2]:
            x1 = x1 + x2
            x2 = ((x2 << np.uint32(r)) | (x2 >> np.uint32(32 - r))) ^ x1
        x1 = x1 + ks[(i + 1) % 3]
        x2 = x2 + ks[(i + 2) % 3] + np.uint32(i + 1)
    return x1, x2


def _hash(key, count):
    """Threefry of a flat uint32 ``count`` of even size in JAX's original layout: the
    first and the second half are the two counter words."""
    half = count.shape[0] // 2
    y1, y2 = threefry2x32(key[0], key[1], count[:half], count[half:])
    return jnp.concatenate([y1, y2])


def _hash_iota(key, size: int):
    """:func:`_hash` of the counters ``0 .. size - 1``; an odd count is padded with a 0
    (JAX's layout). The counter words are made from an iota rather than by padding
    and splitting an array: under ``vmap`` that padding cost XLA five times the hash."""
    return words_of_keys(key[0], key[1], size)


def words_of_keys(k1, k2, size: int):
    """``jax.random.bits(key, (size,), uint32)`` of many keys at once, laid out words first:
    (size, ...) for the keys whose data words are ``k1`` and ``k2`` (each (...)). The same
    numbers as ``vmap`` over the keys (:func:`_hash_iota` per key), hashed across the keys:
    vmapped, XLA made each key's words one by one (27 words per key at 9 obstacles: 4 ns
    a word against about 1 ns across the keys). One key (scalar words): :func:`_hash_iota`."""
    half = (size + 1) // 2
    i = jnp.arange(half, dtype=jnp.uint32).reshape((half,) + (1,) * jnp.ndim(k1))
    y1, y2 = threefry2x32(k1[None], k2[None], i, jnp.where(i + half < size, i + half,
                                                             np.uint32(0)))
    return jnp.concatenate([y1, y2[:size - half]])


def _seed(seed):
    return jax.random.key_data(jax.random.key(seed, impl="threefry2x32"))


def _split(key, shape):
    return _hash_iota(key, 2 * math.prod(shape)).reshape(*shape, 2)


def _fold_in(key, data):
    word = jnp.asarray(data).astype(jnp.uint32)
    return _hash(key, jnp.stack([jnp.zeros_like(word), word]))


def _random_bits(key, bit_width, shape):
    size = math.prod(shape)
    words = -(-bit_width * size // 32)
    if words >= 2**32 - 1:
        raise NotImplementedError("more than 2**32 - 2 random words from one key")
    bits = _hash_iota(key, words)
    if bit_width == 64:
        hi, lo = (b.astype(jnp.uint64) for b in jnp.split(bits, 2))
        return ((hi << np.uint64(32)) | lo).reshape(shape)
    if bit_width in (8, 16):
        per = 32 // bit_width
        shifts = jnp.arange(per, dtype=jnp.uint32) * np.uint32(bit_width)
        parts = (bits[:, None] >> shifts[None, :]) & np.uint32((1 << bit_width) - 1)
        dtype = jnp.uint8 if bit_width == 8 else jnp.uint16
        return parts.reshape(-1)[:size].astype(dtype).reshape(shape)
    return bits.reshape(shape)


IMPL = define_prng_impl(key_shape=(2,), seed=_seed, split=_split, random_bits=_random_bits,
                        fold_in=_fold_in, name="hga_jax_threefry2x32", tag="hft")
"""The PRNG implementation: threefry2x32 with the hash unrolled."""


def unit(words, dtype=jnp.float32):
    """Floats uniform on the grid ``k / 2**24`` in [0, 1) from uint32 ``words`` (their top
    24 bits), as ``dtype`` (float32 or float64). The one rule for uniform floats from
    words: exact in either dtype, so ``unit(w) < p`` is never true for p = 0 and always
    for p = 1, and the same word gives the same number in both."""
    return (words >> np.uint32(8)).astype(dtype) * jnp.asarray(2.0**-24, dtype)


def wrap(data):
    """Key data (uint32, a last axis of 2; numpy or traced) as keys of this implementation."""
    return jax.random.wrap_key_data(data, impl=IMPL)


def key(seed):
    """A key of this implementation for integer ``seed`` (same stream as ``jax.random.key``)."""
    return wrap(_seed(seed))


def from_threefry(k):
    """The same key (a typed threefry2x32 key) as a key of this implementation."""
    return wrap(jax.random.key_data(k))


# --- The same keys on the host (numpy), for programs that take their keys as input ---

def host_key(seed: int) -> np.ndarray:
    """``key_data(key(seed))`` for ``0 <= seed < 2**32``: ``(2,)`` uint32 ``[0, seed]``."""
    return np.array([0, seed], np.uint32)


def _host_hash(kd: np.ndarray, x1: np.ndarray, x2: np.ndarray):
    with np.errstate(over="ignore"):  # uint32 arithmetic wraps, as intended
        return threefry2x32(kd[..., 0:1], kd[..., 1:2], x1, x2)


def host_fold_in(kd: np.ndarray, data: np.ndarray) -> np.ndarray:
    """``key_data(fold_in(k, d))`` for key data ``kd`` (..., 2) and uint32 ``data`` (...)."""
    d = np.asarray(data, np.uint32)[..., None]
    y1, y2 = _host_hash(np.asarray(kd, np.uint32), np.zeros_like(d), d)
    return np.concatenate([y1, y2], axis=-1)


def host_split(kd: np.ndarray, num: int) -> np.ndarray:
    """``key_data(split(k, num))`` for key data ``kd`` (..., 2): (..., num, 2)."""
    i = np.arange(num, dtype=np.uint32)
    y1, y2 = _host_hash(np.asarray(kd, np.uint32), i, i + np.uint32(num))
    flat = np.concatenate([y1, y2], axis=-1)  # the 2 * num words in JAX's order
    return flat.reshape(flat.shape[:-1] + (num, 2))
