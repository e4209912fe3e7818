"""The closed-form Dubins path (hga_jax.model.dubins) and the judge of peer paths
(hga_jax.peers.judge): end poses reached, lengths against the exact free-turn solver
and OMPL, hand-computed cases, and the judge's verdicts against the GA's own model."""
from __future__ import annotations

import math

import numpy as np
import pytest

from hga_jax.host.config import load_scenario, scenario_from_dict
from hga_jax.model.exact import solve
from hga_jax.model.path import evaluate_path, from_chromosome
from hga_jax.model import dubins
from hga_jax.peers.judge import judge_poses, judge_segments

PI = math.pi


def walk(p, segments):
    """Integrate a segment list from pose ``p``: ``(end pose, largest break)``, where a
    break is the position (m) or heading (rad) jump between consecutive pieces."""
    x, y, h = p
    worst = 0.0
    for s in segments:
        if s["type"] == "arc":
            (cx, cy), r, a0, sw = s["center"], s["radius"], s["start_angle"], s["sweep"]
            turn = math.copysign(PI / 2, sw)
            sx, sy, sh = cx + r * math.cos(a0), cy + r * math.sin(a0), a0 + turn
            ex, ey, eh = cx + r * math.cos(a0 + sw), cy + r * math.sin(a0 + sw), a0 + sw + turn
        else:
            (sx, sy), (ex, ey) = s["start"], s["end"]
            sh = eh = math.atan2(ey - sy, ex - sx)
        worst = max(worst, math.hypot(sx - x, sy - y), abs(math.remainder(sh - h, 2 * PI)))
        x, y, h = ex, ey, eh
    return (x, y, h), worst


def pose_error(a, b):
    return max(math.hypot(a[0] - b[0], a[1] - b[1]), abs(math.remainder(a[2] - b[2], 2 * PI)))


def random_pairs(seed, count, rho):
    """``count`` pose pairs 0 to 5 rho apart, random headings."""
    rng = np.random.default_rng(seed)
    for _ in range(count):
        p = (rng.uniform(-2, 2), rng.uniform(-2, 2), rng.uniform(-PI, PI))
        d, bearing = rng.uniform(0, 5 * rho), rng.uniform(-PI, PI)
        yield p, (p[0] + d * math.cos(bearing), p[1] + d * math.sin(bearing),
                  rng.uniform(-PI, PI))


def scene(start, goal, obstacles=(), field=None, r=0.09, rho=0.2):
    """A scenario from poses in metres and radians."""
    def pose(p):
        return {"x": float(p[0]), "y": float(p[1]), "heading_deg": math.degrees(p[2])}

    d = {"name": "t", "robot": {"radius": r, "min_turn_radius": rho}, "start": pose(start),
         "goal": pose(goal), "obstacles": [dict(o) for o in obstacles]}
    if field is not None:
        d["field"] = field
    return scenario_from_dict(d)


def arc(c, r, a0, sweep):
    return {"type": "arc", "center": list(c), "radius": r, "start_angle": a0, "sweep": sweep}


def line(a, b):
    return {"type": "line", "start": list(a), "end": list(b)}


# Dubins paths.

@pytest.mark.parametrize("rho", [0.2, 1.0])
def test_dubins_ends_at_the_goal_continuously(rho):
    words = set()
    for p, q in random_pairs(1, 200, rho):
        segs = dubins.shortest(p, q, rho)
        end, worst = walk(p, segs)
        assert pose_error(end, q) < 1e-9
        assert worst < 1e-9
        assert 1 <= len(segs) <= 3
        assert all(s["radius"] == rho for s in segs if s["type"] == "arc")
        assert sum(s["type"] == "line" for s in segs) <= 1
        assert dubins.length(p, q, rho) >= math.dist(p[:2], q[:2]) - 1e-12
        total = sum(rho * abs(s["sweep"]) if s["type"] == "arc" else
                    math.dist(s["start"], s["end"]) for s in segs)
        assert total == pytest.approx(dubins.length(p, q, rho), rel=1e-12, abs=1e-12)
        words.add("".join("S" if s["type"] == "line" else "LR"[s["sweep"] < 0] for s in segs))
    assert {"LSL", "RSR", "LSR", "RSL", "LRL", "RLR"} <= words


