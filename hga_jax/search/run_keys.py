"""The keys of a run and of its generations: what a seed means.

Run ``k`` of seed ``s`` has the key ``fold_in(key(s), k)`` of JAX's threefry2x32
stream (as a key of :mod:`hga_jax.search.rng`); generation 0 uses the first half
of ``split(run key)``, generations 1..G the keys split from the second half.
The host makes the same keys with numpy (:func:`host_generation_keys`), so a
compiled block of generations takes them as input.
"""
from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from . import rng
from hga_jax.jax_compat import fixed_stream
from .settings import GASettings


@fixed_stream
def run_key(seed: int, k):
    """The PRNG key of run ``k`` of ``seed``: ``fold_in(key(seed), k)`` of JAX's default
    threefry2x32 stream, as a key of :mod:`hga_jax.search.rng` (the same numbers, faster)."""
    return jax.random.fold_in(rng.key(seed), k)


@fixed_stream
def generation_keys(key, settings: GASettings):
    """The keys of generations 0..G of the run with key ``key``: ``(G + 1,)``.

    ``k0, kg = split(key)``; generation 0 uses ``k0``, generation g >= 1 uses
    ``split(kg, G)[g - 1]`` (:func:`host_generation_keys` makes the same on the host).
    """
    k0, kg = jax.random.split(key)
    later = jax.random.split(kg, settings.generations)
    return jnp.concatenate([k0[None], later])


def host_generation_keys(seed: int, ks, settings: GASettings):
    """:func:`generation_keys` of runs ``ks`` of ``seed``, made on the host (numpy):
    keys of :mod:`hga_jax.search.rng`, shaped ``(len(ks), G + 1)``."""
    return rng.wrap(host_generation_key_data(seed, ks, settings))


def host_generation_key_data(seed: int, ks, settings: GASettings) -> np.ndarray:
    """The data of :func:`host_generation_keys`: uint32, ``(len(ks), G + 1, 2)``. A compiled
    block of generations takes its columns as input (as keys: :func:`hga_jax.search.rng.wrap`)
    instead of hashing them out itself."""
    ks = np.asarray(ks, np.int64)
    run = rng.host_fold_in(np.broadcast_to(rng.host_key(seed), ks.shape + (2,)), ks)
    k0kg = rng.host_split(run, 2)
    later = rng.host_split(k0kg[..., 1, :], settings.generations)
    return np.concatenate([k0kg[..., :1, :], later], axis=-2)


def run_indices(ks):
    """``ks`` (a sequence or array of run indices) as a 1-D int32 array, checked."""
    ks = jnp.asarray(ks)
    if ks.ndim != 1 or not jnp.issubdtype(ks.dtype, jnp.integer):
        raise TypeError(f"ks: expected a 1-D sequence of integer run indices, got shape "
                        f"{tuple(ks.shape)} of {ks.dtype}")
    return ks.astype(jnp.int32)
