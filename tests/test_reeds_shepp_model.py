"""The Reeds–Shepp car among obstacles: the exact optimum of the model.

With no obstacles the optimum is the closed form (every word is reachable); with
obstacles it is never longer than the free-turn optimum (every forward path is a
Reeds–Shepp path) nor shorter than the closed form, and every path it returns passes an
independent float64 check (tests/_rs_check.py) of headings, cusps, curvature,
clearance, field and length. From the command line: ``exact --car reeds-shepp``,
``[robot] car``, what the summary and result.json say, and one-line errors.
"""
from __future__ import annotations

import json
import math

import numpy as np
import pytest

import _rs_check
from hga_jax import scenario_from_dict
from hga_jax.errors import ConfigError
from hga_jax.host.cli import main
from hga_jax.model.cars.reeds_shepp import closed_form
from hga_jax.model.exact import solve
from hga_jax.search.settings import GASettings
from hga_jax.study import scenes

RHO = 0.25


def _scene(rng, obstacles=(), field=None, rho=RHO):
    d = {"name": "rs", "robot": {"radius": 0.09, "min_turn_radius": rho},
         "start": {"x": 1.0, "y": 1.0, "heading_deg": float(rng.uniform(0, 360))},
         "goal": {"x": 1.0 + float(rng.uniform(-1.5, 1.5)),
                  "y": 1.0 + float(rng.uniform(-1.5, 1.5)),
                  "heading_deg": float(rng.uniform(0, 360))},
         "obstacles": list(obstacles)}
    if field:
        d["field"] = field
    return d


def _with_a_cusp():
    """``(scenario, optimum)`` of the first random open scene whose optimum has a cusp."""
    rng = np.random.default_rng(3)
    for _ in range(60):
        sc = scenario_from_dict(_scene(rng), "rs")
        opt = solve(sc, car="reeds-shepp")
        if opt.details["cusps"]:
            return sc, opt
    raise AssertionError("no scene with a cusp among 60")


def test_with_no_obstacles_the_optimum_is_the_closed_form():
    rng = np.random.default_rng(7)
    for k in range(60):
        d = _scene(rng, rho=float(rng.choice([0.15, 0.25, 0.4])))
        sc = scenario_from_dict(d, "rs")
        opt = solve(sc, car="reeds-shepp")
        closed = closed_form.length(sc.start, sc.goal, sc.min_turn_radius)
        assert opt.feasible and opt.turns == "reeds-shepp"
        assert opt.length == pytest.approx(closed, rel=1e-9, abs=1e-12)
        assert _rs_check.problems(d, opt.segments, opt.length) == []


def _obstacle_scenes():
    out = []
    for kind, n in (("uniform", 9), ("obstructed", 9), ("clusters", 9), ("obstructed", 15)):
        for i in range(3):
            out.append(scenes.generate(kind, n, 31, i, f"{kind}{n}_{i}"))
    return out


@pytest.mark.parametrize("k", range(12))
def test_among_obstacles_never_longer_than_free_turns_and_every_path_checks(k):
    d = _obstacle_scenes()[k]
    sc = scenario_from_dict(d, "rs")
    rs, free = solve(sc, car="reeds-shepp"), solve(sc, turns="free")
    assert rs.feasible == free.feasible or (rs.feasible and not free.feasible)
    closed = closed_form.length(sc.start, sc.goal, sc.min_turn_radius)
    assert closed - 1e-9 <= rs.length <= free.length + 1e-9
    assert _rs_check.problems(d, rs.segments, rs.length) == []
    flips = sum(bool(a.get("reverse")) != bool(b.get("reverse"))
                for a, b in zip(rs.segments, rs.segments[1:]))
    assert rs.details["cusps"] == flips
    assert rs.tight_rope_length >= free.length - 1e-9


def test_a_goal_behind_the_start_between_walls_is_reached_backward():
    """Parking: the goal 1 m straight behind the start, same heading, obstacles on both
    sides of the lane: the car backs straight in (no cusp), where a forward car must
    loop round."""
    d = {"name": "lane", "robot": {"radius": 0.09, "min_turn_radius": 0.3},
         "start": {"x": 2.0, "y": 1.0, "heading_deg": 0.0},
         "goal": {"x": 1.0, "y": 1.0, "heading_deg": 0.0},
         "obstacles": [{"x": x, "y": y} for x in (0.9, 1.3, 1.7, 2.1) for y in (0.6, 1.4)]}
    sc = scenario_from_dict(d, "lane")
    rs = solve(sc, car="reeds-shepp")
    assert rs.length == pytest.approx(1.0, abs=1e-9) and rs.details["cusps"] == 0
    assert [s["type"] for s in rs.segments] == ["line"] and rs.segments[0]["reverse"]
    assert _rs_check.problems(d, rs.segments, rs.length) == []
    assert solve(sc, turns="free").length > 2.0


