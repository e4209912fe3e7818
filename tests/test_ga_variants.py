"""GA variants used by the studies: labels bound to obstacles, penalty weights."""
import jax.numpy as jnp
import numpy as np
import pytest

from hga_jax.host.config import load_scenario
from hga_jax.errors import ConfigError
from hga_jax.model.fitness import fitness_of
from hga_jax.search.ga import positional
from hga_jax.model.path import decode64
from hga_jax.running.runner import run_many
from hga_jax.search.settings import GASettings

ROBOCUP = "configs/scenarios/robocup_paper.toml"


def test_obstacle_bound_labels_follow_their_obstacle():
    s = GASettings(label_binding="obstacle")
    perm = jnp.array([[2, 0, 1], [0, 1, 2]])
    labels = jnp.array([[1, 10, 11, 12, -1], [-1, 10, 11, 12, 1]])  # obstacle 0 has 10, ...
    assert positional(perm, labels, s).tolist() == [[1, 12, 10, 11, -1], [-1, 10, 11, 12, 1]]
    assert positional(perm, labels, GASettings()) is labels  # the paper: positional already


def test_obstacle_binding_reports_positional_chromosomes():
    sc = load_scenario(ROBOCUP)
    # 40 runs of 30 generations, seed 0: the paper's program is shared with the study tests
    res = run_many(sc, GASettings(label_binding="obstacle", generations=30), seed=0, runs=40)
    # The reported chromosome, decoded positionally in float64, is the path the search scored.
    h = res.history
    assert np.array_equal(res.violations, h["best_so_far_violations"][-1])
    assert np.allclose(res.length, h["best_so_far_length"][-1], rtol=1e-5)
    paper = run_many(sc, GASettings(generations=30), seed=0, runs=40)
    assert not np.array_equal(paper.length, res.length)


def test_penalty_weight_scales_the_penalty_in_the_search():
    sc = load_scenario(ROBOCUP)
    w = 0.25
    res = run_many(sc, GASettings(penalty_weight=w, generations=10), seed=1, runs=16,
                   exact=False)
    h = res.history
    want = fitness_of(h["best_so_far_length"].astype(np.float64),
                      h["best_so_far_violations"], w * sc.delta)
    assert np.allclose(h["best_so_far_fitness"], want, rtol=1e-5)
    assert np.any(h["best_so_far_violations"] > 0)  # the weight mattered somewhere
    d = decode64(sc, res.perm, res.labels)
    assert np.array_equal(d.violations, res.violations)  # reported figures are unweighted


@pytest.mark.parametrize("bad", [0.0, -1.0, float("inf"), True])
def test_penalty_weight_must_be_positive_and_finite(bad):
    with pytest.raises(ConfigError, match="penalty_weight"):
        GASettings.from_mapping({"penalty_weight": bad}, "x.toml")


def test_label_binding_is_checked():
    with pytest.raises(ConfigError, match="ga.label_binding: must be one of position, obstacle"):
        GASettings.from_mapping({"label_binding": "gene"}, "x.toml")
