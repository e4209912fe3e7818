"""The XLA options the GA's search is compiled with on small scenes
(hga_jax.jax_compat.SEARCH_COMPILER_OPTIONS, chosen by the runner): which programs
get them, and that their runs are the same bits as the default programs'."""
import numpy as np
import pytest

import hga_jax as hg
from hga_jax import jax_compat
from hga_jax.host.config import load_scenario, scenario_from_dict
from hga_jax.running import runner
from hga_jax.search.settings import preset
from hga_jax.study.scenes import generate

ROBOCUP = "configs/scenarios/robocup_paper.toml"
JOBS = {"recommended": 60, "paper": 60}  # test_lane_programs.py's (and the floors') programs


def _options(sc, name, **changes):
    st = preset(name).replace(**changes).for_car(sc.car).for_obstacles(sc.n)
    sa = st.model.search_arrays(sc, np.float32, st.collision, st.uses_legs)
    return runner._compiler_options(st, sa), sa, st


def test_small_forward_scenes_with_a_turn_table_get_the_options():
    sc = load_scenario(ROBOCUP)
    assert _options(sc, "recommended")[0] == jax_compat.SEARCH_COMPILER_OPTIONS
    assert _options(sc, "paper", turns="free")[0] == jax_compat.SEARCH_COMPILER_OPTIONS
    # a reversing car's lengths, and from 15 obstacles on: XLA's defaults
    assert _options(sc, "recommended", turns="reeds-shepp")[0] == {}
    big = scenario_from_dict(generate("scattered", 15, 131, 0, "s15", None))
    assert _options(big, "paper")[0] == {}
    # a fitness that decodes leg by leg (no turn table): the defaults
    opts, sa, st = _options(sc, "paper")
    assert runner._compiler_options(st, sa._replace(turns_full=None)) == {}


def test_a_users_operator_keeps_the_defaults(registries):
    from hga_jax.search import registry
    registry.register("perm_mutation", "my_swap", registry.get("perm_mutation", "exchange"))
    sc = load_scenario(ROBOCUP)
    assert _options(sc, "paper", perm_mutation="my_swap")[0] == {}


@pytest.mark.parametrize("name", sorted(JOBS))
def test_runs_with_the_options_are_the_default_programs_runs(name, monkeypatch):
    sc = load_scenario(ROBOCUP)
    with_options = hg.run_many(sc, name, seed=3, runs=JOBS[name], exact=False)
    # XLA's default, the fusion emitters, asked for by name: this lane builds every
    # program with the loop emitters (conftest.py), and a program's option overrides it
    monkeypatch.setattr(jax_compat, "SEARCH_COMPILER_OPTIONS", {"xla_cpu_use_fusion_emitters": True})
    default = hg.run_many(sc, name, seed=3, runs=JOBS[name], exact=False)
    for field in ("perm", "labels", "generation", "violations", "length"):
        assert np.array_equal(getattr(with_options, field), getattr(default, field)), field
    for key, h in default.history.items():  # every generation's records, bit for bit
        if key == "mean_fitness":  # a record the search reads nothing of: a float sum whose
            continue  # order this lane's level-0 programs may change (the default level's not)
        assert np.array_equal(np.asarray(with_options.history[key]).view(np.uint8),
                              np.asarray(h).view(np.uint8)), key
