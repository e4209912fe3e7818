"""Islands: parents come from the child's own island, each island keeps its own
elites, migrants go from the best of one island to the worst of the next when due,
one island is the GA as it was, and a run with islands is the same alone and in a
batch."""
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hga_jax.errors import ConfigError
from hga_jax.host.config import load_scenario
from hga_jax.running.runner import run_many
from hga_jax.search import ga, islands
from hga_jax.search.selection import roulette_from_words, tournament_from_words
from hga_jax.search.settings import PAPER, RECOMMENDED
from hga_jax.search.state import Population


@pytest.mark.parametrize("pick", [tournament_from_words, roulette_from_words])
@pytest.mark.parametrize("k", [1, 2, 5])
def test_parents_come_from_the_childs_island(pick, k):
    rng = np.random.default_rng(k)
    p = 50
    words = jnp.asarray(rng.integers(0, 2**32, (p, 2), dtype=np.uint64).astype(np.uint32))
    fitness = jnp.asarray(rng.uniform(1.0, 2.0, p).astype(np.float32))
    idx = np.asarray(islands.select(pick, words, fitness, k))
    size = p // k
    assert np.array_equal(idx // size, np.arange(p) // size)
    # within an island, the pick is the selection's own on that island's rows
    for i in range(k):
        rows = slice(i * size, (i + 1) * size)
        own = np.asarray(pick(words[rows], fitness[rows]))
        assert np.array_equal(idx[rows] - i * size, own)


def _pop(fitness):
    p = len(fitness)
    perm = jnp.arange(p, dtype=jnp.int32)[:, None] * jnp.ones((1, 3), jnp.int32)
    f = jnp.asarray(fitness, jnp.float32)
    return Population(perm, perm, f, -f, jnp.zeros(p, jnp.int32), None)


def test_migrants_go_from_each_islands_best_to_the_next_islands_worst():
    fitness = [5, 1, 9, 3,   2, 8, 8, 0,   7, 4, 4, 6]  # three islands of four
    pop = _pop(fitness)
    moved = islands.migrate(pop, pop.fitness, jnp.bool_(True), 3)
    # bests (first of equals): 2, 5, 8; worsts: 1, 7, 9 (first of equals)
    want = np.arange(12)
    want[7], want[9], want[1] = 2, 5, 8
    assert np.array_equal(np.asarray(moved.perm[:, 0]), want)
    assert np.array_equal(np.asarray(moved.fitness), np.asarray(fitness, np.float32)[want])
    kept = islands.migrate(pop, pop.fitness, jnp.bool_(False), 3)
    assert np.array_equal(np.asarray(kept.perm), np.asarray(pop.perm))


def test_migration_is_due_at_multiples_and_never_in_a_restart():
    g = jnp.arange(0, 25)
    due = np.asarray(islands.due(g, jnp.int32(8), jnp.zeros(25, bool)))
    assert np.flatnonzero(due).tolist() == [0, 8, 16, 24]
    assert not np.asarray(islands.due(jnp.int32(16), jnp.int32(8), jnp.bool_(True)))


def test_each_island_keeps_its_own_elites():
    s = PAPER.replace(elites=1, islands=2, population=8)
    old = _pop([1, 9, 2, 3,   4, 5, 8, 6])
    new = _pop([7, 7, 0, 7,   7, 7, 7, 1])
    kept = ga._kept(new, old, jnp.bool_(False), s)
    # island 0: its best parent (9) replaces its worst child (0); island 1: 8 for 1
    assert np.asarray(kept.fitness).tolist() == [7, 7, 9, 7, 7, 7, 7, 8]


@pytest.fixture(scope="module")
def robocup():
    return load_scenario("configs/scenarios/robocup_paper.toml")


def test_one_island_is_the_ga_as_it_was(robocup):
    s = PAPER.replace(generations=6, selection="tournament", elites=2)
    a = run_many(robocup, s, seed=3, runs=6, exact=False)
    b = run_many(robocup, s.replace(islands=1, migrate_every=4), seed=3, runs=6, exact=False)
    for f in ("perm", "labels", "length", "generation"):
        assert np.array_equal(getattr(a, f), getattr(b, f)), f
    assert np.array_equal(a.history["mean_fitness"], b.history["mean_fitness"])


def test_a_run_with_islands_is_the_same_alone_and_in_a_batch(robocup):
    # the batch is the held-out floors' program (60 runs of the recommended preset at 9
    # obstacles; restart_after and migrate_every are data), the single run test_cli's summary's
    s = RECOMMENDED.replace(restart_after=4, islands=5, migrate_every=3)
    whole = run_many(robocup, s, seed=2, runs=60, exact=False)
    alone = run_many(robocup, s, seed=2, runs=1, first_run=4, exact=False)
    for f in ("perm", "labels", "length", "generation"):
        assert np.array_equal(getattr(alone, f)[0], getattr(whole, f)[4]), f
    for h in whole.history:
        assert np.array_equal(alone.history[h][:, 0], whole.history[h][:, 4]), h
    # islands change the search: not the one-population run
    one = run_many(robocup, s.replace(islands=1, migrate_every=0), seed=2, runs=1, first_run=4,
                   exact=False)
    assert not np.array_equal(one.history["mean_fitness"], alone.history["mean_fitness"])


@pytest.mark.parametrize("changes, key", [
    (dict(islands=0), "ga.islands"),
    (dict(islands=-2), "ga.islands"),
    (dict(islands=5, migrate_every=-1), "ga.migrate_every"),
])
def test_bad_island_settings_name_their_key(changes, key):
    with pytest.raises(ConfigError, match=key.replace(".", r"\.")):
        PAPER.replace("x.toml", **changes)


@pytest.mark.parametrize("population, elites, islands, count", [
    (50, 2, 5, 5), (50, 2, 3, 2), (12, 2, 5, 4), (16, 2, 5, 4), (8, 2, 5, 2), (8, 0, 5, 4),
    (7, 2, 5, 1), (50, 2, 1, 1), (50, 9, 5, 5), (50, 10, 5, 2), (4, 0, 9, 2),
])
def test_the_island_count_splits_the_population_evenly_above_the_elites(
        population, elites, islands, count):
    s = PAPER.replace(population=population, elites=elites, islands=islands)
    assert s.island_count == count
    if count > 1:
        size = population // count
        assert population % count == 0 and size >= 2 and size > elites
