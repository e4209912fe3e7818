"""The replanning loop (hga_jax/loop): a frame's arrays built on the device against the host's,
the replanner's one program and its seeds, and episodes with their motions and outcomes."""
from __future__ import annotations

import dataclasses
import json
import math

import jax
import numpy as np
import pytest

from hga_jax import scenario_from_dict
from hga_jax.loop import Car, Replanner, episode, frame, observation, planners
from hga_jax.model.decode import decode_batch
from hga_jax.model.fitness import evaluate

BOUND = 4
CAR = Car(0.09, 0.2, 1.0)
"""The car of the episodes below too (their scene's), so that every test shares one program."""
BARE = CAR._replace(margin=0.0)
"""Without the loop's margin: the host scene's model radii."""


def _scene(robots, start=(0.0, 0.0, 0.0), goal=(3.0, 0.0, 0.0), field=None, name="loop"):
    d = {"name": name, "robot": {"radius": 0.09, "min_turn_radius": 0.2, "speed": 1.0},
         "start": {"x": start[0], "y": start[1], "heading_deg": math.degrees(start[2])},
         "goal": {"x": goal[0], "y": goal[1], "heading_deg": math.degrees(goal[2])},
         "obstacles": [{"x": x, "y": y, "vx": vx, "vy": vy, "radius": r}
                       for x, y, vx, vy, r in robots]}
    if field is not None:
        d["field"] = field
    return scenario_from_dict(d, name)


ROBOTS = [(1.5, -1.2, 0.0, 0.8, 0.09), (0.9, 0.5, 0.3, -0.2, 0.09), (2.2, 0.4, -0.4, 0.1, 0.09)]
"""Three robots that all move (the host scene then judges every robot in time, as a frame does)."""


@pytest.fixture(scope="module")
def replanner():
    rp = Replanner(CAR, BOUND, generations=3, seed=5)
    rp.warm_up()
    return rp


def test_the_frames_arrays_are_the_hosts_in_time():
    """Every robot moving, their circles placed where the frame places them: the frame's
    tangent table (built on the device) is the host's, and the fitness of random
    chromosomes (decoded, tested in time) gives the host decoder's lengths and violations."""
    obs = observation([0.0, 0.0, 0.0], [3.0, 0.0, 0.0], ROBOTS, len(ROBOTS), np.float32)
    sa = jax.jit(lambda o: frame.arrays(o, BARE))(obs)
    sc = _scene(ROBOTS)
    placed = np.asarray(sa.motion.placed, np.float64)
    sc.cached("placement times", lambda: placed)
    host = sc.arrays(np.float32)
    for name in ("p1x", "p1y", "p2x", "p2y", "length"):
        assert np.allclose(np.asarray(getattr(sa.tangents, name)),
                           np.asarray(getattr(host.tangents, name)), atol=2e-5), name
    for name in ("exists", "violations_full"):
        assert np.array_equal(np.asarray(getattr(sa.tangents, name)),
                              np.asarray(getattr(host.tangents, name))), name
    rng = np.random.default_rng(0)
    perm = np.argsort(rng.random((2000, 3)), axis=1).astype(np.int32)
    labels = rng.choice(np.array([-1, 0, 1], np.int32), (2000, 5))
    labels[:, [0, -1]] = rng.choice(np.array([-1, 1], np.int32), (2000, 2))
    mine = jax.jit(lambda p, lab: evaluate(sa, p, lab, "full"))(perm, labels)
    theirs = jax.jit(lambda p, lab: decode_batch(host, p, lab, "full"))(perm, labels)
    assert np.allclose(np.asarray(mine.length), np.asarray(theirs.length), atol=1e-4)
    same = np.asarray(mine.violations) == np.asarray(theirs.violations)
    assert same.mean() > 0.998
    assert (np.asarray(theirs.violations) == 0).any() and (np.asarray(theirs.violations) > 0).any()


def test_a_padded_slot_is_never_touched(replanner):
    """One robot in a bound of four: every plan's chromosome leaves the three empty slots
    untouched, and its length is that of the path it says."""
    replanner.reset()
    for _ in range(3):
        plan = replanner.step(observation([0, 0, 0], [3, 0, 0], ROBOTS[:1], BOUND))[0]
        slots = np.asarray(plan.perm)
        touched = [int(slots[k]) for k in range(BOUND) if plan.labels[k + 1] != 0]
        assert all(t == 0 for t in touched)
        assert sum(_len(s) for s in plan.segments) == pytest.approx(plan.length, abs=1e-4)


def _len(seg):
    return seg["radius"] * abs(seg["sweep"]) if seg["type"] == "arc" else math.dist(
        seg["start"], seg["end"])


def test_one_program_serves_every_robot_count(replanner):
    """Frames with 0 to 4 robots, after a reset too: the program compiled once."""
    before = replanner.compiles()
    for k in range(BOUND + 1):
        replanner.step(observation([0, 0, 0], [3, 0, 0], (ROBOTS + ROBOTS)[:k], BOUND))
    replanner.reset()
    replanner.step(observation([0, 0, 0], [3, 0, 0], ROBOTS, BOUND))
    assert before == 1 and replanner.compiles() == 1


