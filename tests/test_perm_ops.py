"""Tests of the permutation operators (upper module)."""
from __future__ import annotations

import functools
import itertools
from collections import Counter

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hga_jax.search import perm_crossover as pc
from hga_jax.search import perm_mutation as pmu
from hga_jax.search import permutation as pm
from hga_jax.search import registry

# The built-in operators, as the GA finds them.
CROSSOVERS = {name: registry.get("perm_crossover", name) for name in ("cx", "pmx", "ox1")}
MUTATIONS = {name: registry.get("perm_mutation", name) for name in ("inversion", "exchange")}

SIZES = [1, 2, 3, 9, 25]
BATCH = 64

# Eiben & Smith's 9-element example (1-based 1..9 and 9 3 7 8 2 6 5 1 4), 0-based.
A9 = np.arange(9, dtype=np.int32)
B9 = np.array([8, 2, 6, 7, 1, 5, 4, 0, 3], dtype=np.int32)


def _parents(n: int, seed: int = 0, batch: int = BATCH):
    """Operator keys and two batches of random parent permutations."""
    rng = np.random.default_rng(seed)
    a = np.argsort(rng.random((batch, n)), axis=1).astype(np.int32)
    b = np.argsort(rng.random((batch, n)), axis=1).astype(np.int32)
    return jax.random.split(jax.random.key(seed), batch), a, b


def _assert_perms(x, n: int) -> None:
    x = np.asarray(x)
    assert x.dtype == np.int32
    assert x.shape[-1] == n
    np.testing.assert_array_equal(np.sort(x, axis=-1), np.broadcast_to(np.arange(n), x.shape))


# --- numpy references, written as the textbook procedures --------------------

def ref_cx(a, b, start):
    pos_a = {v: i for i, v in enumerate(a)}
    cycle, i = set(), start
    while i not in cycle:
        cycle.add(i)
        i = pos_a[b[i]]
    c1 = [a[i] if i in cycle else b[i] for i in range(len(a))]
    c2 = [b[i] if i in cycle else a[i] for i in range(len(a))]
    return c1, c2


def _ref_pmx_child(p1, p2, lo, hi):
    n = len(p1)
    child = [None] * n
    child[lo:hi] = p1[lo:hi]
    pos_p2 = {v: i for i, v in enumerate(p2)}
    for k in range(lo, hi):
        v = p2[k]
        if v in child:
            continue
        j = k
        while True:  # look at what p1 put there, find it in p2
            j = pos_p2[p1[j]]
            if not lo <= j < hi:
                break
        child[j] = v
    return [p2[k] if c is None else c for k, c in enumerate(child)]


def ref_pmx(a, b, lo, hi):
    return _ref_pmx_child(list(a), list(b), lo, hi), _ref_pmx_child(list(b), list(a), lo, hi)


def _ref_ox1_child(p1, p2, lo, hi):
    n = len(p1)
    child = [None] * n
    child[lo:hi] = p1[lo:hi]
    order = [(hi + t) % n for t in range(n)]
    values = [p2[k] for k in order if p2[k] not in p1[lo:hi]]
    free = [k for k in order if not lo <= k < hi]
    for k, v in zip(free, values, strict=True):
        child[k] = v
    return child


def ref_ox1(a, b, lo, hi):
    return _ref_ox1_child(list(a), list(b), lo, hi), _ref_ox1_child(list(b), list(a), lo, hi)


# --- worked examples -----------------------------------------------------------

def test_cx_worked_example():
    # Position map i -> position in a of b[i] (a is the identity, so it is b[i]):
    # 0 -> 8 -> 3 -> 7 -> 0, 1 -> 2 -> 6 -> 4 -> 1, 5 -> 5.
    c1, c2 = pc.cx_apply(A9, B9, 0)  # cycle {0, 3, 7, 8} from a, the rest from b
    np.testing.assert_array_equal(c1, [0, 2, 6, 3, 1, 5, 4, 7, 8])
    np.testing.assert_array_equal(c2, [8, 1, 2, 7, 4, 5, 6, 0, 3])
    c1, c2 = pc.cx_apply(A9, B9, 4)  # cycle {1, 2, 4, 6}
    np.testing.assert_array_equal(c1, [8, 1, 2, 7, 4, 5, 6, 0, 3])
    np.testing.assert_array_equal(c2, [0, 2, 6, 3, 1, 5, 4, 7, 8])
    c1, c2 = pc.cx_apply(A9, B9, 5)  # fixed point: a[5] == b[5], children = parents
    np.testing.assert_array_equal(c1, B9)
    np.testing.assert_array_equal(c2, A9)


