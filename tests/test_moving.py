"""Robots that move (hga_jax/model/in_time/clearance.py): the tests in time against cases computed by
hand, and their soundness: no check calls feasible a path that comes too close to a
moving robot at the moment the car is there.

- ``chord_reach`` and ``segment_hits`` on a straight path and on arcs, with collision
  times and least distances worked out by hand (or, for an arc whose minimum has no closed
  form, by the rigorous dense bracket of experiments/fuzz_moving.py);
- on random moving scenes, random chromosomes of the three car models (the tight rope,
  free turns, the Reeds–Shepp car) and scenes made so that a robot grazes a path by
  micrometres: neither the float32 fitness, nor the float64 decoder, nor the float64
  path check of the result files calls feasible a path that the dense check shows
  closer than ``R - 1e-6`` m (float32: ``R - 2e-5`` m, its tolerance being 1e-5 m) to a
  moving robot (experiments/fuzz_moving.py; 100,000 chromosomes are marked slow);
- with every velocity 0 the arrays of every car model are those of the scene without
  velocities, bit for bit, and so are the violations.

The dense check is exact where it matters: every sample is a point of the path at the
car's time there, so a sample closer than ``R - margin`` proves a collision; a sampling
``s`` m apart can miss the least distance by up to ``(1 + |V| / speed) s / 2`` (the
distance changes by at most ``speed + |V|`` per second), and the bracket removes that
miss by branch and bound on the same bound (experiments/fuzz_moving.py, ``clearance``):
it decides exactly whether a path comes closer than each margin.
"""
from __future__ import annotations

import dataclasses
import importlib.util
import math
import sys
from pathlib import Path

import jax
import numpy as np
import pytest

from hga_jax import scenario_from_dict
from hga_jax.model import car_model
from hga_jax.model.fitness import evaluate as _evaluate
from hga_jax.model.in_time import clearance
from hga_jax.model.path import decode64

evaluate = jax.jit(_evaluate, static_argnames="collision")
ROOT = Path(__file__).resolve().parents[1]
R = 0.2  # the model radius of every robot below: max(rho 0.2, 0.09 + 0.09)


