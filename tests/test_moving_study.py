"""Studies among robots that move: the scene families of hga_jax.study.moving_scenes, the
solver "frozen", the columns in time and the analysis "moving"."""
import math

import numpy as np
import pandas as pd
import pytest

from hga_jax.errors import ConfigError
from hga_jax.host.config import scenario_from_dict
from hga_jax.model.exact import solve
from hga_jax.model.in_time import clearance
from hga_jax.study import load_study, moving_scenes
from hga_jax.study.moving_study import frozen_plan, rows
from hga_jax.study.run import run_study

SEED = 41


def _scene(kind, n=5, index=0, seed=SEED):
    d = moving_scenes.generate(kind, n, seed, index, f"{kind}_{index}")
    return d, scenario_from_dict(d, d["name"])


@pytest.mark.parametrize("kind", ["leaving", "random_moving"])
def test_a_scene_depends_on_seed_size_and_index_alone_and_keeps_its_bounds(kind):
    d, sc = _scene(kind)
    assert moving_scenes.generate(kind, 5, SEED, 0, f"{kind}_0") == d
    assert moving_scenes.generate(kind, 5, SEED, 1, f"{kind}_0") != d
    assert moving_scenes.generate(kind, 5, SEED + 1, 0, f"{kind}_0") != d
    assert sc.robot_radius == moving_scenes.ROBOT_RADIUS
    assert np.all(sc.radii == moving_scenes.ROBOT_RADIUS)
    assert 0.15 <= sc.min_turn_radius <= 0.30
    assert 1.0 <= sc.speed <= 2.0
    standing = int((~sc.moving).sum())
    assert 4 <= standing <= min(6, sc.n - 1) and sc.moving.any()
    speeds = np.hypot(*np.asarray(sc.velocities)[sc.moving].T)
    assert np.all((speeds >= 0.3 - 1e-3) & (speeds <= 1.5 + 1e-3)), speeds
    assert not np.any(np.asarray(sc.velocities)[~sc.moving])
    # a path feasible in time is known; a certified optimum has a chromosome
    found = solve(sc)
    assert found.feasible and found.lower_bound is not None
    assert not found.optimal or found.expressible


def test_standing_is_the_random_moving_draw_with_every_robot_standing():
    d, sc = _scene("standing")
    assert not sc.has_motion and sc.velocities is None
    assert all("vx" not in o and "vy" not in o for o in d["obstacles"])
    moving_d, moving_sc = _scene("random_moving")
    assert moving_sc.has_motion
    np.testing.assert_array_equal(sc.centres, moving_sc.centres)
    assert (sc.start, sc.goal, sc.speed, sc.min_turn_radius) == (
        moving_sc.start, moving_sc.goal, moving_sc.speed, moving_sc.min_turn_radius)
    assert d["field"] == moving_d["field"]
    assert solve(sc).feasible and solve(sc).expressible


def test_leaving_robots_start_on_or_near_the_still_path():
    _, sc = _scene("leaving")
    still = solve(sc.still_scene())
    x, y, _ = clearance.sample(still.segments, sc.speed, 0.005)
    for c in sc.centres[sc.moving]:
        assert np.min(np.hypot(x - c[0], y - c[1])) <= moving_scenes.NEAR + 0.01


def test_crossing_scenes_collide_in_time_on_the_still_optimum_and_know_a_way_round():
    d, sc = _scene("crossing")
    assert moving_scenes.generate("crossing", 5, SEED, 0, "crossing_0") == d
    still = solve(sc.still_scene())
    assert still.feasible and clearance.segment_hits(sc, still.segments)
    found = solve(sc)
    assert found.feasible and not found.optimal
    assert found.lower_bound == pytest.approx(still.length)
    assert found.length >= still.length and not clearance.segment_hits(sc, found.segments)
    speeds = np.hypot(*np.asarray(sc.velocities)[sc.moving].T)
    assert np.all((speeds >= 0.3 - 1e-3) & (speeds <= 1.5 + 1e-3))


def test_the_frozen_plan_is_the_snapshot_optimum_judged_in_time():
    d, sc = _scene("crossing")
    plan, hits = frozen_plan(sc)
    snapshot = solve(scenario_from_dict({**d, "obstacles": [  # every robot where it starts
        {k: v for k, v in o.items() if k not in ("vx", "vy")} for o in d["obstacles"]]},
        "snap"))
    assert plan.feasible == snapshot.feasible
    assert plan.length == pytest.approx(snapshot.length)
    assert hits == clearance.segment_hits(sc, plan.segments)
    assert hits  # the crossing robots start off the path: the snapshot drives into them