def test_pmx_worked_example():
    # Segment [3, 7): a's 3 4 5 6 go to c1, b's 7 1 5 4 sit opposite.
    # c1 outside the segment takes b's 8 2 6 . . . . 0 3 and repairs clashes via
    # the pairs 3->7, 4->1, 5->5, 6->4: position 2 has 6 -> 4 -> 1 (free), so 1;
    # position 8 has 3 -> 7 (free), so 7. c1 = 8 2 1 3 4 5 6 0 7
    # (Eiben & Smith, 1-based: 9 3 2 4 5 6 7 1 8).
    # c2 keeps b's 7 1 5 4 and takes a's 0 1 2 . . . . 7 8 with the pairs
    # 7->3, 1->4, 5->5, 4->6: position 1 has 1 -> 4 -> 6, so 6; position 7 has
    # 7 -> 3, so 3. c2 = 0 6 2 7 1 5 4 3 8.
    c1, c2 = pc.pmx_apply(A9, B9, 3, 7)
    np.testing.assert_array_equal(c1, [8, 2, 1, 3, 4, 5, 6, 0, 7])
    np.testing.assert_array_equal(c2, [0, 6, 2, 7, 1, 5, 4, 3, 8])


def test_ox1_worked_example():
    # Segment [3, 7). c1 keeps a's 3 4 5 6; b read from position 7 and wrapping is
    # 0 3 8 2 6 7 1 5 4; without 3 4 5 6 it is 0 8 2 7 1, written to positions
    # 7 8 0 1 2: c1 = 2 7 1 3 4 5 6 0 8 (Eiben & Smith, 1-based: 3 8 2 4 5 6 7 1 9).
    # c2 keeps b's 7 1 5 4; a from position 7 is 7 8 0 1 2 3 4 5 6, without
    # 7 1 5 4 it is 8 0 2 3 6, written to 7 8 0 1 2: c2 = 2 3 6 7 1 5 4 8 0.
    c1, c2 = pc.ox1_apply(A9, B9, 3, 7)
    np.testing.assert_array_equal(c1, [2, 7, 1, 3, 4, 5, 6, 0, 8])
    np.testing.assert_array_equal(c2, [2, 3, 6, 7, 1, 5, 4, 8, 0])


def test_inversion_worked_examples():
    np.testing.assert_array_equal(pmu.inversion_apply(A9, 2, 6), [0, 1, 5, 4, 3, 2, 6, 7, 8])
    np.testing.assert_array_equal(pmu.inversion_apply(A9, 0, 9), A9[::-1])
    np.testing.assert_array_equal(pmu.inversion_apply(B9, 7, 9), [8, 2, 6, 7, 1, 5, 4, 3, 0])
    np.testing.assert_array_equal(pmu.inversion_apply(B9, 4, 5), B9)


def test_exchange_worked_examples():
    np.testing.assert_array_equal(pmu.exchange_apply(A9, 1, 7), [0, 7, 2, 3, 4, 5, 6, 1, 8])
    np.testing.assert_array_equal(pmu.exchange_apply(B9, 8, 0), [3, 2, 6, 7, 1, 5, 4, 0, 8])


# --- properties over random parents ------------------------------------------------

def _all_ops(key, a, b):
    """Every operator on one pair, with the draws each one made from ``key``."""
    n = a.shape[-1]
    out = {name: op(key, a, b) for name, op in CROSSOVERS.items()}
    out.update({name: op(key, a) for name, op in MUTATIONS.items()})
    out["start"] = pc.cx_draw(key, n)
    out["cut"] = pm.cut_draw(key, n)  # also pmx_draw, ox1_draw, inversion_draw
    out["ij"] = pmu.exchange_draw(key, n)
    return out


def _run_all(n: int, batch: int = BATCH, seed: int = 0):
    """Parents and every operator's result, batched under one fresh jit."""
    keys, a, b = _parents(n, seed=seed, batch=batch)
    out = jax.jit(lambda k, x, y: jax.vmap(_all_ops)(k, x, y))(keys, a, b)
    return keys, np.asarray(a), np.asarray(b), jax.tree.map(np.asarray, out)


@functools.lru_cache(maxsize=None)
def _results(n: int):
    return _run_all(n, seed=n)


def _reference_children(name, a, b, out, k):
    if name == "cx":
        return ref_cx(a[k].tolist(), b[k].tolist(), int(out["start"][k]))
    ref = {"pmx": ref_pmx, "ox1": ref_ox1}[name]
    lo, hi = out["cut"]
    return ref(a[k].tolist(), b[k].tolist(), int(lo[k]), int(hi[k]))


