"""One rule for "no feasible path" in every model: the same words, ``feasible: false``,
no length, no claim about chromosomes; and ``check`` says why, in a line."""
import json
import math

import numpy as np
import pytest

from hga_jax.host.cli import main
from hga_jax.model import no_path
from hga_jax.model.exact import solve
from hga_jax.model.scenario import Field, Scenario

FIELD = Field(0.0, 2.8, 0.0, 2.3, True)
R, RHO = 0.09, 0.15


def _scene(start, goal, obstacles=(), field=FIELD, rho=RHO):
    obs = np.asarray(obstacles, float).reshape(-1, 2)
    return Scenario("t", R, rho, start, goal, obs, np.full(len(obs), R), field)


def _toml(path, start, goal, obstacles=(), keep=True):
    text = (f'name = "{path.stem}"\n[robot]\nradius = {R}\nmin_turn_radius = {RHO}\n'
            f"[start]\nx = {start[0]}\ny = {start[1]}\nheading_deg = {start[2]}\n"
            f"[goal]\nx = {goal[0]}\ny = {goal[1]}\nheading_deg = {goal[2]}\n"
            + "".join(f"[[obstacles]]\nx = {x}\ny = {y}\n" for x, y in obstacles)
            + f"[field]\nxmin = 0.0\nxmax = 2.8\nymin = 0.0\nymax = 2.3\n"
              f"keep_inside = {'true' if keep else 'false'}\n")
    path.write_text(text)
    return str(path)


# Start 0.03 m inside the kept left edge (x = 0.09 m), facing it: a turn away needs 0.15 m.
FACING = ((0.12, 1.0, 180.0), (2.0, 1.0, 0.0))
# Goal 0.02 m below the kept top edge (y = 2.21 m), arriving downwards: its back to the edge.
BACKED = ((0.5, 1.0, 0.0), (2.0, 2.19, -90.0))
# Start facing obstacle 1 0.02 m away, obstacles on both sides: no piece leaves it.
POCKET = ((1.0, 1.0, 0.0), (2.3, 1.0, 0.0),
          [(1.2, 1.0), (1.0, 1.25), (1.0, 0.75), (0.8, 1.2), (0.8, 0.8)])
# A wall of obstacles across the field between the poses.
WALL = ((0.5, 1.0, 0.0), (2.3, 1.0, 0.0), [(1.4, y) for y in np.arange(0.05, 2.3, 0.3)])


def _rad(pose):
    return (pose[0], pose[1], math.radians(pose[2]))


@pytest.mark.parametrize("turns", ["tight-rope", "free"])
def test_every_model_answers_no_path_alike(turns):
    sc = _scene(_rad(FACING[0]), _rad(FACING[1]))
    opt = solve(sc, "full", turns)
    assert not opt.feasible and opt.length == math.inf and opt.turns == turns
    assert opt.upper is None and opt.path is None and opt.best_expressible is None
    d = opt.to_dict()
    assert d["feasible"] is False and d["length"] is None and d["expressible"] is None
    assert "faces the kept field's left edge (x = 0.09 m) 0.03 m away" in d["message"]


@pytest.mark.parametrize("turns", ["tight-rope", "free"])
def test_exact_prints_and_writes_one_verdict(tmp_path, capsys, turns):
    scene = _toml(tmp_path / "facing.toml", *FACING)
    assert main(["exact", scene, "--turns", turns, "--out", str(tmp_path / "o")]) == 0
    text = capsys.readouterr().out
    model = "collision full" + (", free turns" if turns == "free" else "")
    assert f"no feasible path exists ({model}): the start (0.12, 1, heading 180 deg)" in text
    for claim in ("inf m", "chromosome", "optimum 0", "free arc"):
        assert claim not in text
    doc = json.loads((tmp_path / "o" / "result.json").read_text())
    assert doc["optimum"]["feasible"] is False and doc["optimum"]["length"] is None
    assert doc["best"] is None and doc["summary"]["optimum_length"] is None


def test_a_run_on_a_scene_without_path_is_refused_as_check_refuses_it(tmp_path, capsys):
    """run follows check: a scene in which no feasible path can exist is bad input (exit
    2, check's line, nothing searched or written)."""
    scene = _toml(tmp_path / "facing.toml", *FACING)
    assert main(["run", scene, "--turns", "free", "--preset", "paper", "--population", "8",
                 "--generations", "1", "--runs", "2", "--quiet", "--no-cache", "--out",
                 str(tmp_path / "o")]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err == (f"hga-jax: error: {scene}: no feasible path exists (collision full, free "
                   "turns): the start (0.12, 1, heading 180 deg) faces the kept field's left "
                   "edge (x = 0.09 m) 0.03 m away, and turning away needs 0.15 m at rho = 0.15 m: "
                   "both its turning circles cross that edge ahead of it\n")
    assert not (tmp_path / "o").exists()
    assert main(["check", scene]) == 2  # check: the same verdict
    assert "no feasible path exists (collision full): the start" in capsys.readouterr().err


@pytest.mark.parametrize("case, words", [
    (FACING, ["the start (0.12, 1, heading 180 deg) faces the kept field's left edge "
              "(x = 0.09 m) 0.03 m away, and turning away needs 0.15 m"]),
    (BACKED, ["the goal (2, 2.19, heading -90 deg) backs onto the kept field's top edge "
              "(y = 2.21 m) 0.02 m away, and arriving needs 0.15 m"]),
    (POCKET, ["no path leaves the start (1, 1, heading 0 deg): its left turning circle "
              "meets obstacle 1 after 8 deg, its right turning circle meets obstacle 1",
              "the line ahead meets obstacle 1 after 0.02"]),
    (WALL, ["paths leave the start and reach the goal, but none joins them"]),
], ids=["facing", "backed", "pocket", "wall"])
def test_check_says_why_no_path_can_exist(tmp_path, capsys, case, words):
    scene = _toml(tmp_path / "s.toml", *case)
    assert main(["check", scene]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    (line,) = err.strip().splitlines()
    assert line.startswith(f"hga-jax: error: {scene}: no feasible path exists (collision full): ")
    for w in words:
        assert w in line


def test_check_follows_the_scenario_model_and_says_ok_where_a_path_exists(tmp_path, capsys):
    scene = _toml(tmp_path / "s.toml", (0.5, 1.0, 0.0), (2.3, 1.0, 0.0), [(1.4, 1.0)])
    assert main(["check", scene, "configs/scenarios/robocup_paper.toml"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].endswith("(scenario s, 1 obstacle, a feasible path exists under collision full)")
    # the field not kept: the same poses have a path
    free = _toml(tmp_path / "f.toml", *FACING, keep=False)
    assert main(["check", free]) == 0


def test_the_edge_rule_is_the_boundary_of_feasibility():
    """A start facing the left edge at angle theta from its normal has a path exactly
    when its distance to the kept edge is at least rho (1 - sin theta)."""
    rng = np.random.default_rng(3)
    field = Field(0.0, 6.0, 0.0, 6.0, True)
    for _ in range(40):
        theta = rng.uniform(-1.4, 1.4)
        need = RHO * (1.0 - abs(math.sin(theta)))
        for d, has in ((need - 0.004, False), (need + 0.004, True)):
            if d <= 0:
                continue
            start = (R + d, 3.0, math.pi + theta)
            sc = _scene(start, (4.5, 3.0, 0.0), field=field)
            assert no_path.exists(sc) == has, (theta, d)
            assert solve(sc).feasible == has
            if not has:
                assert "faces the kept field's left edge" in no_path.why(sc)
