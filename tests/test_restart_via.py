"""``restart_via``: a restart of a run whose best path so far collides seeds that share
of its individuals via a random obstacle too; a run whose best is clear, and generation
0, seed as before."""
import jax.numpy as jnp
import numpy as np
import pytest

from hga_jax.errors import ConfigError
from hga_jax.host.config import load_scenario
from hga_jax.search import ga
from hga_jax.search.settings import PAPER
from hga_jax.search.state import blank

# seeded restarts every 2 generations; no seed via an obstacle unless a rate says so
SEEDED = PAPER.replace(seeding=1.0, restart_after=2)


@pytest.fixture(scope="module")
def due():
    """A run's state after generation 0 of the bundled scene, at generation 2 with its
    best unchanged since 0: the next step restarts it."""
    sc = load_scenario("configs/scenarios/robocup_paper.toml")
    sa = SEEDED.model.search_arrays(sc, np.float32, SEEDED.collision, SEEDED.uses_legs)
    state = ga.compiled_step(ga.run_key(3, 0), blank(sa, SEEDED))  # generation 0
    best = state.best._replace(generation=jnp.int32(0))
    return state._replace(generation=jnp.int32(2), best=best)


def _restart(state, violations, **rates):
    """The population the restart makes, with the best's violation count set and these
    rates (data of the one compiled step)."""
    settings = SEEDED.replace(**rates)
    best = state.best._replace(violations=jnp.int32(violations))
    state = state._replace(best=best, rates=settings.rates(np.float32))
    out = ga.compiled_step(ga.run_key(3, 7), state)
    assert int(out.generation) == 3
    return np.asarray(out.pop.perm), np.asarray(out.pop.labels)


def test_a_colliding_best_restarts_with_seeds_via_an_obstacle(due):
    via_all = _restart(due, 0, seeding_via=1.0)  # every seed via an obstacle, as a rate
    direct = _restart(due, 0)
    # the run's best collides: restart_via takes its seeds via an obstacle, from the same words
    assert all(np.array_equal(a, b) for a, b in zip(_restart(due, 1, restart_via=1.0), via_all))
    # a clear best, or restart_via = 0: the seeds of generation 0's rule
    for got in (_restart(due, 0, restart_via=1.0), _restart(due, 1)):
        assert all(np.array_equal(a, b) for a, b in zip(got, direct))
    assert not np.array_equal(via_all[1], direct[1])
    # shares: the seeds of both spreads go via an obstacle (the same spread twice: those)
    half = _restart(due, 0, seeding_via=0.5)
    assert all(np.array_equal(a, b) for a, b in zip(
        _restart(due, 1, seeding_via=0.5, restart_via=0.5), half))
    assert all(np.array_equal(a, b) for a, b in zip(_restart(due, 1, seeding_via=0.5), half))
    assert all(np.array_equal(a, b) for a, b in zip(
        _restart(due, 1, seeding_via=0.5, restart_via=1.0), via_all))


@pytest.mark.parametrize("value", [-0.1, 1.5, float("nan"), "all"])
def test_bad_restart_via_names_its_key(value):
    with pytest.raises(ConfigError, match=r"ga\.restart_via"):
        PAPER.replace("x.toml", restart_via=value)
