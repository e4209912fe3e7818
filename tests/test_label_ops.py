"""Tests of the label operators (lower module)."""
from __future__ import annotations

import functools
import itertools
from collections import Counter

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hga_jax.search import label_ops as lo_
from hga_jax.search import registry

LENGTHS = [3, 11, 27]  # L = n + 2 for n = 1, 9, 25
BATCH = 256


def _assert_allowed(labels) -> None:
    """Ends in {-1, +1}, the other positions in {-1, 0, +1}."""
    x = np.asarray(labels)
    assert x.dtype == np.int32
    assert np.isin(x, [-1, 0, 1]).all()
    assert (x[..., 0] != 0).all() and (x[..., -1] != 0).all()


def _all_ops(key, a, b):
    """Every label operator on one pair, with the draws it made from ``key``."""
    L = a.shape[-1]
    k1, k2 = jax.random.split(key)
    return {
        "random": lo_.random_labels(k1, L),
        "two_point": lo_.two_point(key, a, b),
        "cut": lo_.two_point_draw(key, L),
        "redraw_0": lo_.redraw(k2, a, 0.0),
        "redraw_half": lo_.redraw(k2, a, 0.5),
        "redraw_1": lo_.redraw(k2, a, 1.0),
        "draw_half": lo_.redraw_draw(k2, L, 0.5),
    }


@functools.lru_cache(maxsize=None)
def _results(L: int):
    rng = np.random.default_rng(L)
    a, b = rng.integers(-1, 2, (2, BATCH, L), dtype=np.int32)
    a[:, [0, -1]] = rng.choice([-1, 1], (BATCH, 2))
    b[:, [0, -1]] = rng.choice([-1, 1], (BATCH, 2))
    keys = jax.random.split(jax.random.key(L), BATCH)
    out = jax.jit(jax.vmap(_all_ops))(keys, a, b)
    return keys, np.asarray(a), np.asarray(b), jax.tree.map(np.asarray, out)


# --- worked examples -----------------------------------------------------------

def test_two_point_worked_example():
    a = jnp.array([1, 0, -1, 1, 0, -1], jnp.int32)
    b = jnp.array([-1, 1, 1, 0, -1, 1], jnp.int32)
    c1, c2 = lo_.two_point_apply(a, b, 1, 4)
    np.testing.assert_array_equal(c1, [1, 1, 1, 0, 0, -1])
    np.testing.assert_array_equal(c2, [-1, 0, -1, 1, -1, 1])
    c1, c2 = lo_.two_point_apply(a, b, 0, 6)  # whole chromosome: the parents swap
    np.testing.assert_array_equal(c1, b)
    np.testing.assert_array_equal(c2, a)


def test_redraw_worked_example():
    labels = jnp.array([1, -1, 0, 1, -1, 0, 1, -1], jnp.int32)
    mask = jnp.array([1, 1, 1, 1, 1, 1, 0, 1], bool)
    choice = jnp.array([0, 0, 0, 0, 1, 1, 1, 1], bool)
    # ends flip (1 -> -1, -1 -> 1); middle genes step 1 + choice along
    # -1 -> 0 -> +1 -> -1: -1+1 = 0, 0+1 = 1, 1+1 = -1, -1+2 = 1, 0+2 = -1;
    # position 6 is not masked and keeps its 1.
    np.testing.assert_array_equal(
        lo_.redraw_apply(labels, mask, choice), [-1, 0, 1, -1, 1, -1, 1, 1]
    )


# --- properties over random labels ----------------------------------------------

@pytest.mark.parametrize("L", LENGTHS)
def test_random_labels_allowed_and_uniform(L):
    _, a, _, out = _results(L)
    _assert_allowed(a)
    _assert_allowed(out["random"])
    r = out["random"]
    ends = np.concatenate([r[:, 0], r[:, -1]])
    assert abs((ends == 1).mean() - 0.5) < 0.08
    middle = r[:, 1:-1].ravel()
    for v in (-1, 0, 1):
        assert abs((middle == v).mean() - 1 / 3) < 0.08