def test_dubins_hand_cases():
    rho = 0.5
    o = (0.0, 0.0, 0.0)
    assert dubins.shortest(o, o, rho) == []
    assert dubins.length(o, o, rho) == 0.0
    # straight ahead: one line
    segs = dubins.shortest(o, (3.0, 0.0, 0.0), rho)
    assert dubins.length(o, (3.0, 0.0, 0.0), rho) == pytest.approx(3.0, abs=1e-12)
    assert [s["type"] for s in segs] == ["line"]
    # U-turn to the pose 2 rho to the left, facing back: a half circle CCW round (0, rho)
    segs = dubins.shortest(o, (0.0, 2 * rho, PI), rho)
    assert dubins.length(o, (0.0, 2 * rho, PI), rho) == pytest.approx(PI * rho, abs=1e-12)
    assert len(segs) == 1 and segs[0]["center"] == pytest.approx([0.0, rho], abs=1e-15)
    assert segs[0]["sweep"] == pytest.approx(PI, abs=1e-12)
    assert segs[0]["start_angle"] == pytest.approx(-PI / 2, abs=1e-15)
    # the same to the right: clockwise round (0, -rho)
    segs = dubins.shortest(o, (0.0, -2 * rho, PI), rho)
    assert len(segs) == 1 and segs[0]["sweep"] == pytest.approx(-PI, abs=1e-12)
    assert segs[0]["center"] == pytest.approx([0.0, -rho], abs=1e-15)
    # a quarter turn left, then straight on: pi/2 rho + 1
    q = (rho, rho + 1.0, PI / 2)
    assert dubins.length(o, q, rho) == pytest.approx(PI / 2 * rho + 1.0, abs=1e-12)
    assert [s["type"] for s in dubins.shortest(o, q, rho)] == ["arc", "line"]
    # turning round on the spot: three arcs of pi/3, 5 pi/3, pi/3 (LRL or RLR)
    segs = dubins.shortest(o, (0.0, 0.0, PI), rho)
    assert dubins.length(o, (0.0, 0.0, PI), rho) == pytest.approx(7 * PI / 3 * rho, abs=1e-12)
    assert sorted(abs(s["sweep"]) for s in segs) == pytest.approx([PI / 3, PI / 3, 5 * PI / 3])
    with pytest.raises(ValueError):
        dubins.shortest(o, o, 0.0)


def test_dubins_is_the_exact_free_turn_optimum():
    rho = 0.2
    for p, q in random_pairs(2, 20, rho):
        sc = scene(p, q, rho=rho)
        exact = solve(sc, turns="free").length
        assert dubins.length(sc.start, sc.goal, rho) == pytest.approx(exact, rel=1e-9, abs=1e-12)


def test_dubins_matches_ompl():
    pytest.importorskip("ompl")
    from ompl import base as ob

    for rho in (0.15, 1.3):
        space = ob.DubinsStateSpace(rho, False)
        s1, s2 = space.allocState(), space.allocState()
        for p, q in random_pairs(3, 100, rho):
            for st, (x, y, h) in ((s1, p), (s2, q)):
                st.setX(x)
                st.setY(y)
                st.setYaw(h)
            assert dubins.length(p, q, rho) == pytest.approx(space.distance(s1, s2), abs=1e-9)


# The judge.

START, GOAL = (0.0, 0.0, 0.0), (2.0, 0.0, 0.0)
STRAIGHT = [line((0.0, 0.0), (2.0, 0.0))]


@pytest.mark.parametrize("dy, feasible", [
    (0.0, False), (0.1, False), (0.2 - 1e-6, False),  # through the model circle (R = 0.2 m)
    (0.2, True),  # tangent to it
    (0.2 + 1e-6, True), (-0.2 - 1e-6, True),  # beside it
])
def test_judge_a_line_against_an_obstacle(dy, feasible):
    sc = scene(START, GOAL, [{"x": 1.0, "y": dy}])
    j = judge_segments(sc, STRAIGHT)
    assert j.length == pytest.approx(2.0, abs=1e-15)
    assert j.gaps == 0 and j.segments == STRAIGHT
    assert j.feasible is feasible
    assert j.violations == (0 if feasible else 1)


def test_judge_arcs_above_half_a_circle():
    """3/4 circles from the bottom of a circle: counter-clockwise through the right, the
    top and the left, or clockwise through the left, the top and the right. An obstacle
    beside a quarter of the circle is a hit of the arcs that sweep that quarter only."""
    r = 0.5  # = rho: obstacles of radius 0.01 have model radius 0.5
    ccw = [arc((0.0, 0.0), r, -PI / 2, 1.5 * PI)]  # (0, -r) heading 0 to (-r, 0) heading -pi/2
    cw = [arc((0.0, 0.0), r, -PI / 2, -1.5 * PI)]  # (0, -r) heading pi to (r, 0) heading -pi/2
    for deg, in_ccw, in_cw in ((45, True, True), (90, True, True), (-45, True, False),
                               (-135, False, True)):
        a = math.radians(deg)
        q = {"x": 0.99 * math.cos(a), "y": 0.99 * math.sin(a), "radius": 0.01}
        for segs, goal, hit in ((ccw, (-r, 0.0, -PI / 2), in_ccw), (cw, (r, 0.0, -PI / 2), in_cw)):
            start = (0.0, -r, 0.0 if segs is ccw else PI)
            j = judge_segments(scene(start, goal, [q], rho=r), segs)
            assert j.gaps == 0 and j.length == pytest.approx(1.5 * PI * r, abs=1e-15)
            assert j.violations == int(hit), (deg, segs is ccw)