def test_a_seed_repeats_its_loop():
    """Two replanners of one seed give the same plans frame after frame; another seed's
    populations differ."""
    def plans(seed):
        rp = Replanner(CAR, BOUND, generations=3, seed=seed)
        out = []
        for f in range(4):
            obs = observation([0.1 * f, 0, 0], [3, 0, 0], ROBOTS, BOUND)
            p = rp.step(obs)[0]
            out.append((p.length, p.violations, p.perm.tolist(), p.labels.tolist()))
        return out, np.asarray(rp._core.pop.perm)

    a, pa = plans(5)
    b, pb = plans(5)
    _, pc = plans(6)
    assert a == b and np.array_equal(pa, pb)
    assert not np.array_equal(pa, pc)


def test_a_start_inside_a_robot_plans_and_says_so(replanner):
    """A robot 5 cm from the car (inside its model circle): a plan, its status naming the
    robot, no exception."""
    replanner.reset()
    plan = replanner.step(observation([0, 0, 0], [3, 0, 0], [(0.05, 0.0, 0.0, 0.0, 0.09)],
                                      BOUND))[0]
    assert plan.status == "start inside robot 0"
    assert plan.segments and plan.violations > 0


def test_poses_carry_time(replanner):
    replanner.reset()
    plan = replanner.step(observation([0, 0, 0], [3, 0, 0], [], BOUND))[0]
    poses = plan.poses(0.5)
    assert plan.length == pytest.approx(3.0, abs=1e-5)  # the straight line
    assert np.allclose(poses["t"], poses["s"] / CAR.speed)
    assert np.allclose(poses["y"], 0.0, atol=1e-6) and poses["x"][-1] == pytest.approx(3.0)


# ---------------------------------------------------------------------------
# Episodes.

CROSSING = [(1.5, -1.4, 0.0, 1.0, 0.09)]
"""A robot that crosses the straight way at x = 1.5 just as the car gets there."""


def _episode(planner_name, robots=CROSSING, motion="constant", seed=0, limit=6.0, **kw):
    sc = _scene(robots)
    car = episode.car_of(sc)
    p = planners.make(planner_name, car, BOUND, seed=seed, generations=3)
    return episode.run(sc, p, episode.EpisodeSettings(motion=motion, time_limit=limit, **kw),
                       seed=seed)


def test_the_hga_goes_round_a_crossing_robot_and_the_frozen_plan_does_not():
    """The straight line collides in time: the time-aware HGA reaches the goal without
    contact, later than 3 s (the straight line's time); the exact planner among robots
    frozen at each frame drives into the robot."""
    hga = _episode("hga")
    assert hga.outcome == "reached" and hga.contact is None
    assert 3.0 < hga.time  # (before the time limit: reached)
    frozen = _episode("exact")
    assert frozen.outcome == "collided" and frozen.contact["robot"] == 0


def test_the_episode_file_has_the_models_keys(tmp_path):
    ep = _episode("hga", limit=0.5)
    d = json.loads(json.dumps(ep.to_dict()))
    for key in ("dt", "speed", "robot", "goal", "tolerance", "planner", "motion", "seed",
                "frames", "outcome", "time"):
        assert key in d
    assert set(d["robot"]) >= {"radius", "min_turn_radius", "car"}
    assert d["outcome"] == "timeout" and d["time"] == pytest.approx(0.5)
    f = d["frames"][1]
    assert f["t"] == pytest.approx(1 / 60) and len(f["ego"]) == 4 and f["ego"][3] == 1
    assert f["obstacles"][0][:4] == pytest.approx([1.5, -1.4 + 1 / 60, 0.0, 1.0])
    assert f["plan_ms"] > 0
    assert f["ego"][0] == pytest.approx(1 / 60, abs=0.02)  # one frame's driving, 1/60 m


def test_constant_motion_reflects_at_the_field():
    pos, vel = episode._reflect(np.array([[0.05, 1.0]]), np.array([[-1.0, 0.0]]),
                                np.array([0.09]), (0.0, 2.0, 0.0, 2.0))
    assert pos[0].tolist() == pytest.approx([0.13, 1.0]) and vel.tolist() == [[1.0, 0.0]]


def test_chase_and_random_keep_their_bounds():
    s = episode.EpisodeSettings(motion="chase", accel=2.0, max_speed=1.5)
    vel = episode._steer(np.array([[0.0, 0.0]]), np.array([[1.0, 0.0]]), (0.0, 0.0), s,
                         np.random.default_rng(0))
    assert vel[0].tolist() == pytest.approx([-2.0 / 60, 0.0])  # accel dt toward the car
    r = dataclasses.replace(s, motion="random")
    a = episode._steer(np.ones((50, 2)), np.zeros((50, 2)), (0, 0), r, np.random.default_rng(1))
    b = episode._steer(np.ones((50, 2)), np.zeros((50, 2)), (0, 0), r, np.random.default_rng(1))
    assert np.array_equal(a, b)
    change = np.hypot(*(a - 1.0).T)
    assert change.max() <= 2.0 / 60 + 1e-12 and change.min() > 0
    assert np.hypot(*a.T).max() <= 1.5 + 1e-12


