"""Robots that move, in path figures and in ``check``: each moving robot drawn where the
car passes closest, its track, time marks along the path, and the goal held at arrival."""
import dataclasses
import math

import _figure_checks as checks
import numpy as np
import pytest

from hga_jax.errors import ConfigError
from hga_jax.host.cli import main
from hga_jax.host.config import load_scenario, scenario_from_dict
from hga_jax.host.plots import plot_path, save_figure
from hga_jax.host.plots.moving_robots import mark_step, mark_times
from hga_jax.model.exact import solve
from hga_jax.model.in_time import clearance
from hga_jax.model.scenario import Scenario

R = 0.2  # every model circle below: max(rho 0.2, 0.09 + 0.09)
LINE = [{"type": "line", "start": [0.0, 0.0], "end": [3.0, 0.0]}]  # 3 m east along y = 0
CROSSING = """\
name = "crossing"
[robot]
radius = 0.09
min_turn_radius = 0.2
speed = {speed}
[start]
x = 0.0
y = 0.0
heading_deg = 0
[goal]
x = 3.0
y = 0.0
heading_deg = 0
[[obstacles]]
x = 1.5
y = 0.6
[[obstacles]]
x = {x}
y = {y}
vy = 0.8
"""


def _scene(speed=1.0, x=1.5, y=-1.0, **robot):
    """Robot 1 stands above the line; robot 2 moves north at 0.8 m/s from (x, y)."""
    obstacles = [{"x": 1.5, "y": 0.6}, {"x": x, "y": y, "vy": 0.8, **robot}]
    return scenario_from_dict({
        "name": "crossing", "robot": {"radius": 0.09, "min_turn_radius": 0.2, "speed": speed},
        "start": {"x": 0.0, "y": 0.0, "heading_deg": 0.0},
        "goal": {"x": 3.0, "y": 0.0, "heading_deg": 0.0}, "obstacles": obstacles})


def _by_gid(ax, gid):
    return [a for a in ax.get_children() if a.get_gid() == gid]


def _gids(ax):
    return sorted(str(a.get_gid()) for a in ax.get_children() if a.get_gid())


def test_robot_is_drawn_where_the_car_passes_closest():
    sc = _scene()
    ax = plot_path(sc, LINE).axes[0]
    # By hand: the car at (t, 0), robot 2 at (1.5, -1 + 0.8 t); the squared distance
    # (t - 1.5)^2 + (0.8 t - 1)^2 is least at t = 4.6 / 3.28.
    t = 4.6 / 3.28
    (disc,) = _by_gid(ax, "moving_robot")
    assert disc.center == pytest.approx((1.5, -1.0 + 0.8 * t), abs=1e-3)
    assert disc.radius == pytest.approx(0.09)
    (a,) = clearance.closest_approach(sc, LINE)
    assert a.obstacle == 1 and disc.center == pytest.approx(a.centre, abs=1e-12)
    gap = math.hypot(t - 1.5, 0.8 * t - 1.0) - R  # < 0: it meets the car
    assert a.clearance == pytest.approx(gap, abs=1e-5) and gap < 0  # sampled every mm
    (ring,) = _by_gid(ax, "moving_model_circle")
    assert ring.center == pytest.approx(a.centre) and ring.radius == pytest.approx(R)
    assert ring.get_edgecolor()[:3] == (1.0, 0.0, 0.0)  # the violation colour
    (cross,) = _by_gid(ax, "moving_collision")
    assert (cross.get_xdata()[0], cross.get_ydata()[0]) == pytest.approx((t, 0.0), abs=1e-3)
    # Its track over the path's 3 s, its body at t = 0, an arrow along its velocity.
    (track,) = _by_gid(ax, "moving_track")
    assert np.allclose(np.c_[track.get_data()], [[1.5, -1.0], [1.5, -1.0 + 0.8 * 3.0]])
    (first,) = _by_gid(ax, "moving_start")
    assert first.center == pytest.approx((1.5, -1.0)) and not first.get_fill()
    assert len(_by_gid(ax, "moving_velocity")) == 1 and len(_by_gid(ax, "moving_car")) == 1
    # The standing robot is drawn as always, at its centre; both are numbered from 1.
    (body,) = _by_gid(ax, "obstacle")
    assert body.center == pytest.approx((1.5, 0.6))
    assert sorted(t.get_text() for t in _by_gid(ax, "obstacle_number")) == ["1", "2"]
    labels = ax.get_legend_handles_labels()[1] + [t.get_text() for t in ax.get_legend().texts]
    assert any(s.startswith("robot 2 at closest approach\n(t = 1.40 s") and "collision" in s
               for s in labels)
    assert any(s.startswith("track over the path's duration") for s in labels)


