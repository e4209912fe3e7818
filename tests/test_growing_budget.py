"""A budget that grows with the scene (GASettings.generations_per_obstacle): the
generation count it gives, its checks, and what the runner records."""
import numpy as np
import pytest

from hga_jax.errors import ConfigError
from hga_jax.host.config import load_scenario
from hga_jax.running.runner import run_many
from hga_jax.search.settings import PAPER, RECOMMENDED, GASettings


def test_generations_grow_by_the_rule_beyond_nine_obstacles():
    s = GASettings(generations=50, generations_per_obstacle=24)
    assert [s.for_obstacles(n).generations for n in (0, 9, 10, 15, 25, 40)] == [
        50, 50, 74, 194, 434, 794]
    resolved = s.for_obstacles(25)
    assert resolved.generations_per_obstacle == 0
    assert resolved.for_obstacles(25) == resolved  # resolving twice changes nothing
    assert s.budget(25) == {"rule": "generations = 50 + 24 * max(0, n - 9)", "obstacles": 25,
                            "generations": 434, "evaluations_per_run": 50 * 435}
    assert PAPER.for_obstacles(40) is PAPER and PAPER.budget(40) is None


def test_the_recommended_budgets_stay_within_the_evaluation_targets():
    evals = {n: RECOMMENDED.budget(n)["evaluations_per_run"] for n in (15, 25, 40)}
    assert evals == {15: 9750, 25: 21750, 40: 39750}
    assert RECOMMENDED.for_obstacles(9).generations == 50  # the paper's budget up to 9


@pytest.mark.parametrize("value", [-1, 1.5, True])
def test_a_bad_rule_is_refused_naming_the_key(value):
    with pytest.raises(ConfigError, match="ga.generations_per_obstacle"):
        GASettings.from_mapping({"generations_per_obstacle": value}, "s.toml")


def test_the_runner_applies_the_rule_and_records_it():
    sc = load_scenario("configs/scenarios/cluttered.toml")  # 28 obstacles
    grow = GASettings(population=6, generations=2, generations_per_obstacle=1)
    res = run_many(sc, grow, seed=4, runs=3, exact=False)
    assert res.settings.generations == 2 + 19 and res.settings.generations_per_obstacle == 0
    assert res.history["best_fitness"].shape == (22, 3)
    assert res.evaluations == 3 * 6 * 22
    assert res.budget == grow.budget(28)
    assert res.to_dict()["budget"]["generations"] == 21
    fixed = run_many(sc, GASettings(population=6, generations=21), seed=4, runs=3, exact=False)
    assert np.array_equal(res.length, fixed.length)  # the rule only sets the count
    assert "budget" not in fixed.to_dict()