@pytest.mark.parametrize("L", LENGTHS)
def test_two_point_swaps_the_segment(L):
    _, a, b, out = _results(L)
    c1, c2 = out["two_point"]
    lo, hi = out["cut"]
    assert ((lo >= 0) & (lo < hi) & (hi <= L)).all()
    seg = (np.arange(L) >= lo[:, None]) & (np.arange(L) < hi[:, None])
    np.testing.assert_array_equal(c1, np.where(seg, b, a))
    np.testing.assert_array_equal(c2, np.where(seg, a, b))
    _assert_allowed(c1)
    _assert_allowed(c2)


def test_two_point_draw_is_uniform():
    L, count = 4, 20_000
    lo, hi = jax.jit(jax.vmap(lo_.two_point_draw, (0, None)), static_argnums=1)(
        jax.random.split(jax.random.key(3), count), L
    )
    freq = Counter(zip(np.asarray(lo).tolist(), np.asarray(hi).tolist()))
    assert set(freq) == set(itertools.combinations(range(L + 1), 2))
    for c in freq.values():
        assert abs(c / count - 0.1) < 0.012


@pytest.mark.parametrize("L", LENGTHS)
def test_redraw_pm0_is_identity(L):
    _, a, _, out = _results(L)
    np.testing.assert_array_equal(out["redraw_0"], a)


@pytest.mark.parametrize("L", LENGTHS)
def test_redraw_pm1_changes_every_gene(L):
    _, a, _, out = _results(L)
    new = out["redraw_1"]
    assert (new != a).all()
    _assert_allowed(new)
    np.testing.assert_array_equal(new[:, [0, -1]], -a[:, [0, -1]])
    # A middle gene takes either other value, about half the time each.
    mid_a, mid_new = a[:, 1:-1], new[:, 1:-1]
    up = (mid_new - mid_a) % 3 == 1
    assert abs(up.mean() - 0.5) < 0.1


@pytest.mark.parametrize("L", LENGTHS)
def test_redraw_changes_exactly_the_masked_genes(L):
    _, a, _, out = _results(L)
    mask, choice = out["draw_half"]
    assert mask.dtype == bool and mask.shape == a.shape and choice.shape == a.shape
    new = out["redraw_half"]  # same key as draw_half
    np.testing.assert_array_equal(new != a, mask)
    _assert_allowed(new)
    assert abs(mask.mean() - 0.5) < 0.05
    assert abs(choice.mean() - 0.5) < 0.05


def test_redraw_mask_frequency_matches_pm():
    mask, _ = jax.jit(lo_.redraw_draw, static_argnums=1)(jax.random.key(9), 50_000, 0.02)
    assert abs(np.asarray(mask).mean() - 0.02) < 0.003


# --- batching ------------------------------------------------------------------

def test_jit_vmap_equals_item_by_item():
    keys, a, b, out = _results(11)
    single = jax.jit(_all_ops)
    for k in range(4):
        item = single(keys[k], jnp.asarray(a[k]), jnp.asarray(b[k]))
        for g, w in zip(jax.tree.leaves(item), jax.tree.leaves(out)):
            np.testing.assert_array_equal(g, w[k])


def test_registry():
    assert registry.names("label_crossover")[:1] == ("two_point",)
    assert registry.get("label_crossover", "two_point") is lo_.two_point
    assert registry.names("label_mutation")[:1] == ("redraw",)
    assert registry.get("label_mutation", "redraw") is lo_.redraw
    a = jnp.array([1, 0, 0, 1], jnp.int32)
    b = jnp.array([-1, 1, -1, -1], jnp.int32)
    c1, c2 = registry.get("label_crossover", "two_point")(jax.random.key(0), a, b)
    np.testing.assert_array_equal(np.sort(np.stack([c1, c2]), axis=0), np.sort(np.stack([a, b]), axis=0))
