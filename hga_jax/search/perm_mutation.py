"""Mutations of the upper module: inversion and reciprocal exchange.

Conventions as :mod:`hga_jax.search.perm_crossover`: ONE permutation (n,) in, one
out; a random ``*_draw`` and a deterministic ``*_apply`` step,
``op(key, p) == op_apply(p, *op_draw(key, n))``; jit- and vmap-able.

The settings' names are those of :mod:`hga_jax.search.registry` (``perm_mutation``).
"""
from __future__ import annotations

import jax.numpy as jnp
from jax import Array

from . import permutation as pm

def inversion_draw(key: Array, n: int) -> tuple[Array, Array]:
    """Inversion segment ``[lo, hi)``, uniform over ``0 <= lo < hi <= n``."""
    return pm.cut_draw(key, n)


def inversion_apply(p: Array, lo: Array, hi: Array) -> Array:
    """``p`` with ``p[lo:hi]`` reversed."""
    n = p.shape[-1]
    # reversed(p)[k + n - lo - hi] == p[lo + hi - 1 - k]: a flip and a roll.
    mirrored = jnp.roll(jnp.flip(p, -1), lo + hi - n)
    return jnp.where(pm.segment(n, lo, hi), mirrored, p)


def inversion(key: Array, p: Array) -> Array:
    """Inversion mutation: reverse a random segment (see :func:`hga_jax.search.permutation.cut_draw`)."""
    return inversion_apply(p, *inversion_draw(key, p.shape[-1]))


def exchange_draw(key: Array, n: int) -> tuple[Array, Array]:
    """Two positions ``(i, j)``, distinct when ``n >= 2``, uniform over such pairs."""
    if n < 2:
        zero = jnp.zeros((), jnp.int32)
        return zero, zero
    r = pm.uniform_int(key, (2,), jnp.array([0, 1], jnp.int32), n)
    return r[0], (r[0] + r[1]) % n


def exchange_apply(p: Array, i: Array, j: Array) -> Array:
    """``p`` with the values at positions ``i`` and ``j`` swapped."""
    pos = jnp.arange(p.shape[-1], dtype=jnp.int32)
    pi, pj = jnp.sum(jnp.where(pos == i, p, 0)), jnp.sum(jnp.where(pos == j, p, 0))
    return jnp.where(pos == i, pj, jnp.where(pos == j, pi, p)).astype(p.dtype)


def exchange(key: Array, p: Array) -> Array:
    """Reciprocal exchange mutation: swap two random positions."""
    return exchange_apply(p, *exchange_draw(key, p.shape[-1]))

