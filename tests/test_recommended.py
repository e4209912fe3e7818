"""The presets: the bundled GA files are the presets, and the recommended HGA keeps
finding the optimum on small obstructed families, of the studies' generator and of the
held-out clusters generator, at 9 and 15 obstacles (thresholds set from measured rates).
"""
import dataclasses
import functools
import tomllib
from pathlib import Path

import numpy as np
import pytest

from hga_jax.host.config import scenario_from_dict
from hga_jax.running.runner import run_many
from hga_jax.search.settings import PAPER, PRESETS, RECOMMENDED, GASettings, preset
from hga_jax.errors import ConfigError
from hga_jax.study import clusters
from hga_jax.study.scenes import generate

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("name", ["paper", "recommended"])
def test_bundled_ga_files_are_the_presets(name):
    path = ROOT / "configs" / "ga" / f"{name}.toml"
    table = tomllib.loads(path.read_text())
    assert GASettings.from_mapping(table, str(path), prefix="") == PRESETS[name]


def test_presets_and_their_budget():
    assert preset("paper") == PAPER == GASettings()
    assert preset("recommended") == RECOMMENDED
    # up to 9 obstacles the same budget: 50 x (50 + 1) = 2,550 decoded chromosomes per run
    for st in (PAPER, RECOMMENDED):
        st = st.for_obstacles(9)
        assert st.population * (st.generations + 1) == 2550
    # beyond, the recommended budget grows within 10,000 (15), 25,000 (25) and 50,000 (40)
    assert PAPER.for_obstacles(40) == PAPER
    grown = [RECOMMENDED.for_obstacles(n) for n in (15, 25, 40)]
    assert [s.population * (s.generations + 1) for s in grown] == [9750, 21750, 39750]
    with pytest.raises(ConfigError, match="preset: must be one of recommended, paper"):
        preset("fast")
    differs = {f.name for f in dataclasses.fields(GASettings)
               if getattr(PAPER, f.name) != getattr(RECOMMENDED, f.name)}
    assert differs == {"selection", "elites", "path_mutation", "pm_path", "seeding",
                       "seeding_via", "restart_via", "restart_arcs", "wrap_clearer", "guided_arcs", "restart_after", "islands",
                       "migrate_every",
                       "penalty_weight",
                       "generations_per_obstacle", "reversing_budget", "pairs_from",
                       "ends_of_best", "straight_of_best", "tight_of_best"}


# Four obstructed 9-obstacle scenes (the studies' generator, a seed no study or tuning
# used). Measured with 2,000 runs per scene (seed 0): the recommended HGA hit the
# optimum in 8,000 of 8,000 runs; the paper's in 1.9%, 6.4%, 9.0% and 12.5%.
# (That was hga-jax 0.3's recommended HGA, with flips; the 0.4 one, guided moves, hit
# in 2,000 of 2,000 runs, 500 per scene.) Thresholds: 98% for the recommended (4 misses
# allowed in 240 runs), 25% for the paper.
@functools.cache
def _scenes():
    """Made on first use (not while the file is collected, in every worker)."""
    return [scenario_from_dict(generate("obstructed", 9, 31, i, f"obstructed9_{i}"), f"scene {i}")
            for i in range(4)]


@pytest.mark.parametrize("name, low, high", [  # the held-out tests below cover the default lane
    pytest.param("recommended", 0.98, 1.0, marks=pytest.mark.slow), ("paper", 0.0, 0.25)])
def test_hit_rate_on_a_small_obstructed_family(name, low, high):
    hits, evaluations = [], 0
    for sc in _scenes():
        res = run_many(sc, PRESETS[name], seed=0, runs=60, preset=name)
        hits.append(res.hit)
        evaluations = res.evaluations
        assert res.preset == name and res.to_dict()["preset"] == name
    rate = float(np.mean(np.concatenate(hits)))
    assert low <= rate <= high, rate
    assert evaluations == 60 * 2550  # every decoded chromosome counted, no more


# Held-out families, seeds no tuning used (measured with seed 0 before the thresholds
# were set; the tests run the first runs of those):
# - clusters, 9 obstacles, seed 77, scenes 0-3, 1,000 runs each: recommended 100%, 100%,
#   97.5% and 0.1% (scene 3's only feasible path is a 6.6 m loop round every clump, which
#   the search almost never finds: it ends on the 2.1 m path through the middle clump);
#   paper 5.7%, 7.3%, 29.7%, 0%.
# - obstructed (the studies' generator), 15 obstacles, seed 79, scenes 0-1, 500 runs
#   each: recommended 100%, 100%; paper 2.2%, 1.6%.
# - clusters, 15 obstacles, seed 78, scenes 0-1, 500 runs each: recommended 100%, 100%;
#   paper 9.2%, 2.2%.
@functools.cache
def _held_out(family):
    """A family's scenes and runs per scene, made on first use."""
    return {
        "clusters9": lambda: ([clusters.generate(9, 77, i, f"clusters9_{i}") for i in range(4)], 60),
        "obstructed15": lambda: ([generate("obstructed", 15, 79, i, f"obstructed15_{i}")
                                  for i in range(2)], 25),
        "clusters15": lambda: ([clusters.generate(15, 78, i, f"clusters15_{i}") for i in range(2)], 25),
    }[family]()


@pytest.mark.parametrize("family, name, low, high", [  # quality checks, on demand (-m slow);
    # test_hit_rate_on_a_small_obstructed_family stays in the default lane
    pytest.param("clusters9", "recommended", 0.70, 1.0, marks=pytest.mark.slow),
    ("clusters9", "paper", 0.0, 0.25),
    pytest.param("obstructed15", "recommended", 0.95, 1.0, marks=pytest.mark.slow),
    pytest.param("obstructed15", "paper", 0.0, 0.15, marks=pytest.mark.slow),
    pytest.param("clusters15", "recommended", 0.95, 1.0, marks=pytest.mark.slow)])
def test_hit_rate_on_held_out_families(family, name, low, high):
    dicts, runs = _held_out(family)
    hits, feasible = [], []
    for d in dicts:
        res = run_many(scenario_from_dict(d, d["name"]), PRESETS[name], seed=0, runs=runs,
                       preset=name)
        hits.append(res.hit)
        feasible.append(res.feasible)
        assert res.evaluations == runs * PRESETS[name].for_obstacles(len(d["obstacles"])
                                                                     ).population * (
            res.settings.generations + 1)
    rate = float(np.mean(np.concatenate(hits)))
    assert low <= rate <= high, rate
    if name == "recommended" and family != "clusters9":
        assert np.all(np.concatenate(feasible))  # never a colliding answer here
