"""``reversing_budget``: a car that also drives backward makes that many times the
generations of the forward car's rule; the forward car, the paper's preset and the
compiled programs are as they were."""
import dataclasses

import numpy as np
import pytest

from hga_jax.errors import ConfigError
from hga_jax.host.config import load_scenario
from hga_jax.running.runner import run_many
from hga_jax.search.settings import PAPER, RECOMMENDED


@pytest.mark.parametrize("n", [0, 5, 9, 15, 25, 40])
def test_the_reversing_car_makes_three_times_the_forward_cars_generations(n):
    forward = RECOMMENDED.for_car("dubins").for_obstacles(n)
    reversing = RECOMMENDED.for_car("reeds-shepp").for_obstacles(n)
    assert forward.generations == 50 + 24 * max(0, n - 9)
    assert reversing.generations == 3 * forward.generations
    assert reversing.for_obstacles(n) == reversing  # resolved: again changes nothing
    assert (reversing.generations_per_obstacle, reversing.reversing_budget) == (0, 1)
    # resolved for the forward car first, the factor is kept and applies with the car
    assert forward.reversing_budget == 3
    assert forward.for_car("reeds-shepp").for_obstacles(n) == reversing
    # the paper's preset: 50 generations for either car
    assert PAPER.for_car("reeds-shepp").for_obstacles(n).generations == 50


def test_the_rule_is_recorded_as_it_was_applied():
    rs = RECOMMENDED.for_car("reeds-shepp")
    assert rs.budget(25) == {
        "rule": "generations = 3 * (50 + 24 * max(0, n - 9)) (a car that reverses)",
        "obstacles": 25, "generations": 1302, "evaluations_per_run": 50 * 1303}
    fixed = PAPER.replace(reversing_budget=2).for_car("reeds-shepp")
    assert fixed.budget(9)["rule"] == "generations = 2 * 50 (a car that reverses)"
    assert RECOMMENDED.for_car("dubins").budget(9)["rule"] == "generations = 50 + 24 * max(0, n - 9)"
    assert PAPER.for_car("reeds-shepp").budget(9) is None


def test_the_factor_is_no_part_of_a_compiled_program():
    rs = RECOMMENDED.for_car("reeds-shepp")
    assert rs.structure() == rs.replace(reversing_budget=1).structure()


def test_a_reversing_run_makes_and_records_the_generations():
    sc = dataclasses.replace(load_scenario("configs/scenarios/robocup_paper.toml"),
                             car="reeds-shepp")
    res = run_many(sc, PAPER.replace(generations=2, reversing_budget=3), seed=0, runs=2,
                   exact=False)
    assert np.asarray(res.history["best_fitness"]).shape == (7, 2)  # 3 x 2 generations + 1
    assert res.evaluations == 2 * 50 * 7
    assert res.budget["rule"] == "generations = 3 * 2 (a car that reverses)"


@pytest.mark.parametrize("value", [0, -1, 2.5, "x", True])
def test_bad_reversing_budgets_name_their_key(value):
    with pytest.raises(ConfigError, match=r"ga\.reversing_budget"):
        PAPER.replace("x.toml", reversing_budget=value)