def test_judge_an_arc_on_a_model_circle_is_no_hit():
    # the arc runs on the obstacle's model circle itself (R = rho = 0.5)
    sc = scene((0.0, -0.5, 0.0), (-0.5, 0.0, -PI / 2), [{"x": 0.0, "y": 0.0, "radius": 0.01}],
               rho=0.5)
    assert judge_segments(sc, [arc((0.0, 0.0), 0.5, -PI / 2, 1.5 * PI)]).feasible


def test_judge_breaks():
    sc = scene(START, GOAL)
    assert judge_segments(sc, STRAIGHT) == (2.0, 0, STRAIGHT, 0)
    j = judge_segments(sc, [line((0.0, 0.0), (1.0, 0.0)), line((1.1, 0.0), (2.0, 0.0))])
    assert j.gaps == 1 and j.violations == 1 and not j.feasible
    j = judge_segments(sc, [line((0.0, 0.0), (1.0, 0.0)), line((1.0, 0.0), (1.9, 0.0))])
    assert j.gaps == 1  # stops short of the goal
    j = judge_segments(sc, [line((0.1, 0.0), (2.0, 0.0))])
    assert j.gaps == 1  # starts off the start
    j = judge_segments(sc, [])
    assert j.gaps == 1 and j.length == 0.0
    # a kink: the second line leaves in another direction
    bent = (2.0, 0.5, math.atan2(0.5, 1.0))
    j = judge_segments(scene(START, bent), [line((0.0, 0.0), (1.0, 0.0)),
                                            line((1.0, 0.0), (2.0, 0.5))])
    assert j.gaps == 1 and j.violations == 1
    # a wrong heading at the goal
    assert judge_segments(scene(START, (2.0, 0.0, 1e-3)), STRAIGHT).gaps == 1
    assert judge_segments(scene(START, (2.0, 0.0, 1e-7)), STRAIGHT).gaps == 0
    # an arc that turns the wrong way at its start
    j = judge_segments(scene((0.0, 0.0, PI), (0.0, 0.4, 0.0)), [arc((0.0, 0.2), 0.2, -PI / 2, PI)])
    assert j.gaps == 2  # heading pi given, 0 found; then pi found at the end, 0 asked
    # pieces without a direction (a line of 1e-9 m, an arc of sweep 0) pass the heading on
    j = judge_segments(sc, [line((0.0, 0.0), (1.0, 0.0)), line((1.0, 0.0), (1.0, 1e-9)),
                            arc((1.0, 0.2), 0.2, -PI / 2, 0.0), line((1.0, 0.0), (2.0, 0.0))])
    assert j.gaps == 0 and j.feasible and j.length == pytest.approx(2.0, abs=1e-8)
    # no motion at all, start equal to goal
    assert judge_segments(scene(START, START), []) == (0.0, 0, [], 0)


def test_judge_the_kept_field():
    field = {"xmin": 0.0, "xmax": 3.0, "ymin": 0.0, "ymax": 2.0, "keep_inside": True}
    sc = scene((2.5, 1.0, 0.0), (2.5, 1.5, PI), field=field)  # inner box x <= 2.91
    inside = [arc((2.5, 1.25), 0.25, -PI / 2, PI)]  # reaches x = 2.75
    assert judge_segments(sc, inside).feasible
    out = [line((2.5, 1.0), (2.8, 1.0)), arc((2.8, 1.25), 0.25, -PI / 2, PI),  # x = 3.05
           line((2.8, 1.5), (2.5, 1.5))]
    j = judge_segments(sc, out)
    assert j.gaps == 0 and j.violations == 1
    assert j.length == pytest.approx(0.6 + 0.25 * PI, abs=1e-12)
    j = judge_segments(sc, [line((2.5, 1.0), (2.95, 1.0))])
    assert j.violations == 1 + 1  # the line leaves the field, and the goal is not reached


