"""The ``clusters`` scene family: unlike ``obstructed`` (seeded, blocked and solvable:
tests/test_held_out_generators.py)."""
import os

import numpy as np
import pytest
from test_held_out_generators import pool as held_out_pool

from hga_jax.host.config import load_scenario, scenario_from_dict
from hga_jax.study import load_study
from hga_jax.study.config import Family
from hga_jax.study.scenes import FIELD_W, FIELD_H, family_scenes

@pytest.fixture(scope="module")
def pool():
    """20 scenes: n in (9, 15), two seeds, five each (the generators' shared test scenes)."""
    return held_out_pool("clusters")


def test_every_field_is_kept(pool):
    assert all(scenario_from_dict(d).field.keep_inside for d in pool.values())


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
