"""Episodes as one compiled program (hga_jax/loop/batch.py): the car's way along a decoded
plan against the host's poses, and whole episodes against the host's episode loop."""
from __future__ import annotations

import math

import jax
import numpy as np
import pytest

from hga_jax import load_scenario, scenario_from_dict
from hga_jax.host.poses import at as poses_at
from hga_jax.loop import batch, episode, planners
from hga_jax.loop.replanner import _segments
from hga_jax.model.decode import decode_batch


def _wrap(x):
    return (np.asarray(x) + np.pi) % (2 * np.pi) - np.pi


def test_the_way_along_a_decoded_plan_is_the_hosts():
    """Poses every 1 cm along decoded tight-rope paths (robots wrapped both ways) equal the
    host's poses of the same pieces, to float32 rounding; beyond the end, the goal pose."""
    sc = load_scenario("configs/scenarios/robocup_paper.toml")
    sa = sc.arrays(np.float32)
    rng = np.random.default_rng(3)
    n = sc.n
    perm = np.stack([rng.permutation(n) for _ in range(6)]).astype(np.int32)
    labels = rng.integers(-1, 2, (6, n + 2)).astype(np.int32)
    labels[:, 0] = rng.choice([-1, 1], 6)
    labels[:, -1] = rng.choice([-1, 1], 6)
    d = jax.device_get(decode_batch(sa, perm, labels))
    way = jax.jit(batch.along)
    for k in range(6):
        segs = _segments(d.circles[k], d.arcs[k], d.lines[k], d.count[k])
        total = sum(seg["radius"] * abs(seg["sweep"]) if seg["type"] == "arc" else
                    math.dist(seg["start"], seg["end"]) for seg in segs)
        u = np.append(np.arange(0.0, total, 0.01), total + 0.5).astype(np.float32)
        got, length = way(d.circles[k], d.arcs[k], d.lines[k], d.count[k], u)
        host = poses_at(segs, u)
        assert float(length) == pytest.approx(total, rel=1e-5)
        np.testing.assert_allclose(np.asarray(got)[:, :2], host[:, :2], atol=2e-4)
        assert np.max(np.abs(_wrap(np.asarray(got)[:, 2] - host[:, 2]))) < 2e-3
        np.testing.assert_allclose(np.asarray(got)[-1], [*sc.goal[:2], _wrap(sc.goal[2])],
                                   atol=2e-4)


def _scene(robots, name="batch"):
    d = {"name": name, "robot": {"radius": 0.09, "min_turn_radius": 0.2, "speed": 1.0},
         "start": {"x": 0.5, "y": 1.0, "heading_deg": 0.0},
         "goal": {"x": 2.5, "y": 1.0, "heading_deg": 0.0},
         "obstacles": [{"x": x, "y": y, "vx": vx, "vy": vy, "radius": 0.09}
                       for x, y, vx, vy in robots]}
    return scenario_from_dict(d, name)


@pytest.mark.slow
def test_batched_episodes_end_as_the_hosts():
    """A robot that leaves the line: reached after exactly the 2 m at 1 m/s (121 frames),
    as the host's loop; a robot that chases the car faster than it drives: collided, as
    the host's, at nearly the same moment; four episodes in one call, one program."""
    leave = _scene([(1.5, 1.0, 0.0, 0.3)], "leave")
    chase = _scene([(2.0, 1.6, 0.0, 0.0)], "chase")
    s = episode.EpisodeSettings(time_limit=4.0)
    hunt = episode.EpisodeSettings(time_limit=4.0, motion="chase", max_speed=2.5, accel=8.0)
    got = batch.run_batch(batch.scenes([leave, leave], [0, 1]), s)
    assert list(got.outcome) == [1, 1]
    np.testing.assert_allclose(got.time, 2.0, atol=1e-5)
    assert list(got.frames) == [121, 121]
    car = episode.car_of(leave)
    host = episode.run(leave, planners.make("hga", car, 1, seed=0), s, seed=0)
    assert host.outcome == "reached" and len(host.frames) == 121
    caught = batch.run_batch(batch.scenes([chase], [0]), hunt)
    ref = episode.run(chase, planners.make("hga", car, 1, seed=0), hunt, seed=0)
    assert ref.outcome == "collided" and batch.OUTCOMES[int(caught.outcome[0])] == "collided"
    assert float(caught.time[0]) == pytest.approx(ref.time, abs=0.05)
    assert int(caught.robot[0]) == 0 and float(caught.overlap[0]) > 0
