"""The operator registry: every registered operator gives valid output, and operators
registered from outside the package (a selection, a crossover, a label mutation) take
part in the GA with the documented signatures and random stream."""
from __future__ import annotations

import types

import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hga_jax.errors import ConfigError
from hga_jax.host.config import load_scenario
from hga_jax.search import ga, registry, variation
from hga_jax.search.settings import GASettings

ROBOCUP = "configs/scenarios/robocup_paper.toml"
N, BATCH = 9, 32
PAIRS = [(kind, name) for kind in registry.KINDS for name in registry.names(kind)]


@pytest.fixture(scope="module")
def robocup():
    return load_scenario(ROBOCUP)


@pytest.fixture(scope="module")
def legs(robocup):
    return robocup.search_arrays(with_legs=True).legs


def _perms(n, seed):
    r = np.random.default_rng(seed)
    return jnp.asarray(np.argsort(r.random((BATCH, n)), axis=1).astype(np.int32))


def _labels(n, seed):
    r = np.random.default_rng(seed)
    lab = r.integers(-1, 2, (BATCH, n + 2)).astype(np.int32)
    lab[:, [0, -1]] = r.choice([-1, 1], (BATCH, 2))
    return jnp.asarray(lab)


def _genes(n, seed):
    return jnp.asarray(np.random.default_rng(seed).integers(0, 3, (BATCH, n + 2)).astype(np.int32))


def _assert_genes(g, n):
    g = np.asarray(g)
    assert g.shape == (BATCH, n + 2) and g.dtype == np.int32 and np.isin(g, [0, 1, 2]).all()


def _assert_perms(p, n):
    p = np.asarray(p)
    assert p.shape == (BATCH, n) and p.dtype == np.int32
    assert np.array_equal(np.sort(p, axis=1), np.tile(np.arange(n), (BATCH, 1)))


def _assert_labels(lab, n):
    lab = np.asarray(lab)
    assert lab.shape == (BATCH, n + 2) and lab.dtype == np.int32
    assert np.isin(lab, [-1, 0, 1]).all() and (lab[:, [0, -1]] != 0).all()


@pytest.mark.parametrize(("kind", "name"), PAIRS)
def test_every_registered_operator_gives_valid_output(kind, name, legs):
    fn = registry.get(kind, name)
    keys = jax.random.split(jax.random.key(7), BATCH)
    a, b = _perms(N, 1), _perms(N, 2)
    la, lb = _labels(N, 3), _labels(N, 4)
    if kind == "selection":
        fitness = jnp.asarray(np.random.default_rng(5).uniform(0.1, 3.0, 50), jnp.float32)
        opts = registry.entry(kind, name).options(GASettings(tournament_size=3))
        idx = np.asarray(jax.jit(lambda k, f: fn(k, f, **opts))(keys[0], fitness))
        assert idx.shape == (50,) and idx.dtype == np.int32
        assert ((idx >= 0) & (idx < 50)).all() and len(set(idx.tolist())) > 1
    elif kind == "perm_crossover":
        c1, c2 = jax.jit(jax.vmap(fn))(keys, a, b)
        _assert_perms(c1, N), _assert_perms(c2, N)
        assert not np.array_equal(c1, a)  # some pair was crossed
    elif kind == "perm_mutation":
        _assert_perms(jax.jit(jax.vmap(fn))(keys, a), N)
    elif kind == "label_crossover":
        c1, c2 = jax.jit(jax.vmap(fn))(keys, la, lb)
        _assert_labels(c1, N), _assert_labels(c2, N)
    elif kind == "label_mutation":
        out = jax.jit(jax.vmap(lambda k, l: fn(k, l, 0.5)))(keys, la)
        _assert_labels(out, N)
        assert not np.array_equal(out, la)
        np.testing.assert_array_equal(jax.vmap(lambda k, l: fn(k, l, 0.0))(keys, la), la)
    elif kind == "leg_crossover":
        ga_, gb_ = _genes(N, 3), _genes(N, 4)
        c1, c2 = jax.jit(jax.vmap(fn))(keys, ga_, gb_)
        _assert_genes(c1, N), _assert_genes(c2, N)
        # Genes stay at their positions: each child's gene comes from a parent there.
        assert ((c1 == ga_) | (c1 == gb_)).all() and not np.array_equal(c1, ga_)
    elif kind == "leg_mutation":
        g = _genes(N, 3)
        out = jax.jit(jax.vmap(lambda k, x: fn(k, x, 0.5)))(keys, g)
        _assert_genes(out, N)
        assert 0.3 < float(np.mean(np.asarray(out) != np.asarray(g))) < 0.7  # about half
        np.testing.assert_array_equal(jax.vmap(lambda k, x: fn(k, x, 0.0))(keys, g), g)
        np.testing.assert_array_equal(jax.vmap(lambda k, x: fn(k, x, 1.0))(keys, g) != g, True)
    elif kind == "end_mutation":  # seven-valued genes of a reversing car, positional
        g = jnp.asarray(np.random.default_rng(6).integers(0, 7, (BATCH, N + 2)), jnp.int32)
        l2, g2 = jax.jit(jax.vmap(lambda k, l, x: fn(k, l, x, 7)))(keys, la, g)
        _assert_labels(l2, N)
        g2 = np.asarray(g2)
        assert g2.shape == g.shape and ((g2 >= 0) & (g2 < 7)).all()
        if name == "none":
            assert np.array_equal(l2, la) and np.array_equal(g2, g)
        else:  # one end redrawn (at most one middle gene changes), or the direct path
            la_, l2_ = np.asarray(la), np.asarray(l2)
            same = (l2_ == la_) & (g2 == np.asarray(g))
            direct = (l2_[:, 1:-1] == 0).all(axis=1)
            assert (direct | ((~same[:, 1:-1]).sum(axis=1) <= 1)).all()
            assert not same.all()
    else:
        p2, l2 = jax.jit(jax.vmap(lambda k, p, l: fn(k, p, l, legs)))(keys, a, la)
        _assert_perms(p2, N), _assert_labels(l2, N)
        if name == "none":
            assert np.array_equal(p2, a) and np.array_equal(l2, la)


