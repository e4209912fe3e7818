"""Float sums whose rounding does not depend on the batch shape.

XLA may sum or scan an axis in a different order when the same computation is
vmapped over 1 or 1000 runs, which changes the last bit of a total and, through
roulette selection, a whole run. These sums are fixed trees of elementwise
additions over the last axis, so run ``k`` is bit-identical alone or in a batch.
"""
from __future__ import annotations

import jax.numpy as jnp


def tree_sum(x):
    """Sum over the last axis by pairwise halving (zero-padded to a power of two)."""
    n = x.shape[-1]
    width = 1 << max(n - 1, 0).bit_length()
    if width != n:
        pad = jnp.zeros(x.shape[:-1] + (width - n,), x.dtype)
        x = jnp.concatenate([x, pad], axis=-1)
    while x.shape[-1] > 1:
        half = x.shape[-1] // 2
        x = x[..., :half] + x[..., half:]
    return x[..., 0]


def prefix_sum(x):
    """Inclusive prefix sum over the last axis (Hillis-Steele: log2(n) shifted adds)."""
    n = x.shape[-1]
    shift = 1
    while shift < n:
        pad = jnp.zeros(x.shape[:-1] + (shift,), x.dtype)
        x = x + jnp.concatenate([pad, x[..., :-shift]], axis=-1)
        shift *= 2
    return x
