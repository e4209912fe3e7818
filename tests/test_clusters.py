"""The ``clusters`` scene family: seeded, blocked, solvable, and unlike ``obstructed``."""
import os
import re

import numpy as np
import pytest

from hga_jax.errors import ConfigError
from hga_jax.host.config import load_scenario, scenario_from_dict
from hga_jax.model.exact import solve
from hga_jax.study import clusters, load_study
from hga_jax.study.config import Family
from hga_jax.study.scene_files import blocked as _blocked
from hga_jax.study.scenes import FIELD_W, FIELD_H, family_scenes, generate

CASES = [(n, seed, i) for n in (9, 15) for seed in (0, 7) for i in range(5)]


@pytest.fixture(scope="module")
def pool():
    """20 scenes: n in (9, 15), two seeds, five each."""
    return {c: generate("clusters", c[0], c[1], c[2], f"c{c[0]}_{c[2]}") for c in CASES}


def test_seeded_by_seed_count_and_index(pool):
    assert clusters.generate(9, 0, 1, "c9_1") == pool[(9, 0, 1)]
    assert pool[(9, 0, 0)] != pool[(9, 0, 1)]
    assert pool[(9, 0, 0)]["obstacles"] != pool[(9, 7, 0)]["obstacles"]


def test_every_scene_is_blocked_and_its_optimum_wraps_three(pool):
    for (n, _, _), d in pool.items():
        sc = scenario_from_dict(d)
        assert sc.n == n and sc.field is not None and sc.field.keep_inside
        assert _blocked(sc)
        opt = solve(sc)
        assert opt.feasible and opt.expressible
        assert len({o for o, _ in opt.touched}) >= 3


def test_radii_headings_fields_and_ends_vary(pool):
    scs = [scenario_from_dict(d) for d in pool.values()]
    for sc in scs:
        assert 0.05 <= sc.robot_radius <= 0.12 and 0.10 <= sc.min_turn_radius <= 0.30
        assert np.all((sc.radii >= 0.04) & (sc.radii <= 0.22))
    assert any(np.ptp(sc.model_radii) > 1e-6 for sc in scs)  # differ within a scene
    assert len({round(sc.robot_radius, 4) for sc in scs}) > 1
    heads = np.degrees([[sc.start[2], sc.goal[2]] for sc in scs]).ravel()
    assert np.any(np.abs(heads) > 60) and np.any(np.abs(heads) > 120)
    sizes = [(sc.field.xmax, sc.field.ymax) for sc in scs]
    assert any(abs(w - FIELD_W) > 1e-3 or abs(h - FIELD_H) > 1e-3 for w, h in sizes)
    assert any(h > w for w, h in sizes) and any(w > h for w, h in sizes)
    dx = [abs(sc.goal[0] - sc.start[0]) for sc in scs]
    dy = [abs(sc.goal[1] - sc.start[1]) for sc in scs]
    assert any(b > a for a, b in zip(dx, dy))  # not always left to right


def test_family_scenes_write_loadable_files(tmp_path):
    scenes = family_scenes(Family("cl", "clusters", (9,), 2, 3), str(tmp_path))
    assert len({s.text for s in scenes}) == 2
    sc = load_scenario(scenes[0].path)
    assert sc.n == 9 and "radius = " in scenes[0].text
    assert os.path.basename(scenes[0].path) == "cl_n009_000.toml"


STUDY = """name = "s"
runs = 10
[[families]]
name = "held_out"
kind = "clusters"
obstacles = {obstacles}
scenes = 4
seed = 2
{extra}"""


def test_study_with_a_clusters_family_parses(tmp_path):
    p = tmp_path / "study.toml"
    p.write_text(STUDY.format(obstacles="[9, 15]", extra=""))
    fam = load_study(str(p)).families[0]
    assert fam == Family("held_out", "clusters", (9, 15), 4, 2, None)


@pytest.mark.parametrize("obstacles, extra, key", [
    ("[9]", "density = 1.4\n", "families[1].density"),
    ("[2]", "", "families[1].obstacles"),
])
def test_bad_clusters_family_names_the_key(tmp_path, obstacles, extra, key):
    p = tmp_path / "study.toml"
    p.write_text(STUDY.format(obstacles=obstacles, extra=extra))
    with pytest.raises(ConfigError, match=re.escape(key)):
        load_study(str(p))