def test_exact_command_with_the_reeds_shepp_car(tmp_path, capsys):
    d = {"name": "lane", "robot": {"radius": 0.09, "min_turn_radius": 0.3,
                                   "car": "reeds-shepp"},
         "start": {"x": 2.0, "y": 1.0, "heading_deg": 0.0},
         "goal": {"x": 1.0, "y": 1.2, "heading_deg": 30.0}, "obstacles": []}
    import tomli_w

    path = tmp_path / "lane.toml"
    path.write_text(tomli_w.dumps(d))
    assert main(["exact", str(path), "--out", str(tmp_path / "a"), "--plot"]) == 0
    printed = capsys.readouterr().out
    assert "Reeds-Shepp optimum" in printed and "cusp" in printed
    assert "free-turn optimum" in printed and "tight-rope optimum" in printed
    data = json.loads((tmp_path / "a" / "result.json").read_text())
    assert data["settings"]["car"] == "reeds-shepp" and data["optimum"]["turns"] == "reeds-shepp"
    segs = data["optimum"]["segments"]
    assert any(s.get("reverse") for s in segs)
    assert _rs_check.problems(d, segs, data["optimum"]["length"]) == []
    assert (tmp_path / "a" / "path.png").stat().st_size > 0
    # The same scene under --car dubins: the free-turn optimum is longer.
    assert main(["exact", str(path), "--car", "dubins", "--turns", "free",
                 "--out", str(tmp_path / "b")]) == 0
    capsys.readouterr()
    free = json.loads((tmp_path / "b" / "result.json").read_text())["optimum"]["length"]
    assert free > data["optimum"]["length"] + 1e-3