@pytest.mark.parametrize("n", SIZES)
@pytest.mark.parametrize("name", sorted(CROSSOVERS))
def test_crossover_children_are_permutations(name, n):
    _, _, _, out = _results(n)
    c1, c2 = out[name]
    _assert_perms(c1, n)
    _assert_perms(c2, n)


@pytest.mark.parametrize("n", SIZES)
@pytest.mark.parametrize("name", sorted(CROSSOVERS))
def test_crossover_matches_textbook_reference(name, n):
    _, a, b, out = _results(n)
    c1, c2 = out[name]
    for k in range(len(a)):
        e1, e2 = _reference_children(name, a, b, out, k)
        np.testing.assert_array_equal(c1[k], e1)
        np.testing.assert_array_equal(c2[k], e2)
    if name != "cx":  # c1 keeps a's segment, c2 keeps b's
        lo, hi = out["cut"]
        seg = (np.arange(n) >= lo[:, None]) & (np.arange(n) < hi[:, None])
        np.testing.assert_array_equal(np.where(seg, c1, a), a)
        np.testing.assert_array_equal(np.where(seg, c2, b), b)


@pytest.mark.parametrize("n", SIZES)
def test_cx_properties(n):
    _, a, b, out = _results(n)
    c1, c2 = out["cx"]
    starts = out["start"]
    assert ((starts >= 0) & (starts < n)).all()
    assert ((c1 == a) | (c1 == b)).all() and ((c2 == a) | (c2 == b)).all()
    np.testing.assert_array_equal(c1 == a, c2 == b)
    rows = np.arange(len(a))
    np.testing.assert_array_equal(c1[rows, starts], a[rows, starts])
    np.testing.assert_array_equal(c2[rows, starts], b[rows, starts])


@pytest.mark.parametrize("n", SIZES)
@pytest.mark.parametrize("name", sorted(MUTATIONS))
def test_mutation_results_are_permutations(name, n):
    _, _, _, out = _results(n)
    _assert_perms(out[name], n)


@pytest.mark.parametrize("n", SIZES)
def test_mutations_change_what_they_should(n):
    _, a, _, out = _results(n)
    lo, hi = out["cut"]
    for p, l, h, o in zip(a, lo, hi, out["inversion"]):
        np.testing.assert_array_equal(o, np.concatenate([p[:l], p[l:h][::-1], p[h:]]))
    i, j = out["ij"]
    if n >= 2:
        assert (i != j).all()
    expected = a.copy()
    rows = np.arange(len(a))
    expected[rows, i], expected[rows, j] = a[rows, j], a[rows, i]
    np.testing.assert_array_equal(out["exchange"], expected)


@pytest.mark.parametrize("n", [1, 25])
def test_random_permutation(n):
    keys = jax.random.split(jax.random.key(7), 200)
    perms = np.asarray(jax.jit(jax.vmap(pm.random_permutation, (0, None)), static_argnums=1)(keys, n))
    _assert_perms(perms, n)
    if n > 1:
        assert len({tuple(p) for p in perms}) == 200
        # Each value lands in each position about equally often (200 / 25 = 8).
        assert np.bincount(perms[:, 0], minlength=n).max() < 25


@pytest.mark.parametrize("n", [1, 2, 9, pm.RANK_MAX_N, pm.RANK_MAX_N + 1, 40, pm.SCAN_MAX_N,
                               pm.SCAN_MAX_N + 1])
