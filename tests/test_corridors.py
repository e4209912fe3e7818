"""The ``corridors`` scene family (held-out scenes for the search): barriers of
overlapping circles across the field, each with a gap or two (seeded, blocked and
solvable: tests/test_held_out_generators.py)."""
import numpy as np
import pytest
from test_held_out_generators import pool as held_out_pool

from hga_jax.host.config import scenario_from_dict
from hga_jax.study import corridors

def test_robots_and_obstacles_vary_within_their_ranges():
    scs = [scenario_from_dict(d) for d in held_out_pool("corridors").values()]
    for sc in scs:
        assert 0.05 <= sc.robot_radius <= 0.12 and 0.09 <= sc.min_turn_radius <= 0.25
        assert np.all((sc.radii >= 0.03) & (sc.radii <= 0.15))
    assert any(np.ptp(sc.model_radii) > 1e-6 for sc in scs)


@pytest.mark.parametrize("n", [9, 15, 26, 40])
def test_barriers_are_closed_but_at_their_gaps_and_reach_past_the_edges(n):
    rng = np.random.default_rng([7, n])
    pairs = zigzags = 0
    for _ in range(20):
        r, rho = rng.uniform(*corridors.ROBOT_RADIUS), rng.uniform(*corridors.TURN_RADIUS)
        w, h, centres, radii, model, held, middles, rooms = corridors._place(rng, n, r, rho)
        walls = 1 + n // 12
        assert held >= 2 * walls and 0.55 * n <= held <= n
        np.testing.assert_allclose(model, np.maximum(rho, radii + r))
        assert np.isclose(rooms.sum(), w) and len(middles) == walls + 1
        counts = np.diff(np.linspace(0, held, walls + 1).round().astype(int))
        lows = []
        for f, c in zip(np.concatenate([[0], np.cumsum(counts)[:-1]]), counts):
            xy, m = centres[f:f + c], model[f:f + c]
            clear = np.hypot(*np.diff(xy, axis=0).T) - (m[:-1] + m[1:])  # < 0: overlapping
            gaps = np.flatnonzero(clear > 0)
            assert 1 <= gaps.size <= 2 and np.all(clear[gaps] >= 0.03 - 1e-9)
            assert xy[0, 1] - m[0] < 0 and xy[-1, 1] + m[-1] > h  # past both edges
            lows.append(xy[gaps[0]:gaps[0] + 2, 1].mean() < h / 2 if gaps.size == 1 else None)
        one = [(a, b) for a, b in zip(lows, lows[1:]) if a is not None and b is not None]
        pairs, zigzags = pairs + len(one), zigzags + sum(a != b for a, b in one)
    if n > 12:  # several barriers: one-gap neighbours' gaps mostly alternate between halves
        assert pairs >= 5 and zigzags >= 0.6 * pairs