def test_a_robot_that_keeps_clear_is_not_marked():
    sc = _scene(x=2.8, y=-3.0)  # passes x = 2.8 long after the car
    ax = plot_path(sc, LINE).axes[0]
    (a,) = clearance.closest_approach(sc, LINE)
    assert a.clearance > 0
    (disc,) = _by_gid(ax, "moving_robot")
    assert disc.center == pytest.approx(a.centre)
    (ring,) = _by_gid(ax, "moving_model_circle")
    assert ring.get_edgecolor()[:3] != (1.0, 0.0, 0.0)
    assert not _by_gid(ax, "moving_collision")
    texts = [t.get_text() for t in ax.get_legend().texts]
    assert not any("collision" in s for s in texts)


@pytest.mark.parametrize("speed, step, times", [
    (1.0, 0.5, [0.5, 1.0, 1.5, 2.0, 2.5]),  # 3 s
    (0.5, 1.0, [1.0, 2.0, 3.0, 4.0, 5.0]),  # 6 s
    (4.0, 0.1, [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7]),  # 0.75 s
])
def test_time_marks_on_a_line(speed, step, times):
    sc = _scene(speed=speed)
    ax = plot_path(sc, LINE).axes[0]
    ticks = _by_gid(ax, "time_mark")
    assert mark_step(3.0 / speed) == pytest.approx(step)
    assert len(ticks) == len(times)
    for tick, t in zip(ticks, times):
        xy = np.c_[tick.get_data()]
        assert xy.mean(axis=0) == pytest.approx((t * speed, 0.0), abs=1e-9)  # the car then
        assert xy[0, 0] == pytest.approx(xy[1, 0])  # across the path
    digits = 0 if step >= 1 else 1
    assert [t.get_text() for t in _by_gid(ax, "time_label")] == [f"{t:.{digits}f} s"
                                                                 for t in times]


def test_time_marks_on_arcs_match_the_drive():
    sc = load_scenario("configs/scenarios/robocup_paper.toml")
    segs = solve(sc).segments
    vel = np.zeros((sc.n, 2))
    vel[0] = (0.3, -0.2)
    sc = dataclasses.replace(sc, velocities=vel, speed=0.7)
    end = clearance.timed(segs, sc.speed)[-1].t1
    ax = plot_path(sc, segs).axes[0]
    ticks = _by_gid(ax, "time_mark")
    times = mark_times(end)
    assert 4 <= len(ticks) == len(times) <= 10
    assert times[-1] < end <= times[-1] + mark_step(end) + 1e-9
    x, y, t = clearance.sample(segs, sc.speed, 1e-4)
    for tick, tm in zip(ticks, times):
        mid = np.c_[tick.get_data()].mean(axis=0)
        i = int(np.argmin(abs(t - tm)))
        assert mid == pytest.approx((x[i], y[i]), abs=2e-4)


@pytest.mark.parametrize("duration", [0.013, 0.3, 1.0, 3.0, 4.28, 9.99, 10.0, 47.0, 1234.5])
def test_mark_step_leaves_four_to_ten_marks(duration):
    step = mark_step(duration)
    times = mark_times(duration)
    assert 4 <= len(times) <= 10
    assert times == pytest.approx([step * k for k in range(1, len(times) + 1)])
    assert duration - step <= times[-1] < duration
    assert round(step / 10 ** math.floor(math.log10(step)), 9) in (1.0, 2.0, 2.5, 5.0)
    assert mark_times(0.0) == []


def test_a_static_scene_draws_nothing_that_moves():
    still = _scene()
    still = Scenario(still.name, still.robot_radius, still.min_turn_radius, still.start,
                     still.goal, still.centres, still.radii, None)
    zero = Scenario(still.name, still.robot_radius, still.min_turn_radius, still.start,
                    still.goal, still.centres, still.radii, None,
                    velocities=np.zeros((2, 2)), speed=0.5)
    figs = [plot_path(s, LINE) for s in (still, zero)]
    for fig in figs:
        ax = fig.axes[0]
        assert not [g for g in _gids(ax) if g.startswith(("moving_", "time_"))]
        assert len(_by_gid(ax, "obstacle")) == 2 and len(_by_gid(ax, "model_circle")) == 2
    assert _gids(figs[0].axes[0]) == _gids(figs[1].axes[0])
    assert ([t.get_text() for t in figs[0].axes[0].get_legend().texts]
            == [t.get_text() for t in figs[1].axes[0].get_legend().texts])


