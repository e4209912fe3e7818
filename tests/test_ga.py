"""The GA loop: determinism, batching, best-so-far tracking, elitism, operator registry."""
import itertools

import numpy as np
import pytest

from hga_jax.host.config import load_scenario
from hga_jax.model.path import evaluate_path
from hga_jax.running.runner import run_many
from hga_jax.model.scenario import Scenario
from hga_jax.search.settings import GASettings

ROBOCUP = "configs/scenarios/robocup_paper.toml"
FIELDS = ("perm", "labels", "length", "violations", "generation")


@pytest.fixture(scope="module")
def robocup():
    return load_scenario(ROBOCUP)


@pytest.fixture(scope="module")
def batch100(robocup):
    return run_many(robocup, "paper", seed=3, runs=100, exact=False)


def _same_runs(a, b, rows_a, rows_b):
    for f in FIELDS:
        assert np.array_equal(getattr(a, f)[rows_a], getattr(b, f)[rows_b]), f
    for h in a.history:
        assert np.array_equal(a.history[h][:, rows_a], b.history[h][:, rows_b]), h


def test_same_seed_gives_identical_results(robocup, batch100):
    again = run_many(robocup, "paper", seed=3, runs=100, exact=False)
    _same_runs(again, batch100, slice(None), slice(None))
    other = run_many(robocup, "paper", seed=4, runs=100, exact=False)
    assert not np.array_equal(other.history["mean_fitness"], batch100.history["mean_fitness"])


@pytest.mark.parametrize("k", [0, 41, 99])
def test_run_k_alone_equals_run_k_in_a_batch(robocup, batch100, k):
    alone = run_many(robocup, "paper", seed=3, runs=1, first_run=k, exact=False)
    _same_runs(alone, batch100, slice(0, 1), slice(k, k + 1))


def test_chunking_and_blocks_do_not_change_runs(robocup, batch100, monkeypatch):
    from hga_jax.running import budget

    # About 3 generations per block: 51 generations in 17 blocks.
    monkeypatch.setattr(budget, "BLOCK_WORK", 9 * 7 * 50 * 3)
    assert budget.plan(9, batch100.settings, 30, 7).block == 3
    part = run_many(robocup, "paper", seed=3, runs=30, first_run=10, chunk=7, exact=False)
    _same_runs(part, batch100, slice(None), slice(10, 40))


def test_blocks_equal_one_scan_and_run_batch_takes_a_list(robocup, monkeypatch):
    import jax

    from hga_jax.running import budget
    from hga_jax.search import ga

    from hga_jax import compiled

    s = GASettings(generations=12)  # 13 generations in blocks of 4: a ragged last block
    monkeypatch.setattr(budget, "BLOCK_WORK", 9 * 4 * 50 * 4)
    assert budget.plan(9, s, 10, 4).block == 4  # generations 0-3, 4-7, 8-11, 12
    # The generation count is data: a job of 15 generations compiles the program that
    # then runs these 13 (the comparison with one scan below checks its bits).
    run_many(robocup, GASettings(generations=14), seed=5, runs=4, chunk=4, exact=False)
    before = compiled.tally()
    res = run_many(robocup, s, seed=5, runs=10, chunk=4, exact=False)
    assert compiled.tally_since(before)["ga-block"] == {"compiled": 0, "loaded": 0, "reused": 1}
    sa = robocup.search_arrays()
    # a plain list; the scenario an argument, as the runner passes it (not folded in)
    best, history = jax.jit(lambda a: ga.run_batch(5, [0, 5, 9], a, s))(sa)
    for f in ("perm", "labels", "generation"):
        assert np.array_equal(np.asarray(getattr(best, f)), getattr(res, f)[[0, 5, 9]]), f
    for name, value in history._asdict().items():
        assert np.array_equal(np.asarray(value).T, res.history[name][:, [0, 5, 9]]), name
    with pytest.raises(TypeError, match="ks: expected a 1-D sequence of integer run indices"):
        ga.run_batch(5, [0.5, 1.0], robocup.arrays(), s)
    assert jax.tree.leaves(best)[0].shape[0] == 3


def test_history_and_best_so_far(batch100):
    h = batch100.history
    g = batch100.settings.generations
    assert h["best_fitness"].shape == (g + 1, 100)
    assert np.all(np.diff(h["best_so_far_fitness"], axis=0) >= 0)
    assert np.all(h["best_fitness"] <= h["best_so_far_fitness"])
    assert np.all(h["mean_fitness"] <= h["best_fitness"] * (1 + 1e-6))
    # The generation first reached is where the best-so-far fitness last rose.
    last = h["best_so_far_fitness"][-1]
    first = np.argmax(h["best_so_far_fitness"] == last[None], axis=0)
    assert np.array_equal(first, batch100.generation)
    assert batch100.evaluations == 100 * 50 * 51


def test_reported_lengths_are_float64_re_evaluations(robocup, batch100):
    for i in (0, 7, 55):
        p = evaluate_path(robocup, batch100.perm[i], batch100.labels[i])
        assert p.length == batch100.length[i] and p.violations == batch100.violations[i]
    best = batch100.best
    assert best.length == batch100.length[batch100.best_run]
    assert best.length == pytest.approx(min(batch100.length[batch100.feasible]), rel=1e-12)


def test_elitism_keeps_the_generation_best(robocup):
    s = GASettings(elites=2, generations=15)
    res = run_many(robocup, s, seed=1, runs=20, exact=False)
    assert np.all(np.diff(res.history["best_fitness"], axis=0) >= 0)