def test_names_start_with_the_builtins_and_settings_read_them():
    assert registry.names("selection") == ("roulette", "tournament")
    assert registry.names("perm_crossover") == ("cx", "pmx", "ox1")
    assert registry.names("perm_mutation") == ("inversion", "exchange")
    assert registry.names("label_crossover") == ("two_point",)
    assert registry.names("label_mutation") == ("redraw",)
    assert registry.names("path_mutation")[0] == "none"
    assert registry.names("leg_crossover") == ("two_point",)
    assert registry.names("leg_mutation") == ("redraw",)
    assert GASettings().label_mutation == "redraw"
    with pytest.raises(ValueError, match="known: cx, pmx, ox1"):
        registry.get("perm_crossover", "nope")
    with pytest.raises(ValueError, match="kind must be one of"):
        registry.names("crossover")
    with pytest.raises(ConfigError, match="label_mutation: must be one of redraw"):
        GASettings(label_mutation="nope")


def test_register_unregister_and_isolated():
    def keep(key, a, b):
        return a, b

    with registry.isolated():
        assert registry.register("perm_crossover", "keep_t", keep) is keep

        @registry.register("label_mutation", "same_t")
        def same(key, labels, rate):
            return labels

        assert callable(same) and registry.get("label_mutation", "same_t") is same
        assert registry.names("perm_crossover") == ("cx", "pmx", "ox1", "keep_t")
        assert GASettings(perm_crossover="keep_t", label_mutation="same_t").perm_crossover == "keep_t"
        assert registry.register("perm_crossover", "keep_t", keep) is keep  # same fn: no-op
        with pytest.raises(ValueError, match="already registered"):
            registry.register("perm_crossover", "keep_t", lambda k, a, b: (b, a))
        with pytest.raises(ValueError, match="built in"):
            registry.register("perm_crossover", "cx", keep)
        with pytest.raises(ValueError, match="built in"):
            registry.register("path_mutation", "none", keep)
        with pytest.raises(ValueError, match="identifier"):
            registry.register("perm_mutation", "my op", lambda k, p: p)
        with pytest.raises(TypeError, match="unknown options"):
            registry.register("selection", "s_t", keep, size=3)
        registry.unregister("perm_crossover", "keep_t")
        assert "keep_t" not in registry.names("perm_crossover")
        with pytest.raises(ValueError, match="built in"):
            registry.unregister("selection", "roulette")
    assert registry.names("label_mutation") == ("redraw",)
    with pytest.raises(ConfigError, match="perm_crossover"):
        GASettings(perm_crossover="keep_t")


# --- user operators inside the GA -----------------------------------------------------

def _population(P=10, n=N, seed=0):
    fitness = jnp.asarray(np.random.default_rng(seed).uniform(0.5, 2.0, P), jnp.float32)
    return types.SimpleNamespace(perm=_perms(n, seed)[:P], labels=_labels(n, seed)[:P],
                                 fitness=fitness, legs=None)


def _vary(settings, old, seed=0):
    words = jax.random.bits(jax.random.key(seed), (variation.draw_rows(old.perm.shape[1], settings),
                                                   old.perm.shape[0]), dtype=jnp.uint32)

    @jax.jit  # compiled: eager, the variation's many small steps take seconds
    def vary(words, perm, labels, fitness):
        pop = types.SimpleNamespace(perm=perm, labels=labels, fitness=fitness, legs=old.legs)
        return variation._vary(words, pop, settings)[:2]

    return (np.asarray(x) for x in vary(words, old.perm, old.labels, old.fitness))