def test_bad_episode_settings_are_one_line():
    with pytest.raises(ValueError, match="motion: must be one of"):
        episode.EpisodeSettings(motion="bounce")
    with pytest.raises(ValueError, match="dt: must be a number > 0"):
        episode.EpisodeSettings(dt=0.0)


def test_an_animation_of_an_episode(tmp_path):
    """Half a second (30 frames): one image every 6 frames and the last, a GIF that opens."""
    from PIL import Image

    from hga_jax.host.plots.episode_animation import animate

    sc = _scene(CROSSING)
    p = planners.make("hga", episode.car_of(sc), BOUND, seed=0, generations=3)
    ep = episode.run(sc, p, episode.EpisodeSettings(time_limit=0.5), keep_plans=True)
    assert len(ep.plans) == len(ep.frames) == 30
    assert animate(ep, ep.plans, str(tmp_path / "e.gif")) == 6
    with Image.open(tmp_path / "e.gif") as im:
        assert im.n_frames >= 2 and im.size[0] > 100


SCENE = """name = "crossing"
[robot]
radius = 0.09
min_turn_radius = 0.2
speed = 1.0
[start]
x = 0.0
y = 0.0
heading_deg = 0.0
[goal]
x = 3.0
y = 0.0
heading_deg = 0.0
[[obstacles]]
x = 1.5
y = -1.4
vx = 0.0
vy = 1.0
"""


def test_the_episode_command(tmp_path, capsys):
    """It writes episode.json (reached, no contact) and, asked, episode.gif; a second run
    into the same folder is refused without --force; a bad flag is one line, exit 2."""
    from hga_jax.host.cli import main

    scene = tmp_path / "crossing.toml"
    scene.write_text(SCENE)
    out = tmp_path / "ep"
    args = ["episode", str(scene), "--generations", "3", "--bound", str(BOUND), "--out", str(out),
            "--time-limit", "6", "--no-cache"]
    assert main(args + ["--animate"]) == 0
    d = json.loads((out / "episode.json").read_text())
    assert d["outcome"] == "reached" and d["contact"] is None and d["planner"] == "hga"
    assert (out / "episode.gif").stat().st_size > 1000
    assert "hga: reached at" in capsys.readouterr().out
    assert main(args) == 2
    assert "already holds an episode.json" in capsys.readouterr().err
    assert main(["episode", str(scene), "--dt", "-1", "--out", str(tmp_path / "x")]) == 2
    assert capsys.readouterr().err.strip() == (
        "hga-jax: error: command line: --dt: must be a number > 0, got -1.0")


def test_the_sampler_takes_the_direct_path_when_it_is_clear_and_repeats_its_seed():
    """No robot near: the straight line (3 m), found among the direct paths; a seed gives
    the same plans twice."""
    sc = _scene([(1.5, 2.0, 0.0, 0.0, 0.09)])
    car = episode.car_of(sc)
    p = planners.make("sampler", car, BOUND, seed=3)
    view = planners.View((0.0, 0.0, 0.0), (3.0, 0.0, 0.0), np.array([[1.5, 2.0, 0.0, 0.0, 0.09]]))
    got = p.plan(view)
    assert got.status == "clear" and got.length == pytest.approx(3.0, abs=1e-5)
    a = _episode("sampler", limit=1.0, seed=2)
    b = _episode("sampler", limit=1.0, seed=2)
    assert [f["ego"] for f in a.frames] == [f["ego"] for f in b.frames]


def test_a_deadline_sets_each_frames_generations():
    """With a deadline in ms the frame runs from 1 to ``generations`` generations as its time
    model says fit: all of them for a deadline nothing reaches (the same plans as the
    replanner without one), one for a deadline nothing meets; the plan says how many ran."""
    loose = Replanner(CAR, BOUND, generations=3, seed=5, deadline_ms=1e6)
    tight = Replanner(CAR, BOUND, generations=3, seed=5, deadline_ms=1e-3)
    plain = Replanner(CAR, BOUND, generations=3, seed=5)
    for rp in (loose, tight):
        rp.warm_up()
    assert (loose.budget(), tight.budget(), plain.budget()) == (3, 1, 3)
    for f in range(3):
        obs = observation([0.1 * f, 0, 0], [3, 0, 0], ROBOTS, BOUND)
        a, b, c = loose.step(obs)[0], tight.step(obs)[0], plain.step(obs)[0]
        assert (a.generations, b.generations, c.generations) == (3, 1, 3)
        assert (a.length, a.perm.tolist(), a.labels.tolist()) == (
            c.length, c.perm.tolist(), c.labels.tolist())
    with pytest.raises(ValueError, match="deadline_ms"):
        Replanner(CAR, BOUND, deadline_ms=0.0)
