"""Baselines: the pure-Python decoder of the DEAP baseline (always tested), the DEAP
version of the paper's GA and OMPL's Dubins planners (each skipped when its package
is missing)."""
import csv
import glob
import importlib.util
import os
import random

import numpy as np
import pytest
from _families import FAMILIES, chromosomes, scenes

from hga_jax.host.config import load_scenario, scenario_from_dict
from hga_jax.model.exact import solve
from hga_jax.model.path import decode64, from_chromosome
from hga_jax.peers.python_decoder import PythonDecoder
from hga_jax.study.scenes import generate


def _load(name):
    spec = importlib.util.spec_from_file_location(name, os.path.join("experiments", "baselines",
                                                                     name + ".py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _agreement(sc, rng, count):
    """Decode ``count`` random chromosomes per collision mode and share of zero labels
    (plus the exact optimum's, when expressible) with both decoders: returns the number
    decoded, the largest length difference (m), the mismatches, feasible and infeasible
    counts."""
    checked, worst, wrong, feasible = 0, 0.0, [], 0
    for collision in ("full", "paper"):
        py = PythonDecoder.from_scenario(sc, collision)
        batches = [chromosomes(rng, sc.n, count, p_zero) for p_zero in (0.2, 0.5, 0.8)]
        opt = solve(sc, collision)
        if opt.feasible and opt.expressible:
            perm, labels = from_chromosome(opt.upper, opt.lower, sc.n)
            batches.append((perm[None], labels[None]))
        for perm, labels in batches:
            d = decode64(sc, perm, labels, collision)
            for p, lab, length, violations in zip(perm, labels, d.length, d.violations):
                ours = py.decode(p.tolist(), lab.tolist())
                checked += 1
                feasible += ours[1] == 0
                worst = max(worst, abs(ours[0] - float(length)))
                if abs(ours[0] - float(length)) > 1e-9 or ours[1] != int(violations):
                    wrong.append((sc.name, collision, p.tolist(), lab.tolist(), ours,
                                  (float(length), int(violations))))
    return checked, worst, wrong, feasible


@pytest.mark.slow  # the DEAP peer's decoder; its fitness test stays in the default lane
@pytest.mark.parametrize("group", ["scenes", "families"])
def test_python_decoder_gives_hga_jax_lengths_and_violations(group):
    """The DEAP baseline's own decoder (plain floats and math) against hga-jax's float64
    decoder: bundled scenarios and generated RoboCup-like scenes; under ``slow`` also the
    degenerate families of the decoder tests (touching circles, goal on a start circle, ...)."""
    if group == "scenes":
        rng = np.random.default_rng(9)
        cases = [(load_scenario(p), 100) for p in sorted(glob.glob("configs/scenarios/*.toml"))]
        cases = [(sc, k) for sc, k in cases if not sc.has_motion]  # the peer plans a snapshot
        cases += [(scenario_from_dict(generate(kind, n, 21, 0, f"{kind}{n}", 1.4)), 40)
                  for kind, n in (("clutter", 25), ("obstructed", 9))]
    else:
        rng = np.random.default_rng(10)
        cases = [(scenario_from_dict(d), 25) for family in FAMILIES for d in scenes(family, 5, 5)]
    total, worst, wrong, feasible = 0, 0.0, [], 0
    for sc, count in cases:
        c, w, bad, f = _agreement(sc, rng, count)
        total, worst, feasible = total + c, max(worst, w), feasible + f
        wrong += bad
    assert wrong == [], wrong[:5]
    assert total > 2500 and worst < 1e-9
    assert 0.05 * total < feasible < 0.95 * total  # both kinds of path are compared


def test_python_decoder_fitness_is_the_papers():
    sc = load_scenario("configs/scenarios/robocup_paper.toml")
    py = PythonDecoder.from_scenario(sc)
    assert py.delta == pytest.approx(sc.delta, rel=1e-15)
    opt = solve(sc)
    perm, labels = from_chromosome(opt.upper, opt.lower, sc.n)
    fit, length, violations = py.fitness(perm.tolist(), labels.tolist())
    assert violations == 0 and length == pytest.approx(2.24543, abs=1e-5)
    assert fit == pytest.approx(10000 / (opt.length + 1), rel=1e-12)
    straight = [0] * (sc.n + 2)  # start CCW, no obstacle, goal CCW
    straight[0] = straight[-1] = -1
    fit, length, violations = py.fitness(list(range(sc.n)), straight)
    assert violations > 0
    assert fit == pytest.approx(10000 / (length + violations * 2 * np.pi * 0.18 + 1), rel=1e-12)
    with pytest.raises(ValueError):
        PythonDecoder.from_scenario(sc, "nearly")


@pytest.fixture(scope="module")
def deap_hga():
    pytest.importorskip("deap")
    return _load("deap_hga")


@pytest.fixture(scope="module")
def deap_ga():
    pytest.importorskip("deap")
    from hga_jax.peers import deap_ga

    return deap_ga


def test_cycle_crossover_by_hand(deap_ga):
    a, b = [0, 1, 2, 3, 4, 5], [1, 2, 0, 4, 5, 3]
    # positions 0, 1, 2 form one cycle (a[0]=0 sits at b's position 2, ...), 3, 4, 5 another
    rng = random.Random(0)
    for _ in range(20):
        c1, c2 = deap_ga.cycle_crossover(a, b, rng)
        assert sorted(c1) == sorted(c2) == a
        assert (c1, c2) in (([0, 1, 2, 4, 5, 3], [1, 2, 0, 3, 4, 5]),
                            ([1, 2, 0, 3, 4, 5], [0, 1, 2, 4, 5, 3]))
    p = list(range(7))
    for seed in range(10):
        q = deap_ga.inversion(p, random.Random(seed))
        assert any(q == p[:lo] + p[lo:hi][::-1] + p[hi:]
                   for lo in range(8) for hi in range(lo + 1, 8))
    labels = deap_ga.redraw([1, 0, -1, 1, -1], 1.0, random.Random(2))
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
        # only changed individuals are evaluated again: at least the first population
        assert 50 <= int(r["evaluations"]) <= 50 * 7
    again = tmp_path / "again.csv"
    assert deap_hga.main(args[:-1] + [str(again)]) == 0
    assert [r["length"] for r in csv.DictReader(again.open())] == [r["length"] for r in rows]
