"""The turn table (hga_jax.model.turns) and the fitness's lookups against the leg-by-leg decoder."""
from __future__ import annotations

import math

import jax
import numpy as np
import pytest

from hga_jax import scenario_from_dict
from hga_jax.model import turns
from hga_jax.host.config import load_scenario
from hga_jax.model.path import decode64
from hga_jax.model.fitness import evaluate, looked_up
from hga_jax.study.scenes import generate

from _families import chromosomes, scenes

BUNDLED = ["robocup_paper", "cluttered", "open_field", "overlapping"]


def _decoded64(sc, perm, labels, collision):
    # The float64 decoder every reported length comes from, compiled once per scene size.
    d = decode64(sc, perm, labels, collision)
    return np.asarray(d.length), np.asarray(d.violations)


def _looked_up(sc, perm, labels, collision, dtype):
    with jax.enable_x64(dtype == np.float64):
        sa = sc.search_arrays(dtype, collision)
        table = sa.turns_full if collision == "full" else sa.turns_paper
        assert table is not None
        e = jax.jit(lambda s, p, l: evaluate(s, p, l, collision))(sa, perm, labels)
        return np.asarray(e.length, np.float64), np.asarray(e.violations)


def _check(sc, collision, count=3000, seed=0, dtypes=(np.float64, np.float32)):
    rng = np.random.default_rng(seed)
    perm, labels = chromosomes(rng, sc.n, count, p_zero=0.3)
    length, viol = _decoded64(sc, perm, labels, collision)
    for dtype in dtypes:
        tol = 1e-9 if dtype == np.float64 else 2e-6
        got_len, got_viol = _looked_up(sc, perm, labels, collision, dtype)
        assert np.array_equal(got_viol, viol), (sc.name, collision, dtype)
        assert np.max(np.abs(got_len - length) / np.maximum(length, 1.0)) < tol, (sc.name, dtype)
    return viol


@pytest.mark.parametrize("collision", ["full", "paper"])
@pytest.mark.parametrize("name", BUNDLED)
def test_lookups_equal_the_decoder_on_bundled_scenes(name, collision):
    sc = load_scenario(f"configs/scenarios/{name}.toml")
    viol = _check(sc, collision)
    assert sc.n < 3 or viol.max() > viol.min()  # the counts vary: the comparison has teeth
    if name == "robocup_paper":
        assert 0 < np.mean(viol == 0) < 1  # feasible and colliding paths among them


@pytest.mark.parametrize("kind,n", [("obstructed", 9), ("clutter", 40)])
def test_lookups_equal_the_decoder_on_generated_scenes(kind, n):
    sc = scenario_from_dict(generate(kind, n, 7, 0, f"{kind}{n}", density=1.4))
    _check(sc, "full", count=2000, dtypes=(np.float64,))


@pytest.mark.parametrize("family", [
    "degenerate", *(pytest.param(f, marks=pytest.mark.slow) for f in ("grid", "overlapping", "random"))])
def test_lookups_equal_the_decoder_on_degenerate_families(family):
    """Touching circles, half-circle arcs, segment ends on circles: the table judges
    every turn with the decoder's geometry, so the counts agree exactly. Scenes whose
    circles share a centre along a possible path get no table (and decode instead)."""
    used = 0
    for i, d in enumerate(scenes(family, 3, 4)):
        sc = scenario_from_dict(d)
        sa = sc.search_arrays(np.float32, "full")
        s64 = sc.arrays(np.float64)
        if not turns.usable(s64.tangents):
            assert sa.turns_full is None
            continue
        used += 1
        _check(sc, ("full", "paper")[i % 2], count=1500, seed=i, dtypes=(np.float64,))
    assert used >= 2


def test_coincident_centres_give_no_table_and_the_decoder_is_used():
    # The goal lies on the start's CW turning circle, heading along it: start CW and
    # goal CW are one circle (rho 0.2 around (0, -0.2)).
    sc = scenario_from_dict({
        "name": "goal on the start circle", "robot": {"radius": 0.05, "min_turn_radius": 0.2},
        "start": {"x": 0.0, "y": 0.0, "heading_deg": 0.0},
        "goal": {"x": 0.2, "y": -0.2, "heading_deg": -90.0},
        "obstacles": [{"x": 2.0, "y": 2.0, "radius": 0.05}]})
    assert not turns.usable(sc.arrays(np.float64).tangents)
    sa = sc.search_arrays(np.float32, "full")
    assert sa.turns_full is None
    perm, labels = np.zeros((1, 1), np.int32), np.array([[1, 0, 1]], np.int32)
    e = jax.jit(evaluate)(sa, perm, labels)  # compiled like the search's: one program, not op by op
    assert float(e.length[0]) == pytest.approx(math.pi / 2 * 0.2, abs=1e-5)  # a quarter turn
    assert int(e.violations[0]) == 0


def test_a_hand_computed_path():
    """Start (0, 0) heading east, goal (2, 0) heading east, one robot of model radius
    0.3 at (1, 0): CW start circle around (0, -0.3), CCW around the obstacle (radius 0.3,
    the model circle), CW goal circle around (2, -0.3). Equal radii, so the inner
    tangents are at 45 degrees through the midpoints between the centres."""
    rho = 0.3
    sc = scenario_from_dict({
        "name": "hand", "robot": {"radius": 0.1, "min_turn_radius": rho},
        "start": {"x": 0.0, "y": 0.0, "heading_deg": 0.0},
        "goal": {"x": 2.0, "y": 0.0, "heading_deg": 0.0},
        "obstacles": [{"x": 1.0, "y": 0.0, "radius": 0.2}]})
    # Start circle (0, -0.3) CW to obstacle (1, 0) CCW: an inner tangent; centre
    # distance d = sqrt(1 + 0.09), tangent length sqrt(d^2 - (2 rho)^2).
    d = math.hypot(1.0, 0.3)
    tangent = math.sqrt(d * d - (2 * rho) ** 2)
    # The first tangent is the centre line (at atan(0.3) above east) turned clockwise
    # by asin(2 rho / d): the path turns right by the difference, passes under the
    # obstacle turning left twice as far, and by symmetry turns right into the goal.
    turn = math.asin(2 * rho / d) - math.atan2(0.3, 1.0)
    arcs = rho * (turn + 2 * turn + turn)  # start arc, arc around the obstacle, goal arc
    want = 2 * tangent + arcs
    perm, labels = np.zeros((1, 1), np.int32), np.array([[1, -1, 1]], np.int32)
    length, viol = _looked_up(sc, perm, labels, "full", np.float64)
    assert viol[0] == 0
    assert length[0] == pytest.approx(want, abs=1e-12)
    with jax.enable_x64(True):
        sa = sc.search_arrays(np.float64, "full")
        lk = looked_up(sa.turns_full, sa.tangents.circles.shape[0], perm, labels)
        assert float(lk[0][0]) == pytest.approx(want, abs=1e-12)


def test_table_size_and_limit():
    assert turns.entries(9) == 23 * 22 * 23
    assert turns.fits(100) and not turns.fits(130)
    sc = load_scenario("configs/scenarios/robocup_paper.toml")
    assert sc.search_arrays(np.float32, "full").turns_full.shape == (turns.entries(9), 2)
