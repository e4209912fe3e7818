"""Optional baselines: the DEAP version of the paper's GA and OMPL's Dubins planners
(each skipped when its package is missing)."""
import csv
import importlib.util
import os
import random

import pytest

from hga_jax.config import load_scenario
from hga_jax.exact import solve


def _load(name):
    spec = importlib.util.spec_from_file_location(name, os.path.join("experiments", "baselines",
                                                                     name + ".py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def deap_hga():
    pytest.importorskip("deap")
    return _load("deap_hga")


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


def test_ompl_paths_are_checked_with_the_models_clearance():
    pytest.importorskip("ompl")
    import numpy as np

    om = _load("ompl_dubins")
    sc = load_scenario("configs/scenarios/robocup_paper.toml")
    c, big = sc.centres[1], sc.model_radii[1]
    inside = np.array([[c[0] + 0.5 * big, c[1]], [0.3, 0.6]])
    assert om.dense_violations(sc, inside) == 1
    assert om.dense_violations(sc, np.array([[c[0] + big + 1e-6, c[1]]])) == 0
    assert om.dense_violations(sc, np.array([[0.05, 1.0]])) == 1  # off the kept field
    r = om.plan(sc, "BITstar", 0.3, 0)
    a, b = np.array(sc.start[:2]), np.array(sc.goal[:2])
    assert r["solved"] and r["length"] > np.hypot(*(b - a))
    assert r["seconds"] == pytest.approx(0.3, abs=0.5)
