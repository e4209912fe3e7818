"""The GA with path moves, seeding and restarts: the same runs alone, in batches, in
blocks and in one scan; restarts happen when and only when a run stalls; seeding
builds generation 0 from wrapped blockers."""
import numpy as np
import pytest

from hga_jax.host.config import load_scenario
from hga_jax.running.runner import run_many
from hga_jax.search.settings import RECOMMENDED

FIELDS = ("perm", "labels", "length", "violations", "generation")


@pytest.fixture(scope="module")
def robocup():
    return load_scenario("configs/scenarios/robocup_paper.toml")


def _same_runs(a, b, rows_a, rows_b):
    for f in FIELDS:
        assert np.array_equal(getattr(a, f)[rows_a], getattr(b, f)[rows_b]), f
    for h in a.history:
        assert np.array_equal(a.history[h][:, rows_a], b.history[h][:, rows_b]), h


@pytest.mark.slow  # alone = batch stays in the default lane: test_ga.py's run-k and large-scene tests
def test_recommended_run_alone_is_its_row_of_a_batch(robocup):
    s = RECOMMENDED.replace(generations=12, restart_after=3)
    whole = run_many(robocup, s, seed=2, runs=12, exact=False)
    alone = run_many(robocup, s, seed=2, runs=1, first_run=7, exact=False)
    _same_runs(alone, whole, slice(0, 1), slice(7, 8))


@pytest.mark.slow
def test_recommended_runs_are_the_same_alone_in_chunks_in_blocks_and_in_one_scan(
        robocup, monkeypatch):
    import jax

    from hga_jax.running import budget
    from hga_jax.search import ga

    s = RECOMMENDED.replace(generations=20, restart_after=3, label_binding="obstacle",
                            path_mutation="mixed")
    whole = run_many(robocup, s, seed=2, runs=24, exact=False)
    alone = run_many(robocup, s, seed=2, runs=1, first_run=17, exact=False)
    _same_runs(alone, whole, slice(0, 1), slice(17, 18))
    monkeypatch.setattr(budget, "BLOCK_WORK", 9 * 5 * 50 * 4)  # blocks of 3 generations
    part = run_many(robocup, s, seed=2, runs=10, first_run=5, chunk=5, exact=False)
    _same_runs(part, whole, slice(None), slice(5, 15))
    sa = robocup.search_arrays(with_legs=True)
    # the scenario an argument, as the runner passes it: baked in as constants, XLA may
    # fold and fuse the fitness otherwise (a mean fitness then differed in its last bit)
    best, history = jax.jit(lambda a: ga.run_batch(2, [0, 9], a, s))(sa)
    for f in ("perm", "labels", "generation"):
        assert np.array_equal(np.asarray(getattr(best, f)), getattr(whole, f)[[0, 9]]), f
    for name, value in history._asdict().items():
        assert np.array_equal(np.asarray(value).T, whole.history[name][:, [0, 9]]), name


def test_scenario_arrays_without_legs_are_refused(robocup):
    from hga_jax.search import ga

    with pytest.raises(ValueError, match="with_legs=True"):
        ga.run(ga.run_key(0, 0), robocup.search_arrays(), RECOMMENDED)


def test_restarts_come_every_r_generations_of_a_stall_and_never_otherwise(robocup):
    """With restart_after = 4, the population of a stalled run is replaced at
    generations 4, 8, ...: its mean fitness falls back to a seeded generation 0's
    level there, while elitism keeps the population's best from falling elsewhere."""
    # the held-out floors' program (60 runs of the recommended preset): a rate differs
    s = RECOMMENDED.replace(restart_after=4)
    res = run_many(robocup, s, seed=1, runs=60, exact=False)
    best_pop = res.history["best_fitness"]  # (G + 1, R): best of each generation's population
    for r in range(60):
        for g in range(1, 51):
            if g % 4:  # two elites: the population's best never falls outside restarts
                assert best_pop[g, r] >= best_pop[g - 1, r], (r, g)
    # on this scene most runs hold the optimum from generation 0 and stall: the
    # restart generations are new seeded populations, whose best is not always kept
    drops = [(g, r) for r in range(60) for g in range(1, 51)
             if best_pop[g, r] < best_pop[g - 1, r]]
    assert drops and all(g % 4 == 0 for g, _ in drops)


def test_seeded_generation_zero_wraps_blockers(robocup):
    """The default scene's direct paths are all blocked: seeded individuals touch
    obstacles, and generation 0 is far better than a random one."""
    from hga_jax.search.settings import PAPER

    seeded = run_many(robocup, PAPER.replace(generations=0, seeding=1.0), seed=0, runs=50,
                      exact=False)
    # generation 0 of the paper's runs (60 of them: the program test_recommended.py and the
    # held-out floors compile)
    random = run_many(robocup, PAPER, seed=0, runs=60, exact=False)
    assert np.all(np.count_nonzero(seeded.labels[:, 1:-1], axis=1) >= 1)
    random_feasible = np.asarray(random.history["best_so_far_violations"])[0] == 0
    assert np.mean(seeded.violations == 0) > 0.9 > np.mean(random_feasible)
    assert np.median(seeded.length[seeded.violations == 0]) < 2.6  # the optimum: 2.2454 m