def test_judge_poses():
    sc = scene((0.0, 0.0, 0.0), (1.0, 1.0, PI / 2), [{"x": 3.0, "y": 3.0}])
    via = (0.5, -0.5, 0.0)
    j = judge_poses(sc, [sc.start, via, sc.goal])
    assert j.feasible and j.gaps == 0
    assert j.length == pytest.approx(dubins.length(sc.start, via, 0.2)
                                     + dubins.length(via, sc.goal, 0.2), rel=1e-12)
    j = judge_poses(sc, [sc.start, sc.goal])
    assert j.feasible and j.length == pytest.approx(dubins.length(sc.start, sc.goal, 0.2))
    assert j.segments == dubins.shortest(sc.start, sc.goal, 0.2)
    # a waypoint inside the obstacle's model circle: the joins pass through it
    j = judge_poses(sc, [sc.start, (3.0, 3.0, 0.0), sc.goal])
    assert j.gaps == 0 and j.violations >= 2
    # waypoints that miss the goal, or no motion away from the start
    assert judge_poses(sc, [sc.start, (1.0, 1.2, PI / 2)]).gaps == 1
    assert judge_poses(sc, [sc.start]).gaps == 1
    assert judge_poses(sc, [(0.5, 0.0, 0.0)]).gaps == 2
    assert judge_poses(scene(START, START), [START, START]) == (0.0, 0, [], 0)


def chromosomes(sc, count, seed):
    """``count`` chromosomes ``(perm, labels)``: every other one random (most obstacles
    left out), the others one to three random changes of the optimal chromosome (a
    label set or cleared, two positions swapped), whose paths are often feasible and
    run close along model circles."""
    rng = np.random.default_rng(seed)
    opt = solve(sc)
    best_perm, best_labels = from_chromosome(opt.upper, opt.lower, sc.n)
    n = sc.n
    for i in range(count):
        if i % 2:
            p0 = (0.6, 0.9)[i // 2 % 2]  # how many obstacles are left out
            perm = rng.permutation(n)
            labels = rng.choice([-1, 0, 1], size=n + 2, p=[(1 - p0) / 2, p0, (1 - p0) / 2])
            labels[[0, -1]] = rng.choice([-1, 1], size=2)
        else:
            perm, labels = best_perm.copy(), best_labels.copy()
            for _ in range(rng.integers(1, 4)):
                k = rng.integers(1, n + 1)  # a position of the upper module (1..n)
                move = rng.integers(3)
                if move == 0:
                    labels[k] = rng.choice([-1, 0, 1])
                elif move == 1:
                    j = rng.integers(1, n + 1)
                    perm[[k - 1, j - 1]] = perm[[j - 1, k - 1]]
                    labels[[k, j]] = labels[[j, k]]
                else:
                    labels[rng.choice([0, n + 1])] *= -1
        yield perm.astype(np.int32), labels.astype(np.int32)


def test_judge_agrees_with_the_model_on_ga_paths():
    """Chromosomes on the RoboCup scenario: the judge of their segment lists gives the
    decoder's length, violations and feasibility (paths with a missing tangent aside)."""
    sc = load_scenario("configs/scenarios/robocup_paper.toml")
    seen = {True: 0, False: 0}
    for perm, labels in chromosomes(sc, 200, seed=4):
        path = evaluate_path(sc, perm, labels)
        if any(v["kind"] == "missing tangent" for v in path.violations_at):
            continue
        j = judge_segments(sc, path.segments)
        assert j.length == pytest.approx(path.length, rel=1e-9, abs=1e-12)
        assert j.gaps == 0, (perm, labels)
        assert j.feasible == path.feasible, (perm, labels, j.violations, path.violations_at)
        assert j.violations == path.violations, (perm, labels, path.violations_at)
        seen[path.feasible] += 1
    assert seen[True] >= 20 and seen[False] >= 20, seen


def test_an_arc_tighter_than_the_car_can_turn_is_a_violation():
    for radius, violations in ((0.1, 1), (0.2, 0), (0.3, 0)):
        # a U-turn to the left on a circle of this radius ends at the goal facing back
        sc = scenario_from_dict({"name": "t", "robot": {"radius": 0.05, "min_turn_radius": 0.2},
                                 "start": {"x": 0.0, "y": 0.0, "heading_deg": 90.0},
                                 "goal": {"x": -2 * radius, "y": 0.0, "heading_deg": -90.0},
                                 "obstacles": []}, "t")
        arc = {"type": "arc", "center": [-radius, 0.0], "radius": radius, "start_angle": 0.0,
               "sweep": math.pi}
        j = judge_segments(sc, [arc])
        assert j.gaps == 0 and j.violations == violations
        assert j.length == pytest.approx(math.pi * radius, abs=1e-12)