def _fuzz():
    spec = importlib.util.spec_from_file_location(
        "fuzz_moving", ROOT / "experiments" / "fuzz_moving.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up
    spec.loader.exec_module(module)
    return module


fuzz = _fuzz()


def _scene(obstacles, speed: float = 1.0, start=(0.0, 0.0, 0.0), goal=(3.0, 0.0, 0.0)):
    return scenario_from_dict({
        "name": "hand", "robot": {"radius": 0.09, "min_turn_radius": R, "speed": speed},
        "start": {"x": start[0], "y": start[1], "heading_deg": start[2]},
        "goal": {"x": goal[0], "y": goal[1], "heading_deg": goal[2]},
        "obstacles": obstacles}, "hand")


AWAY = (-5.0, -5.0, 0.0)
"""A start pose for the scenes of hand-made segments (the check reads only the segments,
the robots and the car's speed; the loader wants the start outside every robot)."""
LINE = [{"type": "line", "start": [0.0, 0.0], "end": [3.0, 0.0]}]
"""The straight path y = 0 from (0, 0) to (3, 0): at speed 1 the car is at (t, 0)."""


# ---------------------------------------------------------------------------
# By hand: a point driven along a chord against a centre moving at constant velocity.

@pytest.mark.parametrize(("o", "v", "t0", "h", "d2"), [
    # crosses the path where the car is at t = 1.5: they meet
    ((1.5, -1.5), (0.0, 1.0), 0.0, 3.0, 0.0),
    # crosses 1.5 s late: relative (t - 1.5, 3 - t), least at t = 2.25, (0.75, 0.75)
    ((1.5, -3.0), (0.0, 1.0), 0.0, 3.0, 1.125),
    # alongside at the car's velocity: 3.5 m apart all the way (no relative motion)
    ((3.5, 0.0), (1.0, 0.0), 0.0, 3.0, 12.25),
    # standing 2 m beyond the end: least at the end
    ((5.0, 0.0), (0.0, 0.0), 0.0, 3.0, 4.0),
    # entered at t0 = 2, the robot already at (-3, 0) and going away: least at the start
    ((-1.0, 0.0), (-1.0, 0.0), 2.0, 3.0, 9.0),
    # the car at speed 2 ((2t, 0), h = 1.5) against (1 + 0.5 t, 0.5): level at t = 2/3
    ((1.0, 0.5), (0.5, 0.0), 0.0, 1.5, 0.25),
])
def test_chord_reach_by_hand(o, v, t0, h, d2):
    got = clearance.chord_reach(0.0, 0.0, 3.0, 0.0, t0, h, o[0], o[1], v[0], v[1])
    assert got == pytest.approx(d2, abs=1e-12)


def test_chord_reach_broadcasts_over_robots_and_chords():
    ox = np.array([1.5, 1.5])[:, None]
    oy = np.array([-1.5, -3.0])[:, None]
    got = clearance.chord_reach(np.array([0.0, 0.0]), 0.0, np.array([3.0, 1.5]), 0.0,
                             np.array([0.0, 0.0]), np.array([3.0, 1.5]), ox, oy, 0.0, 1.0)
    # the second chord stops at (1.5, 0) at t = 1.5: against the late robot (1.5, -1.5) then
    np.testing.assert_allclose(got, [[0.0, 0.0], [1.125, 2.25]], atol=1e-12)


# ---------------------------------------------------------------------------
# By hand: the float64 path check over result-file segments.

def _moving(x, y, vx, vy):
    return {"x": x, "y": y, "vx": vx, "vy": vy}


def test_a_robot_crossing_the_straight_path_hits_it_at_the_known_time():
    sc = _scene([_moving(1.5, -1.5, 0.0, 1.0)])
    assert clearance.segment_hits(sc, LINE) == [(0, 0)]
    (a,) = clearance.closest_approach(sc, LINE, spacing=1e-3)
    assert a.time == pytest.approx(1.5, abs=1e-9) and a.distance == pytest.approx(0.0, abs=1e-9)
    assert a.clearance == pytest.approx(-R, abs=1e-9)
    # the same path in two pieces: the second entered at t = 1
    two = [{"type": "line", "start": [0.0, 0.0], "end": [1.0, 0.0]},
           {"type": "line", "start": [1.0, 0.0], "end": [3.0, 0.0]}]
    assert clearance.segment_hits(sc, two) == [(1, 0)]
    assert clearance.at(sc, (1.5, 0.0), 1.5) == [(0, -R)]


def test_a_robot_crossing_late_misses_by_the_known_distance():
    sc = _scene([_moving(1.5, -3.0, 0.0, 1.0)])
    assert clearance.segment_hits(sc, LINE) == []
    (a,) = clearance.closest_approach(sc, LINE, spacing=1e-3)
    assert a.time == pytest.approx(2.25, abs=1e-9)
    assert a.distance == pytest.approx(math.sqrt(1.125), abs=1e-9)


@pytest.mark.parametrize(("delta", "hit"), [(-1e-6, True), (1e-6, False), (-5e-8, False),
                                            (1e-3, False), (-1e-3, True)])
def test_a_robot_overtaken_at_a_known_least_distance(delta, hit):
    """The robot at (1 + 0.5 t, R + delta): the car at (t, 0) draws level at t = 2, the
    least distance ``R + delta``; a hit iff closer than ``R - 1e-7`` (float64 tolerance)."""
    sc = _scene([_moving(1.0, R + delta, 0.5, 0.0)])
    assert (clearance.segment_hits(sc, LINE) == [(0, 0)]) is hit
    lower, upper = fuzz.clearance(sc, LINE)
    assert lower[0] == pytest.approx(delta, abs=2e-7)
    assert upper[0] == pytest.approx(delta, abs=1e-12)


def test_the_cars_speed_times_the_meeting():
    """The robot at (1 + t, 0.1): at speed 1 the car keeps 1 m behind it (no hit); at
    speed 2 the car, at (2 t, 0), draws level at t = 1, 0.1 m away (a hit)."""
    slow = _scene([_moving(1.0, 0.1, 1.0, 0.0)], speed=1.0)
    fast = _scene([_moving(1.0, 0.1, 1.0, 0.0)], speed=2.0)
    assert clearance.segment_hits(slow, LINE) == []
    assert clearance.segment_hits(fast, LINE) == [(0, 0)]
    (a,) = clearance.closest_approach(fast, LINE, spacing=1e-3)
    assert a.time == pytest.approx(1.0, abs=1e-9) and a.clearance == pytest.approx(0.1 - R)


def _alongside(d: float, speed: float, clockwise: bool):
    """The quarter turn of radius 1 about the origin from (1, 0) (counter-clockwise) or
    from (0, 1) (clockwise), driven at ``speed``, and a robot that moves at the car's
    velocity at the turn's middle, ``d`` from the car then, on the outer side: relative to
    it the car is at ``r (sin phi - phi), d + r (1 - cos phi)`` (tangent, outward), so the
    least distance is ``d``, at the middle."""
    th = math.pi / 4
    p = np.array([math.cos(th), math.sin(th)])
    tangent = np.array([-p[1], p[0]]) * (-1.0 if clockwise else 1.0)
    vel = speed * tangent
    o = p + d * p - (th / speed) * vel
    seg = ({"type": "arc", "center": [0.0, 0.0], "radius": 1.0, "start_angle": math.pi / 2,
            "sweep": -math.pi / 2} if clockwise else
           {"type": "arc", "center": [0.0, 0.0], "radius": 1.0, "start_angle": 0.0,
            "sweep": math.pi / 2})
    return _scene([_moving(*o, *vel)], speed, start=AWAY, goal=(5.0, 5.0, 0.0)), [seg]


@pytest.mark.parametrize("clockwise", [False, True])
@pytest.mark.parametrize(("delta", "hit"), [(-1e-6, True), (1e-4, False), (-1e-4, True),
                                            (0.05, False)])
def test_an_arc_against_a_robot_alongside(clockwise, delta, hit):
    """The least distance is ``R + delta`` by hand; the check cuts the arc into chords
    whose error is at most ``r (2 pi / 1024)^2 / 8 = 4.7e-6`` m here, so ``R - 1e-6`` is a
    hit and ``R + 1e-4`` none (between, it may call a hit: conservative)."""
    sc, segs = _alongside(R + delta, 1.5, clockwise)
    assert (clearance.segment_hits(sc, segs) == [(0, 0)]) is hit
    lower, upper = fuzz.clearance(sc, segs)
    assert upper[0] == pytest.approx(delta, abs=1e-12)
    assert lower[0] == pytest.approx(delta, abs=2e-7)
    (a,) = clearance.closest_approach(sc, segs, spacing=1e-4)
    assert a.time == pytest.approx((math.pi / 4) / 1.5, abs=1e-4)
    assert delta - 1e-9 <= a.clearance <= delta + 1e-6  # samples miss the least by < 1e-6


def test_an_arc_against_robots_on_its_inner_side_by_dense_sampling():
    """Robots inside the turn, moving along it (slower, faster or against the car): at the
    car's time at angle ``th`` the robot is ``d`` inside and their relative velocity is
    along the turn, a stationary point of the distance but not a minimum by hand (the turn
    curves toward the robot). The check agrees with the dense bracket wherever that is
    farther than the chord error bound (4.7e-6 m) from ``R``, and never calls clear a
    piece that the bracket shows closer than ``R - 1e-7``."""
    rng = np.random.default_rng(11)
    seen = {True: 0, False: 0}
    segs = [{"type": "arc", "center": [0.0, 0.0], "radius": 1.0, "start_angle": 0.0,
             "sweep": math.pi / 2}]
    while min(seen.values()) < 8:
        speed = rng.uniform(1.0, 2.0)
        th = rng.uniform(0.2, 1.3)
        p = np.array([math.cos(th), math.sin(th)])
        beta = rng.choice([-1.0, 1.0]) * rng.uniform(0.3, 1.5)  # the robot's speed along
        if (speed - beta) ** 2 < 0.25 * speed ** 2:
            continue  # the car would curve onto it: no stationary point to graze at
        vel = beta * np.array([-p[1], p[0]])
        d = R + rng.choice([-1.0, 1.0]) * 10.0 ** rng.uniform(-5.0, -1.5)
        o = p - d * p - (th / speed) * vel
        sc = _scene([_moving(*o, *vel)], speed, start=AWAY, goal=(5.0, 5.0, 0.0))
        lower, upper = fuzz.clearance(sc, segs, decide=(1e-7,))
        assert upper[0] <= d - R + 1e-12  # it passes d away at th (or closer elsewhere)
        hit = clearance.segment_hits(sc, segs) == [(0, 0)]
        if upper[0] < -1e-7:
            assert hit
        elif lower[0] > 5e-6:
            assert not hit
        seen[bool(upper[0] < 0)] += 1


def _round_the_robot(clockwise: bool):
    """The robot moves up at 1 m/s from (0, -1): at t = 1 it is at the origin. The car
    (speed 1) drives an arc of radius R round the origin, from angle 0.3 to -0.3 (clockwise)
    or from -0.3 to 0.3 (counter-clockwise), through angle 0 at t = 1 (a straight line
    of 0.94 m brings it to the arc's start at t = 0.94). Relative to the robot, at
    ``tau = t - 1`` the car is at squared distance ``R^2 - 2 R tau (u . V) + tau^2`` with
    ``u . V = sin(theta)``, ``theta = -+ tau / R``: ``R^2 + 2 R tau sin(tau / R) + tau^2 >= R^2``
    clockwise (it touches at t = 1 and draws away: clear), ``R^2 - tau^2 + O(tau^4)``
    counter-clockwise (it cuts in: a hit on the arc)."""
    sign = -1.0 if clockwise else 1.0
    a0 = -sign * 0.3
    start = np.array([R * math.cos(a0), R * math.sin(a0)])
    tangent = sign * np.array([-math.sin(a0), math.cos(a0)])
    before = start - 0.94 * tangent
    segs = [{"type": "line", "start": before.tolist(), "end": start.tolist()},
            {"type": "arc", "center": [0.0, 0.0], "radius": R, "start_angle": a0,
             "sweep": sign * 0.6}]
    return _scene([_moving(0.0, -1.0, 0.0, 1.0)], 1.0, start=AWAY, goal=(5.0, 5.0, 0.0)), segs


@pytest.mark.parametrize("clockwise", [True, False])
def test_an_arc_round_a_moving_robot_where_it_is_then(clockwise):
    """An arc on the robot's circle where it stands at t = 1 (as a wrapped moving robot's
    circle stands in the tables) is judged against that robot by its own bound: touching
    and drawing away is clear (a chord test would call the touch a hit), cutting in a hit."""
    sc, segs = _round_the_robot(clockwise)
    hits = clearance.segment_hits(sc, segs)
    lower, upper = fuzz.clearance(sc, segs, decide=(1e-7,))
    if clockwise:
        assert hits == [] and clearance.moments_wrapped(sc, segs) == {0: pytest.approx(1.0)}
        assert lower[0] >= -2e-7 and upper[0] <= 1e-9  # the touch at t = 1 (bracket 1e-7)
    else:
        assert (1, 0) in hits
        assert upper[0] < -1e-3  # about tau^2 / 2R = 9 mm at the arc's end


# ---------------------------------------------------------------------------
# The device fitness and the float64 decoder on a path decoded from a chromosome.

@pytest.mark.parametrize(("robot", "count"), [(_moving(1.5, -1.5, 0.0, 1.0), 1),
                                              (_moving(1.5, -3.0, 0.0, 1.0), 0)])
def test_the_fitness_counts_the_robot_crossing_the_straight_path(robot, count):
    """The chromosome that touches nothing with both left circles: the straight line y = 0
    (length 3), hit by the crossing robot, missed by the late one (its circle a point of
    the tables: nothing to solve for where it stands there)."""
    sc = dataclasses.replace(_scene([robot]), wrap_moving="never")
    perm, labels = np.zeros((1, 1), np.int32), np.array([[-1, 0, -1]], np.int32)
    e = evaluate(sc.search_arrays(np.float32, "full"), perm, labels, "full")
    assert float(e.length[0]) == pytest.approx(3.0, abs=1e-6)
    assert int(e.violations[0]) == count  # (the float64 decoder's: the fuzz below)


# ---------------------------------------------------------------------------
# Soundness on random scenes, all three car models.

LANE_MODES = {"tight-rope": ("at-pass", "never"), "free": ("given", "never"),
              "reeds-shepp": ("given", "never")}
"""The placements of the moving robots' circles of the default lane's two scenes per car
model (experiments/fuzz_moving.py, ``MODES``; slow: every one on every model but for the
Reeds–Shepp car's ``at-best``, which solves each scene in time first)."""


@pytest.mark.parametrize("model", fuzz.MODELS)
def test_no_check_calls_a_colliding_path_feasible(model):
    """Two random scenes of 9 robots (5 moving) per car model, 64 random chromosomes
    each and 3 scenes made from each to graze a path by micrometres (8 chromosomes each):
    no false feasible, and the fuzz sees both feasible paths and paths colliding in time."""
    tallies = fuzz.fuzz(2 * (64 + 3 * fuzz.GRAZE_BATCH), seed=7, rows=64, models=(model,),
                        shapes=((9, 5),), graze_count=3, modes=LANE_MODES[model],
                        exact_select=False)
    t = tallies[model]
    assert t.false == dict.fromkeys(fuzz.CHECKS, 0), t.examples[:3]
    assert t.undecided == dict.fromkeys(fuzz.CHECKS, 0)
    assert t.sampled_below == 0  # closest_approach never below the bracket
    assert t.feasible["float64"] > 0 and t.colliding > 0


@pytest.mark.slow
def test_no_false_feasible_among_100000_chromosomes():
    """The fuzz of experiments/fuzz_moving.py at 100,002 chromosomes (33,334 per car model
    on scenes of 5-9 robots, 1-9 of them moving, every placement of their circles)."""
    tallies = fuzz.fuzz(100_002, seed=1)
    print("\n" + fuzz.report(tallies))
    for t in tallies.values():
        assert t.checked >= 100_002 // 3
        assert t.false == dict.fromkeys(fuzz.CHECKS, 0), t.examples[:3]
        assert t.undecided == dict.fromkeys(fuzz.CHECKS, 0)
        assert t.sampled_below == 0
        assert t.feasible["float64"] > 0 and t.colliding > 0 and t.boundary > 0


# ---------------------------------------------------------------------------
# The static part: every velocity 0 is the scene without velocities, bit for bit.

def _same_bits(a, b) -> None:
    la, ta = jax.tree.flatten(a)
    lb, tb = jax.tree.flatten(b)
    assert ta == tb
    for x, y in zip(la, lb):
        x, y = np.asarray(x), np.asarray(y)
        assert x.dtype == y.dtype and x.shape == y.shape
        assert x.tobytes() == y.tobytes()


@pytest.mark.parametrize("model", fuzz.MODELS)
def test_every_velocity_zero_is_the_still_scene_bit_for_bit(model):
    rng = np.random.default_rng(3)
    _, d = fuzz.scene(rng, fuzz.car_of(model), 7, 4)
    plain = {**d, "obstacles": [{k: v for k, v in o.items() if k not in ("vx", "vy")}
                                for o in d["obstacles"]]}
    zero = {**d, "robot": {**d["robot"], "speed": 1.7},
            "obstacles": [{**o, "vx": 0.0, "vy": -0.0} for o in plain["obstacles"]]}
    a, b = scenario_from_dict(plain, "plain"), scenario_from_dict(zero, "zero")
    c = dataclasses.replace(a, velocities=np.zeros((a.n, 2)))
    for s in (b, c):
        assert not s.has_motion and s.motion() is None
        assert s.circle_radii.tobytes() == a.model_radii.tobytes()
    cm = car_model.get(model)
    for dtype in (np.float32, np.float64):
        for s in (b, c):
            _same_bits(cm.search_arrays(s, dtype, "full"), cm.search_arrays(a, dtype, "full"))
            _same_bits(cm.decode_arrays(s), cm.decode_arrays(a))
    perm, labels, legs = fuzz.chromosomes(rng, model, a.n, 64)
    ref = decode64(a, perm, labels, "full", legs)
    for s in (b, c):
        _same_bits(decode64(s, perm, labels, "full", legs), ref)


def test_the_search_legs_see_a_crossing_robot_where_it_is_placed():
    """The per-leg table that seeding, the repair move and the guided move read (never the
    fitness) lists a robot that crosses the straight path as a blocker of the direct legs,
    where it stands when the car passes it, without charging those legs a violation (the
    guided move's score stays the static rules'); standing still off the path it blocks
    nothing, and under ``wrap_moving = "never"`` (a point no chromosome wraps) neither."""
    crossing = _scene([_moving(1.5, -1.5, 0.0, 1.0)])
    sa = crossing.search_arrays(np.float32, with_legs=True)
    direct = [(a, c) for a in (0, 1) for c in (2, 3)]
    assert any(bool(sa.legs.blockers[a, c, 0]) for a, c in direct)
    blocked = [(a, c) for a, c in direct if sa.legs.blockers[a, c, 0]]
    assert blocked and all(int(sa.legs.count[a, c]) == 1 and not sa.legs.bad[a, c]
                           for a, c in blocked)
    never = dataclasses.replace(crossing, wrap_moving="never")
    nl = never.search_arrays(np.float32, with_legs=True).legs
    assert not np.any(nl.blockers[..., 0])
    away = _scene([_moving(1.5, -1.5, 0.0, 0.0)])  # standing, off the path: no blocker
    al = away.search_arrays(np.float32, with_legs=True).legs
    assert not any(bool(al.blockers[a, c, 0]) for a, c in direct)
