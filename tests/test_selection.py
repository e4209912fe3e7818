"""Tests of the parent selections."""
from __future__ import annotations

import functools

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hga_jax.search import selection as sel

# The built-in selections in the (key, fitness, count, size) form.
SELECTIONS = {"roulette": sel.roulette, "tournament": sel.tournament}
FIT = jnp.array([1.0, 2.0, 3.0, 4.0, 10.0], jnp.float32)


@functools.lru_cache(maxsize=None)
def _selected(name: str, count: int, size: int, seed: int = 0, fit=tuple(FIT.tolist())):
    f = jax.jit(SELECTIONS[name], static_argnums=(2, 3))
    return np.asarray(f(jax.random.key(seed), jnp.asarray(fit, jnp.float32), count, size))


@pytest.mark.parametrize("name", sorted(SELECTIONS))
def test_shape_dtype_range(name):
    idx = _selected(name, 7, 3)
    assert idx.shape == (7,) and idx.dtype == np.int32
    assert ((idx >= 0) & (idx < len(FIT))).all()


def test_roulette_frequencies_match_fitness():
    count = 200_000
    freq = np.bincount(_selected("roulette", count, 2), minlength=5) / count
    # Standard error sqrt(p (1 - p) / count) < 0.0012; allow ~8 of them.
    np.testing.assert_allclose(freq, np.asarray(FIT) / float(FIT.sum()), atol=0.01)


def test_roulette_ignores_size_and_skips_tiny_fitness():
    assert (_selected("roulette", 500, 2) == _selected("roulette", 500, 7)).all()
    idx = _selected("roulette", 20_000, 2, fit=(1e-9, 1.0, 1e-9, 1.0))
    assert set(np.unique(idx).tolist()) == {1, 3}


def test_tournament_with_huge_size_returns_the_argmax():
    # Entrants are drawn with replacement, so even size = P may miss the best
    # ((1 - 1/P)**P ~ 1/e); with size = 40 P a miss has probability ~e**-40.
    idx = _selected("tournament", 1_000, 200)
    assert (idx == int(jnp.argmax(FIT))).all()


def test_tournament_with_size_p_mostly_returns_the_argmax():
    idx = _selected("tournament", 20_000, 5)
    p_best = 1 - (4 / 5) ** 5  # the best is among the 5 entrants
    assert abs((idx == 4).mean() - p_best) < 0.015


def test_tournament_ties_go_to_the_lower_index():
    idx = _selected("tournament", 1_000, 100, fit=(1.0, 5.0, 3.0, 5.0, 2.0))
    assert (idx == 1).all()
    idx = _selected("tournament", 1_000, 100, fit=(2.0,) * 6)
    assert (idx == 0).all()


def test_tournament_rank_distribution():
    # Fitness order = index order; the winner is the largest of `size` uniform
    # draws from 0..P-1, so P(winner <= i) = ((i + 1) / P) ** size.
    P, size, count = 5, 3, 100_000
    idx = _selected("tournament", count, size, fit=tuple(float(i) for i in range(1, P + 1)))
    cdf = np.cumsum(np.bincount(idx, minlength=P)) / count
    np.testing.assert_allclose(cdf, (np.arange(1, P + 1) / P) ** size, atol=0.01)


def test_tournament_size_one_is_uniform():
    freq = np.bincount(_selected("tournament", 50_000, 1), minlength=5) / 50_000
    np.testing.assert_allclose(freq, 0.2, atol=0.01)


@pytest.mark.parametrize("name", sorted(SELECTIONS))
def test_jit_vmap_over_runs_equals_run_by_run(name):
    runs, P, count, size = 4, 6, 9, 3
    keys = jax.random.split(jax.random.key(1), runs)
    fit = jax.random.uniform(jax.random.key(2), (runs, P), minval=0.1, maxval=2.0)
    op = functools.partial(SELECTIONS[name], count=count, size=size)
    batched = np.asarray(jax.jit(jax.vmap(op))(keys, fit))
    assert batched.shape == (runs, count)
    single = jax.jit(op)
    for r in range(runs):
        np.testing.assert_array_equal(batched[r], single(keys[r], fit[r]))


@pytest.mark.parametrize("size", [1, 2, 3, 8, 9])
def test_tournament_from_words_keeps_the_fittest_entrant_lowest_index_first(size):
    # Fitness with many ties; the reference is the rule itself, in numpy.
    from hga_jax.search.permutation import int_from_words
    from hga_jax.search.selection import tournament_from_words

    rng = np.random.default_rng(size)
    fit = rng.integers(1, 4, 12).astype(np.float32)
    words = rng.integers(0, 2**32, (500, size), dtype=np.uint64).astype(np.uint32)
    got = np.asarray(tournament_from_words(jnp.asarray(words), jnp.asarray(fit)))
    entrants = np.asarray(int_from_words(jnp.asarray(words), 0, 12))
    f = fit[entrants]
    want = np.where(f == f.max(axis=1, keepdims=True), entrants, 12).min(axis=1)
    np.testing.assert_array_equal(got, want)
