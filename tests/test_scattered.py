"""The ``scattered`` scene family (held-out scenes for the search): seeded, blocked,
solvable, walls in about half of the scenes, poses that may hug a wall."""
import numpy as np
import pytest

from hga_jax.errors import ConfigError
from hga_jax.host.config import scenario_from_dict
from hga_jax.model.exact import solve
from hga_jax.study import load_study, scattered
from hga_jax.study.scene_files import blocked
from hga_jax.study.scenes import generate

CASES = [(n, seed, i) for n in (6, 12) for seed in (0, 5) for i in range(6)]


@pytest.fixture(scope="module")
def pool():
    """24 scenes: n in (6, 12), two seeds, six each."""
    return {c: generate("scattered", c[0], c[1], c[2], f"s{c[0]}_{c[2]}") for c in CASES}


def test_seeded_by_seed_count_and_index(pool):
    assert scattered.generate(6, 0, 1, "s6_1") == pool[(6, 0, 1)]
    assert pool[(6, 0, 0)] != pool[(6, 0, 1)]
    assert pool[(6, 0, 0)]["obstacles"] != pool[(6, 5, 0)]["obstacles"]


def test_every_scene_is_blocked_and_its_optimum_wraps_two(pool):
    for (n, _, _), d in pool.items():
        sc = scenario_from_dict(d)
        assert sc.n == n and blocked(sc)
        opt = solve(sc)
        assert opt.feasible and opt.expressible
        assert len({o for o, _ in opt.touched}) >= 2


def test_robots_obstacles_fields_and_walls_vary(pool):
    scs = [scenario_from_dict(d) for d in pool.values()]
    for sc in scs:
        assert 0.05 <= sc.robot_radius <= 0.12 and 0.09 <= sc.min_turn_radius <= 0.25
        assert np.all((sc.radii >= 0.03) & (sc.radii <= 0.20))
        box = sc.field
        for x, y, _ in (sc.start, sc.goal):  # inside, at least the robot's radius from the edges
            assert box.xmin + sc.robot_radius <= x <= box.xmax - sc.robot_radius
            assert box.ymin + sc.robot_radius <= y <= box.ymax - sc.robot_radius
        assert np.all(sc.centres >= 0.1 - 1e-9)
        assert np.all(sc.centres <= np.array([box.xmax, box.ymax]) - 0.1 + 1e-9)
    walls = sum(sc.field.keep_inside for sc in scs)
    assert 6 <= walls <= 18  # about half of 24
    assert any(np.ptp(sc.model_radii) > 1e-6 for sc in scs)
    areas = [sc.field.xmax * sc.field.ymax / sc.n for sc in scs]  # m^2 per obstacle
    assert min(areas) < 0.6 and max(areas) > 1.0  # tight and wide fields
    # some pose lies closer to an edge than the robot's radius plus its turning radius
    near = [min(x - sc.field.xmin, sc.field.xmax - x, y - sc.field.ymin, sc.field.ymax - y)
            - sc.robot_radius - sc.min_turn_radius for sc in scs for x, y, _ in (sc.start, sc.goal)]
    assert min(near) < 0


def test_a_study_takes_the_kind_and_refuses_a_density(tmp_path):
    text = ('name = "s"\nruns = 2\n[[families]]\nname = "sc"\nkind = "scattered"\n'
            'obstacles = [9]\nscenes = 1\n[[configs]]\nlabel = "paper"\n')
    (tmp_path / "ok.toml").write_text(text)
    assert load_study(str(tmp_path / "ok.toml")).families[0].kind == "scattered"
    (tmp_path / "bad.toml").write_text(text.replace("scenes = 1", "scenes = 1\ndensity = 1.0"))
    with pytest.raises(ConfigError, match=r"bad\.toml: families\[1\]\.density: not used by "
                                          r"kind scattered"):
        load_study(str(tmp_path / "bad.toml"))