def test_only_moving_robots_and_no_path():
    sc = scenario_from_dict({
        "name": "all move", "robot": {"radius": 0.09, "min_turn_radius": 0.2},
        "start": {"x": 0.0, "y": 0.0, "heading_deg": 0.0},
        "goal": {"x": 3.0, "y": 0.0, "heading_deg": 0.0},
        "obstacles": [{"x": 1.0, "y": 1.0, "vx": 0.1}, {"x": 2.0, "y": -1.0, "vy": 0.2}]})
    ax = plot_path(sc, LINE).axes[0]
    assert len(_by_gid(ax, "moving_robot")) == 2 and not _by_gid(ax, "obstacle")
    texts = [t.get_text() for t in ax.get_legend().texts]
    assert "obstacle (robot)" not in texts and "model circle" not in texts
    ax = plot_path(sc, []).axes[0]  # no path: the robots as at t = 0, no time marks
    assert np.allclose([d.center for d in _by_gid(ax, "moving_robot")], [(1, 1), (2, -1)])
    assert not _by_gid(ax, "time_mark") and not _by_gid(ax, "moving_track")
    assert not any(t.get_text().startswith(("track", "time")) for t in ax.get_legend().texts)


def test_exact_path_among_moving_robots_is_drawn():
    # The standing robots' optimum (straight on) meets robot 2; the exact solver's best
    # path known wraps a frozen copy of it, numbered past the scene's 2 robots where no
    # chromosome's circle of robot 2 stands there (wrap_moving "at-pass").
    sc = dataclasses.replace(_scene(), wrap_moving="at-pass")
    opt = solve(sc)
    assert opt.feasible and not opt.optimal and opt.length > 3.0
    assert any(t.obstacle > sc.n for t in opt.touched)
    ax = plot_path(sc, opt.segments, touched=opt.touched).axes[0]
    (a,) = clearance.closest_approach(sc, opt.segments)
    assert a.clearance >= -1e-6 and not _by_gid(ax, "moving_collision")
    assert _by_gid(ax, "moving_robot")[0].center == pytest.approx(a.centre)
    static = Scenario("still", 0.09, 0.2, sc.start, sc.goal, sc.centres, sc.radii, None)
    with pytest.raises(ValueError, match=r"touched: obstacle must be in 1\.\.2, got number 3"):
        plot_path(static, [], touched=[{"obstacle": 3, "label": 1}])


def test_moving_figure_is_laid_out(tmp_path):
    fig = plot_path(_scene(), LINE, title="crossing: the car meets robot 2")
    assert checks.problems(fig) == []
    assert checks.overlapping_texts(fig) == []
    assert save_figure(fig, tmp_path / "moving.png").stat().st_size > 10_000


def test_check_names_the_robot_on_the_goal_at_arrival(tmp_path, capsys):
    # Robot 2 moves north up x = 3 and reaches the goal (3, 0) at 3 s, just when the car
    # does on the standing robots' shortest path (3 m at 1 m/s).
    on_goal = tmp_path / "goal.toml"
    on_goal.write_text(CROSSING.format(speed=1.0, x=3.0, y=-2.4))
    assert main(["check", str(on_goal)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert len(out) == 2 and out[0].startswith(f"{on_goal}: ok")
    assert out[1].startswith(f"{on_goal}: note: moving robot 2 holds the goal at t = 3.000 s")
    # Twice as fast, the car is there at 1.5 s, when robot 2 is still 1.2 m south.
    on_goal.write_text(CROSSING.format(speed=2.0, x=3.0, y=-2.4))
    assert main(["check", str(on_goal)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert len(out) == 1 and out[0].startswith(f"{on_goal}: ok")


def test_a_moving_robot_on_the_start_is_refused(tmp_path, capsys):
    on_start = tmp_path / "start.toml"
    on_start.write_text(CROSSING.format(speed=1.0, x=0.05, y=0.1))
    with pytest.raises(ConfigError, match=r"start: .*model circle of obstacles\[2\]"):
        load_scenario(on_start)
    assert main(["check", str(on_start)]) == 2
    err = capsys.readouterr().err
    assert "obstacles[2]" in err and "start" in err
