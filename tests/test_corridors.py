"""The ``corridors`` scene family (held-out scenes for the search): barriers of
overlapping circles across the field, each with a gap or two, seeded, blocked, solvable."""
import numpy as np
import pytest

from hga_jax.errors import ConfigError
from hga_jax.host.config import scenario_from_dict
from hga_jax.model.exact import solve
from hga_jax.study import corridors, load_study
from hga_jax.study.scene_files import blocked
from hga_jax.study.scenes import generate

CASES = [(n, seed, i) for n, seed in ((9, 0), (9, 3), (15, 0), (26, 1)) for i in range(2)]


@pytest.fixture(scope="module")
def pool():
    """8 scenes: 9, 15 and 26 obstacles (one, two and three barriers)."""
    return {c: generate("corridors", c[0], c[1], c[2], f"c{c[0]}_{c[2]}") for c in CASES}


def test_seeded_by_seed_count_and_index(pool):
    assert corridors.generate(9, 0, 1, "c9_1") == pool[(9, 0, 1)]
    assert pool[(9, 0, 0)] != pool[(9, 0, 1)]
    assert pool[(9, 0, 0)]["obstacles"] != pool[(9, 3, 0)]["obstacles"]


def test_every_scene_is_blocked_and_its_optimum_wraps_two(pool):
    for (n, _, _), d in pool.items():
        sc = scenario_from_dict(d)
        assert sc.n == n and blocked(sc)
        opt = solve(sc)
        assert opt.feasible and opt.expressible
        assert len({o for o, _ in opt.touched}) >= 2
        assert 0.05 <= sc.robot_radius <= 0.12 and 0.09 <= sc.min_turn_radius <= 0.25
        assert np.all((sc.radii >= 0.03) & (sc.radii <= 0.15))


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


def test_a_study_takes_the_kind_and_refuses_a_density(tmp_path):
    text = ('name = "s"\nruns = 2\n[[families]]\nname = "co"\nkind = "corridors"\n'
            'obstacles = [9]\nscenes = 1\n[[configs]]\nlabel = "paper"\n')
    (tmp_path / "ok.toml").write_text(text)
    assert load_study(str(tmp_path / "ok.toml")).families[0].kind == "corridors"
    (tmp_path / "bad.toml").write_text(text.replace("scenes = 1", "scenes = 1\ndensity = 1.0"))
    with pytest.raises(ConfigError, match=r"bad\.toml: families\[1\]\.density: not used by "
                                          r"kind corridors"):
        load_study(str(tmp_path / "bad.toml"))