@pytest.mark.parametrize("m,e", [(2, 2), (10, 2), (50, 3)])
def test_elites_are_top_k_with_ties_to_the_lower_index(m, e):
    import jax
    import jax.numpy as jnp

    from hga_jax.search.ga import top_indices

    rng = np.random.default_rng(m)
    pick = jax.jit(top_indices, static_argnums=1)
    for _ in range(50):  # few distinct values: many ties
        x = rng.integers(1, 5, m).astype(np.float32) / 4
        want = np.argsort(-x, kind="stable")[:e]
        assert np.array_equal(np.asarray(pick(jnp.asarray(x), e)), want)
        assert np.array_equal(np.asarray(jax.lax.top_k(x, e)[1]), want)


@pytest.mark.parametrize("selection,crossover,mutation", [
    ("tournament", "pmx", "exchange"), ("roulette", "ox1", "exchange"),
    ("tournament", "cx", "inversion"),
])
def test_every_operator_runs_and_keeps_chromosomes_valid(robocup, selection, crossover, mutation):
    s = GASettings(selection=selection, perm_crossover=crossover, perm_mutation=mutation,
                   tournament_size=3, pc_upper=0.9, pm_upper=0.3, pm_lower=0.1, generations=10)
    res = run_many(robocup, s, seed=2, runs=8, exact=False)
    n = robocup.n
    for perm, labels in zip(res.perm, res.labels):
        assert sorted(perm) == list(range(n))
        assert labels[0] in (-1, 1) and labels[-1] in (-1, 1)
        assert set(labels[1:-1]) <= {-1, 0, 1}
    assert np.all(np.isfinite(res.length))


def test_open_field_finds_the_best_dubins_word():
    sc = load_scenario("configs/scenarios/open_field.toml")
    best = min(evaluate_path(sc, [], [a, b]).length for a, b in itertools.product((-1, 1), repeat=2))
    res = run_many(sc, GASettings(generations=5), seed=0, runs=4, exact=False)
    assert res.best.length == pytest.approx(best, rel=1e-12)


def test_small_scene_reaches_the_brute_force_minimum():
    rng = np.random.default_rng(5)
    sc = Scenario("small", 0.09, 0.18, (0.2, 0.2, 0.0), (2.2, 1.0, 0.0),
                  np.array([[1.0, 0.4], [1.4, 0.9], [1.8, 0.5]]), np.full(3, 0.09))
    best = np.inf
    for perm in itertools.permutations(range(3)):
        for labels in itertools.product((-1, 1), (-1, 0, 1), (-1, 0, 1), (-1, 0, 1), (-1, 1)):
            p = evaluate_path(sc, perm, labels)
            if p.feasible:
                best = min(best, p.length)
    res = run_many(sc, "paper", seed=int(rng.integers(100)), runs=20, exact=False)
    assert res.best.length == pytest.approx(best, rel=1e-9)
    assert np.all(res.length[res.feasible] >= best * (1 - 1e-9))


def test_float64_search(robocup):
    res = run_many(robocup, GASettings(precision="float64", generations=5), runs=3, exact=False)
    assert np.all(np.isfinite(res.length))


SHARDED = """
import json, sys, jax
from hga_jax.host.config import load_scenario
from hga_jax.running.runner import run_many
from hga_jax.search.settings import GASettings
r = run_many(load_scenario(sys.argv[1]), GASettings(generations=6), seed=2, runs=5, exact=False)
print(json.dumps([jax.device_count(), r.length.tolist(), r.history["mean_fitness"].tolist()]))
"""


@pytest.mark.slow  # the default lane has test_devices' 1 against 3 devices
def test_sharding_over_two_devices_gives_the_same_runs():
    import json
    import os
    import subprocess
    import sys

    outs = []
    for devices in (1, 2):
        env = {**os.environ, "XLA_FLAGS": f"--xla_force_host_platform_device_count={devices}",
               "JAX_PLATFORMS": "cpu"}
        proc = subprocess.run([sys.executable, "-c", SHARDED, ROBOCUP], capture_output=True,
                              text=True, env=env, check=True)
        outs.append(json.loads(proc.stdout.strip().splitlines()[-1]))
    assert [o[0] for o in outs] == [1, 2]
    assert outs[0][1:] == outs[1][1:]


@pytest.mark.slow  # test_blocks_equal_one_scan_and_run_batch_takes_a_list stays in the default lane
def test_one_compiled_generation_equals_the_scanned_one(robocup):
    import jax

    from hga_jax.search import ga

    s, sa = GASettings(generations=3), robocup.search_arrays()
    key = ga.run_key(7, 0)
    _, history = ga.run(key, sa, s)
    with jax.threefry_partitionable(False):  # the stream the GA draws from
        k0, kg = jax.random.split(key)
        keys = jax.random.split(kg, s.generations)
    state = ga.init(k0, sa, s)
    for g, k in enumerate(keys, start=1):
        for name, value in ga.record(state)._asdict().items():  # generation g - 1
            assert np.array_equal(np.asarray(value), np.asarray(getattr(history, name))[g - 1]), name
        state = ga.compiled_step(k, state)
        assert int(state.generation) == g + 1
    for name, value in ga.record(state)._asdict().items():
        assert np.array_equal(np.asarray(value), np.asarray(getattr(history, name))[-1]), name


def test_run_alone_equals_batch_on_a_large_scene_with_other_operators():
    sc = load_scenario("configs/scenarios/cluttered.toml")  # n = 28: gather-based operators
    s = GASettings(generations=15, perm_crossover="pmx", selection="tournament", elites=1)
    big = run_many(sc, s, seed=9, runs=40, exact=False)
    alone = run_many(sc, s, seed=9, runs=1, first_run=27, exact=False)
    _same_runs(alone, big, slice(0, 1), slice(27, 28))