def test_user_crossover_selection_and_label_mutation_in_one_generation():
    def in_order(key, fitness):
        return jnp.arange(fitness.shape[-1], dtype=jnp.int32)

    def swap(key, a, b):
        return b, a

    def negate(key, labels, rate):
        return jnp.where(rate > 0, -labels, labels)

    with registry.isolated():
        registry.register("selection", "in_order_t", in_order)
        registry.register("perm_crossover", "swap_t", swap)
        registry.register("label_crossover", "swap_t", swap)
        registry.register("label_mutation", "negate_t", negate)
        old = _population(P=11)
        s = GASettings(population=11, selection="in_order_t", perm_crossover="swap_t",
                       label_crossover="swap_t", label_mutation="negate_t", pc_upper=1.0,
                       pm_upper=0.0, pc_lower=0.0, pm_lower=0.3)
        perm, labels = _vary(s, old)
        want = np.asarray(old.perm)
        want = np.concatenate([want[:10].reshape(5, 2, N)[:, ::-1].reshape(10, N), want[10:]])
        np.testing.assert_array_equal(perm, want)  # pairs swapped, the odd last one kept
        np.testing.assert_array_equal(labels, -np.asarray(old.labels))  # rate > 0 reached it
        perm0, labels0 = _vary(s.replace(pc_upper=0.0, pm_lower=0.0), old)
        np.testing.assert_array_equal(perm0, old.perm)
        np.testing.assert_array_equal(labels0, old.labels)
        # A user selection and label mutation take two rows of keys each.
        at = variation._layout(N, s)
        assert at["select"][1] == 2 and at["mutate_lower"][1] == 2
    paper = variation._layout(N, GASettings())
    assert paper["select"] == (0, 1) and paper["mutate_lower"] == (10, N + 2)
    assert variation._layout(N, GASettings(selection="tournament", tournament_size=3))["select"] == (0, 3)


def test_user_selection_option_is_passed():
    seen = {}

    def best_of(key, fitness, tournament_size):
        seen["size"] = tournament_size
        return jnp.full(fitness.shape, jnp.argmax(fitness), jnp.int32)

    with registry.isolated():
        registry.register("selection", "best_t", best_of, settings=("tournament_size",))
        old = _population(P=8)
        s = GASettings(population=8, selection="best_t", tournament_size=5, pc_upper=0.0,
                       pm_upper=0.0, pc_lower=0.0, pm_lower=0.0)
        perm, labels = _vary(s, old)
    assert seen["size"] == 5
    best = int(np.argmax(np.asarray(old.fitness)))
    np.testing.assert_array_equal(perm, np.tile(np.asarray(old.perm)[best], (8, 1)))
    np.testing.assert_array_equal(labels, np.tile(np.asarray(old.labels)[best], (8, 1)))


@pytest.mark.slow  # user operators in a batch stay in the default lane: test_plugins.py's run test
def test_run_batch_with_user_operators(robocup):
    sa = robocup.search_arrays()

    def fittest(key, fitness):
        return jnp.full(fitness.shape, jnp.argmax(fitness), jnp.int32)

    def keep(key, a, b):
        return a, b

    with registry.isolated():
        registry.register("selection", "fittest_t", fittest)
        registry.register("perm_crossover", "keep_t", keep)
        s = GASettings(selection="fittest_t", generations=2, pc_upper=0.0, pm_upper=0.0,
                       pc_lower=0.0, pm_lower=0.0)
        best, hist = ga.run_batch(3, range(6), sa, s)
        bf, mf = np.asarray(hist.best_fitness), np.asarray(hist.mean_fitness)
        # Clones of generation 0's best from generation 1 on: mean equals best.
        np.testing.assert_array_equal(bf[:, 1], bf[:, 0])
        np.testing.assert_allclose(mf[:, 1:], bf[:, 1:], rtol=1e-6)
        assert (mf[:, 0] < bf[:, 0]).all()
        # A crossover that keeps the parents, always applied, is no crossover at all:
        # it reads the very rows of words the built-in would.
        plain = GASettings(generations=5, pc_upper=0.0)
        mine = GASettings(generations=5, pc_upper=1.0, perm_crossover="keep_t")
        h0, h1 = ga.run_batch(3, range(6), sa, plain)[1], ga.run_batch(3, range(6), sa, mine)[1]
        for x, y in zip(h0, h1):
            np.testing.assert_array_equal(x, y)
        cx = ga.run_batch(3, range(6), sa, plain.replace(pc_upper=1.0))[1]
        assert not np.array_equal(cx.mean_fitness, h0.mean_fitness)
