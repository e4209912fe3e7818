"""hga_jax.search.rng: the same numbers as JAX's threefry2x32, key by key and draw by draw."""
from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hga_jax.search import ga, rng

DRAWS = {
    "bits32": lambda k, s: jax.random.bits(k, s),
    "bits16": lambda k, s: jax.random.bits(k, s, jnp.uint16),
    "bits8": lambda k, s: jax.random.bits(k, s, jnp.uint8),
    "uniform": lambda k, s: jax.random.uniform(k, s),
    "randint": lambda k, s: jax.random.randint(k, s, 0, 11),
    "bernoulli": lambda k, s: jax.random.bernoulli(k, 0.3, s),
}


def _data(k):
    return np.asarray(jax.random.key_data(k))


# Compiled (one program per shape, not one per primitive as op by op): the same numbers.
_SPLIT = jax.jit(jax.random.split, static_argnums=1)
_FOLD_IN = jax.jit(jax.random.fold_in)


@pytest.mark.parametrize("seed", [0, 1, 12345, 2**31 - 1])
def test_keys_splits_and_fold_ins_are_threefrys(seed):
    with jax.threefry_partitionable(False):
        a, b = jax.random.key(seed), rng.key(seed)
        assert np.array_equal(_data(a), _data(b))
        for num in (1, 2, 3, 50):
            assert np.array_equal(_data(_SPLIT(a, num)), _data(_SPLIT(b, num)))
        for d in (0, 5, 99_999, 2**31 - 1):
            assert np.array_equal(_data(_FOLD_IN(a, d)), _data(_FOLD_IN(b, d)))


@pytest.mark.parametrize("name", sorted(DRAWS))
@pytest.mark.parametrize("shape", [(3,), (7, 2), (11, 50)])
def test_draws_are_threefrys_alone_jitted_and_vmapped(name, shape):
    draw = DRAWS[name]
    with jax.threefry_partitionable(False):
        a, b = _SPLIT(jax.random.key(7), 5), _SPLIT(rng.key(7), 5)
        alone = jax.jit(lambda k: draw(k, shape))
        assert np.array_equal(np.asarray(alone(a[0])), np.asarray(alone(b[0])))
        batched = jax.jit(jax.vmap(lambda k: draw(k, shape)))
        assert np.array_equal(np.asarray(batched(a)), np.asarray(batched(b)))


def test_run_key_is_the_threefry_run_key():
    with jax.threefry_partitionable(False):
        want = jax.random.fold_in(jax.random.key(3), 17)
    assert np.array_equal(_data(ga.run_key(3, 17)), _data(want))
    assert jax.random.key_impl(ga.run_key(3, 17)) == jax.random.key_impl(rng.key(0))


def test_the_hash_matches_the_published_test_vector():
    """Threefry-2x32 with 20 rounds, key (0x13198a2e, 0x03707344), counter
    (0x243f6a88, 0x85a308d3) gives (0xc4923a9c, 0x483df7a0) (Random123's known-answer
    test, also used by JAX's own tests)."""
    u = np.uint32
    with np.errstate(over="ignore"):  # uint32 arithmetic wraps, as intended
        y = rng.threefry2x32(u(0x13198A2E), u(0x03707344), u(0x243F6A88), u(0x85A308D3))
    assert (int(y[0]), int(y[1])) == (0xC4923A9C, 0x483DF7A0)


@pytest.mark.parametrize("seed", [0, 9, 2**32 - 1])
def test_host_keys_are_the_device_keys(seed):
    """The runner makes each run's generation keys on the host (numpy); they must be
    the keys ga.run derives on the device from the run's key."""
    from hga_jax.search.settings import GASettings

    s = GASettings(generations=7)
    ks = np.array([0, 1, 5, 2**31 - 1])
    host = ga.host_generation_keys(seed, ks, s)
    device = jax.vmap(lambda k: ga.generation_keys(ga.run_key(seed, k), s))(ks)
    assert host.shape == (4, 8)
    assert np.array_equal(_data(host), _data(device))
    with jax.threefry_partitionable(False):
        assert np.array_equal(rng.host_key(seed), _data(jax.random.key(seed)))


@pytest.mark.parametrize("size", [1, 2, 27, 28, 120])
def test_words_of_many_keys_are_each_keys_bits(size):
    data = np.asarray(jax.random.bits(jax.random.key(5), (2, 3, 4)))  # key words (3, 4)
    want = jax.jit(jax.vmap(jax.vmap(lambda d: jax.random.bits(rng.wrap(d), (size,)))))(
        np.stack([data[0], data[1]], axis=-1))  # (3, 4, size)
    got = jax.jit(rng.words_of_keys, static_argnums=2)(data[0], data[1], size)  # (size, 3, 4)
    assert got.shape == (size, 3, 4)
    assert np.array_equal(np.moveaxis(np.asarray(got), 0, -1), np.asarray(want))