STUDY = """name = "tiny_moving"
seed = 3
runs = 2
analyses = ["moving"]
[[families]]
name = "crossing"
kind = "crossing"
obstacles = [5]
scenes = 1
seed = {seed}
[[configs]]
label = "small"
population = 12
generations = 3
[[configs]]
label = "frozen"
solver = "frozen"
"""


def test_a_tiny_study_writes_the_columns_in_time_and_the_moving_table(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text(STUDY.replace("{seed}", str(SEED)))
    out = run_study(str(path), out=str(tmp_path / "o"), progress=False, figures=False)
    tab = out.table
    for col in ("certified", "best_known", "at_best_known", "best_known_expressible",
                "frozen_collides", "frozen_found"):
        assert col in tab, col
    _, sc = _scene("crossing")
    best = solve(sc)
    ga = tab[tab["config"] == "small"]
    assert len(ga) == 2 and not ga["certified"].any()
    assert ga["best_known"].tolist() == pytest.approx([best.length] * 2)
    assert ga["optimum"].tolist() == pytest.approx([best.lower_bound] * 2)  # gaps to the bound
    assert not ga["hit"].any()
    expect = [bool(f) and x <= best.length * (1 + 1e-6)
              for f, x in zip(ga["feasible"], ga["length"])]
    assert ga["at_best_known"].tolist() == expect
    frozen = tab[tab["config"] == "frozen"]
    plan, hits = frozen_plan(sc)
    assert len(frozen) == 1 and frozen["frozen_found"].tolist() == [plan.feasible]
    assert frozen["frozen_collides"].tolist() == [bool(hits)]
    assert frozen["feasible"].tolist() == [bool(plan.feasible and not hits)]
    table = pd.read_csv(tmp_path / "o" / "moving.csv")
    assert list(table["config"]) == ["small", "frozen"]
    for col in ("feasible_rate", "feasible_ci_low", "hit_rate_certified",
                "at_best_known_rate", "at_best_known_ci_high", "frozen_collides_rate",
                "time_per_run_median_ms"):
        assert col in table, col
    small = table.iloc[0]
    assert small["runs_uncertified"] == 2 and small["runs_certified"] == 0
    assert math.isnan(small["hit_rate_certified"])
    assert small["feasible_rate"] == pytest.approx(ga["feasible"].mean())
    assert small["frozen_collides"] == int(bool(hits)) and small["frozen_scenes"] == 1
    text = (tmp_path / "o" / "moving.md").read_text()
    assert "feasible in time" in text and "frozen plan collides in time" in text


def test_the_moving_analysis_counts_a_scene_where_nothing_moves_as_certified():
    tab = pd.DataFrame({
        "config": ["a"] * 4, "solver": ["hga"] * 4, "family": ["f"] * 4,
        "obstacles": [5] * 4, "scenario": ["s1", "s1", "s2", "s2"],
        "feasible": [True, False, True, True], "hit": [True, False, False, False],
        "certified": [None, None, False, False], "at_best_known": [None, None, True, False],
        "time_s": [0.01] * 4})

    class Study:
        configs = [type("C", (), {"label": "a", "solver": "hga"})()]

    (r,) = rows(Study, tab)
    assert (r["scenes"], r["scenes_certified"], r["runs_certified"]) == (2, 1, 2)
    assert r["hit_rate_certified"] == 0.5 and r["at_best_known_rate"] == 0.5
    assert r["feasible_rate"] == 0.75 and r["frozen_scenes"] == 0


@pytest.mark.parametrize("text, key", [
    ('[[families]]\nname = "m"\nkind = "leaving"\nobstacles = [5]\ndensity = 1.0\n'
     '[[configs]]\nlabel = "x"\n', "density"),
    ('[[families]]\nname = "m"\nkind = "crossing"\nobstacles = [1]\n[[configs]]\nlabel = "x"\n',
     "obstacles"),
    ('[[families]]\nname = "m"\nkind = "crossing"\nobstacles = [5]\n'
     '[[configs]]\nsolver = "frozen"\npopulation = 10\n', "population"),
])
def test_study_files_refuse_what_the_moving_families_and_frozen_do_not_take(tmp_path, text, key):
    path = tmp_path / "s.toml"
    path.write_text('name = "s"\nruns = 2\n' + text)
    with pytest.raises(ConfigError, match=key):
        load_study(str(path))


def test_the_moving_study_file_loads_with_its_quick_version():
    for quick in (False, True):
        s = load_study("configs/studies/moving.toml", quick=quick)
        assert [f.kind for f in s.families] == ["leaving", "crossing", "random_moving",
                                                "standing"]
        assert [c.solver for c in s.configs] == ["hga", "hga", "frozen"]
        assert s.runs_of(s.configs[2]) == 1 and "moving" in s.analyses
    standing, random_moving = s.families[3], s.families[2]
    assert standing.seed == random_moving.seed  # the control: the same draws