def test_permutation_from_words_is_the_stable_argsort(n):
    """Ranked by comparisons (n <= RANK_MAX_N), counted in passes over the genes
    (n <= SCAN_MAX_N) or sorted, the permutation is numpy's
    stable argsort of the words, ties (forced here, and words of few values) included."""
    rng = np.random.default_rng(n)
    words = rng.integers(0, 2**32, size=(300, n), dtype=np.uint32)
    words[:100, n // 2] = words[:100, 0]  # a tie in each of the first 100
    words[100:200] = rng.integers(0, 3, size=(100, n), dtype=np.uint32)  # many ties
    got = np.asarray(jax.jit(pm.permutation_from_words)(words))
    assert got.dtype == np.int32
    np.testing.assert_array_equal(got, np.argsort(words, axis=-1, kind="stable"))


def test_every_segment_exhaustively():
    n = 9
    pairs = np.array(list(itertools.combinations(range(n + 1), 2)), np.int32)

    def one(lo, hi):
        return (pc.pmx_apply(A9, B9, lo, hi), pc.ox1_apply(A9, B9, lo, hi),
                pmu.inversion_apply(B9, lo, hi))

    pmx, ox1, inv = jax.tree.map(np.asarray, jax.jit(jax.vmap(one))(pairs[:, 0], pairs[:, 1]))
    for k, (l, h) in enumerate(pairs.tolist()):
        for (c1, c2), ref in ((pmx, ref_pmx), (ox1, ref_ox1)):
            e1, e2 = ref(A9.tolist(), B9.tolist(), l, h)
            np.testing.assert_array_equal(c1[k], e1)
            np.testing.assert_array_equal(c2[k], e2)
        np.testing.assert_array_equal(inv[k], np.concatenate([B9[:l], B9[l:h][::-1], B9[h:]]))


@pytest.mark.parametrize(("n", "threshold"), [(9, 0), (25, 10**6)])
def test_lookup_paths_agree(monkeypatch, n, threshold):
    """Forcing the other look-up path (gathers at n = 9, one-hot at n = 25)
    gives the same results."""
    monkeypatch.setattr(pm, "ONEHOT_MAX_N", threshold)
    _, _, _, got = _run_all(n, seed=n)
    _, _, _, want = _results(n)
    for name in list(CROSSOVERS) + list(MUTATIONS):
        for g, w in zip(jax.tree.leaves(got[name]), jax.tree.leaves(want[name])):
            np.testing.assert_array_equal(g, w)


# --- draws ---------------------------------------------------------------------

DRAWS = 30_000


@functools.lru_cache(maxsize=None)
def _draws():
    """Many draws of each kind under one jit: cuts (n = 4), exchange pairs
    (n = 3), cycle starts (n = 5)."""

    def one(key):
        return pm.cut_draw(key, 4), pmu.exchange_draw(key, 3), pc.cx_draw(key, 5)

    keys = jax.random.split(jax.random.key(1), DRAWS)
    return jax.tree.map(np.asarray, jax.jit(jax.vmap(one))(keys))


def test_cut_draw_is_uniform_over_segments():
    lo, hi = _draws()[0]
    freq = Counter(zip(lo.tolist(), hi.tolist()))
    assert set(freq) == set(itertools.combinations(range(5), 2))  # 10 segments
    for c in freq.values():
        assert abs(c / DRAWS - 0.1) < 0.01


def test_exchange_draw_is_uniform_over_distinct_pairs():
    i, j = _draws()[1]
    freq = Counter(zip(i.tolist(), j.tolist()))
    assert set(freq) == set(itertools.permutations(range(3), 2))
    for c in freq.values():
        assert abs(c / DRAWS - 1 / 6) < 0.015


def test_cx_start_is_uniform():
    freq = np.bincount(_draws()[2], minlength=5) / DRAWS
    np.testing.assert_allclose(freq, 0.2, atol=0.015)


def test_uniform_int_range_and_frequencies():
    x = np.asarray(pm.uniform_int(jax.random.key(5), (60_000,), 3, 9))
    assert x.dtype == np.int32 and x.min() == 3 and x.max() == 8
    np.testing.assert_allclose(np.bincount(x - 3) / 60_000, 1 / 6, atol=0.01)
    y = pm.uniform_int(jax.random.key(6), (4,), jnp.array([0, 2, 5, 7]), jnp.array([1, 3, 6, 8]))
    np.testing.assert_array_equal(y, [0, 2, 5, 7])  # one-value ranges


def test_tiny_sizes_are_identity_like():
    _, _, _, out = _results(1)
    np.testing.assert_array_equal(out["cut"], [[0] * BATCH, [1] * BATCH])
    np.testing.assert_array_equal(out["ij"], 0)
    np.testing.assert_array_equal(out["start"], 0)
    for name in list(CROSSOVERS) + list(MUTATIONS):
        np.testing.assert_array_equal(np.stack(jax.tree.leaves(out[name])), 0)
    _, a, _, out = _results(2)
    np.testing.assert_array_equal(out["exchange"], a[:, ::-1])  # n = 2: always a swap


# --- batching ------------------------------------------------------------------

def test_jit_vmap_equals_item_by_item():
    keys, a, b, out = _results(9)
    single = jax.jit(_all_ops)
    for k in range(4):
        item = single(keys[k], jnp.asarray(a[k]), jnp.asarray(b[k]))
        for name in out:
            for g, w in zip(jax.tree.leaves(item[name]), jax.tree.leaves(out[name])):
                np.testing.assert_array_equal(g, w[k])


def test_raw_uint32_keys_work():
    key = jax.random.PRNGKey(3)
    c1, c2 = pc.cx(key, jnp.asarray(A9), jnp.asarray(B9))
    _assert_perms(c1, 9)
    _assert_perms(pmu.inversion(key, jnp.asarray(B9)), 9)