def test_bad_car_values_are_one_line(tmp_path, capsys):
    rng = np.random.default_rng(1)
    d = _scene(rng)
    d["robot"]["car"] = "tank"
    with pytest.raises(ConfigError, match="robot.car: must be one of dubins, reeds-shepp"):
        scenario_from_dict(d, "x.toml")
    import tomli_w

    d["robot"]["car"] = "reeds-shepp"
    path = tmp_path / "s.toml"
    path.write_text(tomli_w.dumps(d))
    assert main(["exact", str(path), "--car", "tank", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--car" in err[0] and "tank" in err[0]
    assert not (tmp_path / "o").exists()
    assert main(["run", str(path), "--collision", "paper", "--out", str(tmp_path / "r")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "robot.car" in err[0] and "full collision test" in err[0]
    assert str(path) in err[0] and "'paper'" in err[0]
    assert not (tmp_path / "r").exists()
    with pytest.raises(ConfigError, match="full collision test"):
        GASettings(turns="reeds-shepp", collision="paper")
    with pytest.raises(ValueError, match="full collision test"):
        solve(scenario_from_dict(d, "s"), "paper")


def test_plots_draw_backward_pieces_and_cusps():
    from hga_jax.host.plots import plot_path

    sc, opt = _with_a_cusp()
    fig = plot_path(sc, opt.segments)
    ax = fig.axes[0]
    cusps = [a for a in ax.get_lines() if a.get_gid() == "cusp"]
    assert len(cusps) == opt.details["cusps"]
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "cusp" in labels and any("driven backward" in t for t in labels)
    assert math.isfinite(opt.length)


@pytest.mark.parametrize("kind", ["behind", "slot", "wall"])
def test_parking_families_keep_scenes_where_reversing_pays(kind):
    from hga_jax.study import parking

    for i in range(2):
        d = parking.generate(kind, 9, 5, i, f"{kind}{i}")
        assert d == parking.generate(kind, 9, 5, i, f"{kind}{i}")  # (seed, n, i) alone
        sc = scenario_from_dict(d, kind)
        assert sc.car == "reeds-shepp" and sc.n == 9
        rs = solve(sc)  # the scenario's car
        assert rs.turns == "reeds-shepp"
        assert rs.length <= (1 - parking.MIN_SAVING) * rs.details["free_turn_length"]
        assert _rs_check.problems(d, rs.segments, rs.length) == []


def test_the_peer_judge_understands_cusps():
    """The judge of peer paths (OMPL's) takes a piece driven backward as facing against
    its travel: the optimum's segments join at every cusp; dropping one gear flag makes
    a break there."""
    from hga_jax.peers.judge import judge_poses, judge_segments

    sc, opt = _with_a_cusp()
    j = judge_segments(sc, opt.segments)
    assert j.feasible and j.gaps == 0 and j.length == pytest.approx(opt.length, abs=1e-12)
    k = next(i for i, s in enumerate(opt.segments) if s.get("reverse"))
    wrong = [dict(s) for s in opt.segments]
    wrong[k].pop("reverse")
    assert judge_segments(sc, wrong).gaps > 0
    # Waypoints joined by Reeds-Shepp paths: start and goal alone give the closed form.
    joined = judge_poses(sc, [sc.start, sc.goal], car="reeds-shepp")
    assert joined.length == pytest.approx(closed_form.length(sc.start, sc.goal, RHO), abs=1e-12)
    assert joined.gaps == 0


def test_export_writes_the_gear_and_the_cars_heading(tmp_path, capsys):
    """The lane scene backs 1 m straight into its goal: every pose has gear -1 and the
    car's heading (0, against its travel), and the poses end on the goal pose."""
    import tomli_w

    d = {"name": "lane", "robot": {"radius": 0.09, "min_turn_radius": 0.3,
                                   "car": "reeds-shepp"},
         "start": {"x": 2.0, "y": 1.0, "heading_deg": 0.0},
         "goal": {"x": 1.0, "y": 1.0, "heading_deg": 0.0},
         "obstacles": [{"x": x, "y": y} for x in (0.9, 1.3, 1.7, 2.1) for y in (0.6, 1.4)]}
    path = tmp_path / "lane.toml"
    path.write_text(tomli_w.dumps(d))
    assert main(["exact", str(path), "--out", str(tmp_path / "a")]) == 0
    assert main(["export", str(tmp_path / "a" / "result.json"), "--spacing", "0.1"]) == 0
    capsys.readouterr()
    doc = json.loads((tmp_path / "a" / "poses.json").read_text())
    assert doc["columns"][-1] == "gear"
    table = np.asarray(doc["poses"])
    assert len(table) == 11 and np.all(table[:, 5] == -1.0)
    assert np.allclose(table[:, 3], 0.0) and np.allclose(table[:, 1], np.linspace(2.0, 1.0, 11))


def test_a_start_facing_a_wall_backs_away_and_check_says_ok(tmp_path, capsys):
    """Facing the kept field's edge 0.11 m away with rho 0.3 m: no forward path exists
    (the verdict names the edge); the Reeds-Shepp car backs away, with one cusp, and
    `check` passes the scenario that says car = "reeds-shepp"."""
    import tomli_w

    d = {"name": "wall", "robot": {"radius": 0.09, "min_turn_radius": 0.3},
         "start": {"x": 0.2, "y": 1.0, "heading_deg": 180.0},
         "goal": {"x": 1.5, "y": 1.0, "heading_deg": 0.0},
         "field": {"xmin": 0, "xmax": 3, "ymin": 0, "ymax": 2, "keep_inside": True},
         "obstacles": []}
    sc = scenario_from_dict(d, "wall")
    free = solve(sc, turns="free")
    assert not free.feasible and "left edge" in free.message
    rs = solve(sc, car="reeds-shepp")
    assert rs.feasible and rs.details["cusps"] >= 1
    assert _rs_check.problems(d, rs.segments, rs.length) == []
    d["robot"]["car"] = "reeds-shepp"
    path = tmp_path / "wall.toml"
    path.write_text(tomli_w.dumps(d))
    assert main(["check", str(path)]) == 0
    assert "Reeds-Shepp car" in capsys.readouterr().out


def test_poses_on_one_point_and_their_summaries():
    """The goal on the start pose: 0 m, and the summary prints (no ratio to a 0 m tight
    rope). The goal on the start point facing back: a three-arc turn with two cusps,
    pi rho long, where the forward car needs more."""
    from hga_jax.host.report import exact_summary

    base = {"name": "p", "robot": {"radius": 0.09, "min_turn_radius": RHO, "car": "reeds-shepp"},
            "obstacles": [], "start": {"x": 1.0, "y": 1.0, "heading_deg": 30.0}}
    same = scenario_from_dict(dict(base, goal={"x": 1.0, "y": 1.0, "heading_deg": 30.0}), "p")
    opt = solve(same)
    assert opt.length == 0.0 and opt.segments == []
    assert "tight-rope optimum 0.000000 m" in exact_summary(same, opt)
    d = dict(base, goal={"x": 1.0, "y": 1.0, "heading_deg": 210.0})
    back = scenario_from_dict(d, "p")
    opt = solve(back)
    assert opt.length == pytest.approx(math.pi * RHO, abs=1e-9) and opt.details["cusps"] == 2
    assert opt.details["free_turn_length"] > opt.length + 0.1
    assert _rs_check.problems(d, opt.segments, opt.length) == []
    assert "2 cusps" in exact_summary(back, opt)


def test_quarter_turns_hold_the_backing_manoeuvre_ompl_found():
    """A slot scene where OMPL's BIT* (Reeds-Shepp space) once found a 0.6500 m path while
    the model without quarter-turn circles held 0.6539 m: a small forward turn, a cusp
    onto a free circle, a quarter turn and a tangent into the slot. With them the
    optimum is shorter than OMPL's path, and every quarter-turn circle touches a pose
    circle from outside."""
    from hga_jax.model.cars.reeds_shepp import graph as rg
    from hga_jax.study import parking

    d = parking.generate("slot", 9, 77, 11, "slot_n009_011")
    sc = scenario_from_dict(d, "slot")
    opt = solve(sc)
    assert opt.length < 0.6500 and _rs_check.problems(d, opt.segments, opt.length) == []
    assert [tuple(t) for t in opt.touched] == [(1, 1)]  # one touch, however many arcs
    circ, back = rg.circles(sc, quarter=False)
    fixed = tuple(v[:back + 4] for v in circ)
    qx, qy, qs = rg.quarter_turns(sc, fixed, back)
    x, y, r = fixed[:3]
    anchors = np.r_[0, 1, back, back + 1, 2, 3, back + 2, back + 3]
    d_to = (np.hypot(qx[:, None] - x[anchors], qy[:, None] - y[anchors])
            - (r[anchors] + sc.min_turn_radius))
    assert qx.size > 0 and np.all(np.min(np.abs(d_to), axis=1) < 1e-9)


def test_run_takes_car_from_the_command_line(tmp_path, capsys):
    """`run --car dubins` on a Reeds-Shepp scenario searches the forward car; `run --car
    reeds-shepp` on a forward one searches the Reeds-Shepp car's paths and records it."""
    import tomli_w

    d = {"name": "c", "robot": {"radius": 0.09, "min_turn_radius": 0.2, "car": "reeds-shepp"},
         "start": {"x": 0.5, "y": 0.5, "heading_deg": 0.0},
         "goal": {"x": 1.5, "y": 0.9, "heading_deg": 0.0}, "obstacles": [],
         "ga": {"population": 10, "generations": 2}}
    path = tmp_path / "c.toml"
    path.write_text(tomli_w.dumps(d))
    assert main(["run", str(path), "--car", "dubins", "--preset", "paper", "--runs", "2",
                 "--out", str(tmp_path / "a"), "--quiet"]) == 0
    assert "optimum" in capsys.readouterr().out
    forward = json.loads((tmp_path / "a" / "result.json").read_text())
    assert forward["settings"]["car"] == "dubins" and forward["settings"]["turns"] == "tight-rope"
    d["robot"]["car"] = "dubins"
    path.write_text(tomli_w.dumps(d))
    assert main(["run", str(path), "--car", "reeds-shepp", "--preset", "paper", "--runs", "2",
                 "--out", str(tmp_path / "b"), "--quiet"]) == 0
    capsys.readouterr()
    both = json.loads((tmp_path / "b" / "result.json").read_text())
    assert both["settings"]["car"] == "reeds-shepp" and both["settings"]["turns"] == "reeds-shepp"
    # With no obstacles the optimum is the closed form, no longer than the forward car's.
    assert both["optimum"]["length"] <= forward["optimum"]["length"] + 1e-9
    assert main(["run", str(path), "--car", "bike", "--out", str(tmp_path / "b")]) == 2
    assert "--car: must be one of dubins, reeds-shepp" in capsys.readouterr().err


def test_parking_families_for_the_forward_car_keep_scenes_it_can_drive():
    """``car = "dubins"``: the same kinds of poses, kept where the forward car's tight-rope
    optimum is feasible and expressible (a wall scene's start may face a wall it cannot
    turn away from: such a draw is dropped); the Reeds–Shepp family is untouched."""
    from hga_jax.study import parking

    for kind in ("wall", "behind"):
        d = parking.generate(kind, 9, 5, 0, "f", car="dubins")
        assert d == parking.generate(kind, 9, 5, 0, "f", car="dubins")
        sc = scenario_from_dict(d, kind)
        assert sc.car == "dubins"
        opt = solve(sc)
        assert opt.turns == "tight-rope" and opt.feasible and opt.expressible
    wall = scenario_from_dict(parking.generate("wall", 9, 5, 0, "f", car="dubins"), "w")
    x, y = wall.start[:2]
    w, h = 2.8, 2.3  # the RoboCup field the family keeps
    assert min(x, y, w - x, h - y) <= 0.25 + 0.09 + 1e-9  # a start by the wall
    rs = parking.generate("wall", 9, 5, 0, "f")
    assert rs["robot"]["car"] == "reeds-shepp"
