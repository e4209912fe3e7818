"""``restart_arcs``: in a restart of a run whose best path so far collides, the seeds
also wrap the overlapping neighbours of their colliding arcs
(:func:`hga_jax.search.path_ops.wrap_from_words`' arc rule); a run whose best is clear,
generation 0 and a share of 0 seed as before."""
import jax
import jax.numpy as jnp
import numpy as np
import pytest

from hga_jax.errors import ConfigError
from hga_jax.host.config import load_scenario, scenario_from_dict
from hga_jax.model import circle_ids
from hga_jax.search import ga, path_ops
from hga_jax.search.settings import PAPER, RECOMMENDED
from hga_jax.search.state import blank
from hga_jax.search.variation import _legs, overlapping

# A (obstacle 0, model radius 0.3 m) across the direct path; B (obstacle 1, model
# radius 0.1 m) sits on A's top, their model circles overlapping by 0.05 m: a path over
# A's top has clear legs (they meet A's circle left and right of B), and its arc on A
# runs through B.
ARC = {"name": "arc", "robot": {"radius": 0.05, "min_turn_radius": 0.1},
       "start": {"x": 0.8, "y": 0.5, "heading_deg": 0.0},
       "goal": {"x": 2.2, "y": 0.5, "heading_deg": 0.0},
       "obstacles": [{"x": 1.5, "y": 0.5, "radius": 0.25}, {"x": 1.5, "y": 0.85, "radius": 0.05}]}
P = 64


@pytest.fixture(scope="module")
def seeds():
    """The seeds of ``P`` random words from the direct path, legs only and with the arc
    rule on and off for every chromosome, and the scene's legs."""
    sc = scenario_from_dict(ARC)
    st = RECOMMENDED.for_obstacles(sc.n)
    sa = st.model.search_arrays(sc, np.float32, st.collision, st.uses_legs)
    legs = _legs(sa, st)
    rng = np.random.default_rng(5)
    words = jnp.asarray(rng.integers(0, 2**32, (3 * sc.n, P), dtype=np.uint64).astype(np.uint32))
    perm = jnp.asarray(np.tile(np.arange(sc.n, dtype=np.int32)[:, None], (1, P)))
    labels = np.zeros((sc.n + 2, P), np.int32)
    labels[[0, -1]] = rng.choice([-1, 1], (2, P))
    labels = jnp.asarray(labels)
    overlap = overlapping(sa.centres, sa.model_radii)
    wrap = jax.jit(path_ops.wrap_from_words)
    plain = wrap(words, perm, labels, legs)
    on = wrap(words, perm, labels, legs, False, (overlap, jnp.ones(P, bool)))
    off = wrap(words, perm, labels, legs, False, (overlap, jnp.zeros(P, bool)))
    alone = [jax.jit(path_ops.wrap_from_words)(words[:, p], perm[:, p], labels[:, p], legs,
                                               False, (overlap, jnp.asarray(True)))
             for p in range(4)]
    return legs, overlap, [tuple(np.asarray(x) for x in r) for r in (plain, on, off)], alone


def test_overlapping_pairs():
    sc = scenario_from_dict(ARC)
    sa = sc.arrays(np.float32)
    assert np.asarray(overlapping(sa.centres, sa.model_radii)).tolist() == [[False, True],
                                                                             [True, False]]


def test_a_colliding_arc_gets_its_overlapping_neighbour_after_it(seeds):
    legs, _, ((pp, pl), (op, ol), (fp, fl)), alone = seeds
    assert np.array_equal(pp, fp) and np.array_equal(pl, fl)  # off: the legs-only seeds
    over = (pp[0] == 0) & (pl[1] == 1) & (pl[2] == 0)  # A alone, clockwise: over its top
    under = (pp[0] == 0) & (pl[1] == -1) & (pl[2] == 0)
    assert over.sum() >= 5 and under.sum() >= 5  # both sides among the random words
    arcs = np.asarray(legs.arcs)
    a = circle_ids.obstacle(0, 1)
    for p in np.flatnonzero(over):
        start, goal = pl[0, p], pl[-1, p]
        # the legs-only seed: its arc on A has a violation of its own (B)
        assert arcs[circle_ids.side(start), a, 2 + circle_ids.side(goal)]
        # with the rule: B right after A, turning the same way (clockwise)
        assert op[:, p].tolist() == [0, 1] and ol[:, p].tolist() == [start, 1, 1, goal]
    for p in np.flatnonzero(~over):  # no colliding arc: the legs-only seed
        assert np.array_equal(op[:, p], pp[:, p]) and np.array_equal(ol[:, p], pl[:, p])
    for p, (perm, labels) in enumerate(alone):  # a chromosome alone as in the batch
        assert np.array_equal(perm, op[:, p]) and np.array_equal(labels, ol[:, p])


# seeded restarts every 2 generations on a scene of overlapping model circles
SEEDED = PAPER.replace(seeding=1.0, restart_after=2)


def test_the_rule_only_in_a_restart_whose_best_collides():
    sc = load_scenario("configs/scenarios/overlapping.toml")
    sa = SEEDED.model.search_arrays(sc, np.float32, SEEDED.collision, SEEDED.uses_legs)
    state = ga.compiled_step(ga.run_key(3, 0), blank(sa, SEEDED))  # generation 0
    due = state._replace(generation=jnp.int32(2),
                         best=state.best._replace(generation=jnp.int32(0)))

    def restart(violations, **rates):
        settings = SEEDED.replace(**rates)
        s = due._replace(best=due.best._replace(violations=jnp.int32(violations)),
                         rates=settings.rates(np.float32))
        out = ga.compiled_step(ga.run_key(3, 7), s)
        return np.asarray(out.pop.perm), np.asarray(out.pop.labels)

    before = restart(1)
    # a clear best: the seeds of restart_arcs = 0, bit for bit
    assert all(np.array_equal(a, b) for a, b in zip(restart(0, restart_arcs=1.0), restart(0)))
    # a colliding best: the rule changes some seeds (this scene's arcs collide)
    arcs = restart(1, restart_arcs=1.0)
    assert any(not np.array_equal(a, b) for a, b in zip(arcs, before))


@pytest.mark.parametrize("value", [-0.1, 1.5, float("nan"), "all"])
def test_bad_restart_arcs_names_its_key(value):
    with pytest.raises(ConfigError, match=r"ga\.restart_arcs"):
        PAPER.replace("x.toml", restart_arcs=value)


def test_the_summary_names_the_rule_where_it_applies():
    from hga_jax.host.report import _extras

    phrase = "100.00% of them also wrap the overlapping neighbours of their colliding arcs"
    assert phrase in _extras(RECOMMENDED)
    assert "in such a restart " + phrase in _extras(RECOMMENDED)
    alone = _extras(RECOMMENDED.replace(restart_via=0.0))
    assert "in a restart of a run whose best collides " + phrase in alone
    for other in (PAPER, RECOMMENDED.replace(restart_arcs=0.0),
                  RECOMMENDED.replace(turns="free")):  # free turns: the tight rope's rule only
        assert "colliding arcs" not in _extras(other)
