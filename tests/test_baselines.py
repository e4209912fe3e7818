"""The DEAP version of the paper's GA (an optional baseline; skipped without deap)."""
import csv
import importlib.util
import os
import random

import pytest

pytest.importorskip("deap")

from hga_jax.config import load_scenario  # noqa: E402
from hga_jax.exact import solve  # noqa: E402


@pytest.fixture(scope="module")
def deap_hga():
    path = os.path.join("experiments", "baselines", "deap_hga.py")
    spec = importlib.util.spec_from_file_location("deap_hga", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_cycle_crossover_by_hand(deap_hga):
    a, b = [0, 1, 2, 3, 4, 5], [1, 2, 0, 4, 5, 3]
    # positions 0, 1, 2 form one cycle (a[0]=0 sits at b's position 2, ...), 3, 4, 5 another
    rng = random.Random(0)
    for _ in range(20):
        c1, c2 = deap_hga.cycle_crossover(a, b, rng)
        assert sorted(c1) == sorted(c2) == a
        assert (c1, c2) in (([0, 1, 2, 4, 5, 3], [1, 2, 0, 3, 4, 5]),
                            ([1, 2, 0, 3, 4, 5], [0, 1, 2, 4, 5, 3]))
    p = list(range(7))
    for seed in range(10):
        q = deap_hga.inversion(p, random.Random(seed))
        assert any(q == p[:lo] + p[lo:hi][::-1] + p[hi:]
                   for lo in range(8) for hi in range(lo + 1, 8))
    labels = deap_hga.redraw([1, 0, -1, 1, -1], 1.0, random.Random(2))
    assert labels[0] == -1 and labels[-1] == 1  # ends flip
    assert all(new != old for new, old in zip(labels, [1, 0, -1, 1, -1]))


def test_deap_runs_are_seeded_and_measured_against_the_optimum(deap_hga, tmp_path):
    out = tmp_path / "deap.csv"
    args = ["configs/scenarios/robocup_paper.toml", "--runs", "3", "--generations", "6",
            "--out", str(out)]
    assert deap_hga.main(args) == 0
    rows = list(csv.DictReader(out.open()))
    opt = solve(load_scenario("configs/scenarios/robocup_paper.toml")).length
    for r in rows:
        if r["feasible"] == "True":
            assert float(r["gap"]) == pytest.approx(float(r["length"]) / opt - 1)
            assert float(r["length"]) >= opt * (1 - 1e-9)
        assert 0 <= int(r["generation"]) <= 6
    again = tmp_path / "again.csv"
    assert deap_hga.main(args[:-1] + [str(again)]) == 0
    assert [r["length"] for r in csv.DictReader(again.open())] == [r["length"] for r in rows]
