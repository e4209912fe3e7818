"""The exact solver against brute force, hand-computed cases and the decoder.

The brute-force enumerator decodes every distinct chromosome of a small scene
(every ordered subset of obstacles, both labels each, both start and both goal
labels) with the GA decoder in float64; the model's optimum over chromosomes is
the shortest feasible one. The exact solver must find the same length.
"""
from __future__ import annotations

import itertools
import json
import math
from functools import lru_cache

import jax
import numpy as np
import pytest

from hga_jax.model.decode import decode_batch
from hga_jax.model.exact import solve
from hga_jax.model.path import evaluate_path, from_chromosome, segments_length
from hga_jax.model.scenario import Field, Scenario

_decode = jax.jit(decode_batch, static_argnames="collision")
REL = 1e-9


def scene(centres, radii, start, goal, rho=0.5, robot=0.2, field=None, name="t") -> Scenario:
    c = np.asarray(centres, np.float64).reshape(-1, 2)
    return Scenario(name, robot, rho, tuple(start), tuple(goal), c,
                    np.asarray(radii, np.float64).reshape(c.shape[0]), field=field)


@lru_cache(maxsize=None)
def all_chromosomes(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Every distinct decoded path of n obstacles as internal (perm, labels) batches."""
    perms, labels = [], []
    for k in range(n + 1):
        for sub in itertools.permutations(range(n), k):
            rest = [i for i in range(n) if i not in sub]
            for labs in itertools.product((-1, 1), repeat=k):
                for s, gl in itertools.product((-1, 1), repeat=2):
                    perms.append(list(sub) + rest)
                    labels.append([s, *labs] + [0] * (n - k) + [gl])
    return np.asarray(perms, np.int32).reshape(-1, n), np.asarray(labels, np.int32)


def brute_force(sc: Scenario, collision: str) -> float:
    """Shortest feasible decoded path over every chromosome (inf if none)."""
    perm, labels = all_chromosomes(sc.n)
    with jax.enable_x64(True):
        d = _decode(sc.arrays(np.float64), perm, labels, collision=collision)
        length, viol = np.asarray(d.length), np.asarray(d.violations)
    ok = viol == 0
    return float(length[ok].min()) if ok.any() else math.inf


def random_scene(rng: np.random.Generator, n: int) -> Scenario:
    """Obstacles between start and goal, random radii (often overlapping), maybe a kept field."""
    rho, robot = rng.uniform(0.3, 1.2), rng.uniform(0.05, 0.4)
    spread = rng.choice([2.0, 3.5, 5.0])  # small spread: many overlaps
    centres = rng.uniform(5.0 - spread, 5.0 + spread, (n, 2))
    radii = rng.uniform(0.05, 1.2, n)
    model = np.maximum(rho, radii + robot)
    field = None
    if rng.random() < 0.5:
        field = Field(-0.5, 10.5, rng.uniform(-1.0, 2.5), rng.uniform(7.5, 11.0),
                      keep_inside=bool(rng.random() < 0.8))
    lo_y = field.ymin + robot if field else 0.0
    hi_y = field.ymax - robot if field else 10.0

    def pose(x_lo, x_hi):
        while True:
            p = np.array([rng.uniform(x_lo, x_hi), rng.uniform(lo_y, hi_y)])
            if np.all(np.hypot(*(centres - p).T) > model + 1e-3):
                return (float(p[0]), float(p[1]), float(rng.uniform(-np.pi, np.pi)))

    return scene(centres, radii, pose(0.0, 3.0), pose(7.0, 10.0), rho, robot, field)


def optimum_over_chromosomes(res) -> float:
    if res.expressible:
        return res.length
    return res.best_expressible.length if res.best_expressible is not None else math.inf


def close(a: float, b: float) -> bool:
    if math.isinf(a) or math.isinf(b):
        return a == b
    return abs(a - b) <= REL * max(1.0, abs(b))


def check_against_brute_force(seed: int, scenes: int, sizes: tuple[int, int]) -> None:
    rng = np.random.default_rng(seed)
    bad, kinds = [], {"infeasible": 0, "inexpressible": 0, "field": 0}
    for i in range(scenes):
        sc = random_scene(rng, int(rng.integers(*sizes)))
        for collision in ("full", "paper"):
            res = solve(sc, collision)
            want = brute_force(sc, collision)
            got = optimum_over_chromosomes(res)
            kinds["infeasible"] += math.isinf(want)
            kinds["inexpressible"] += not res.expressible
            kinds["field"] += sc.field is not None and sc.field.keep_inside
            if not close(got, want) or (math.isinf(want) and res.feasible and res.expressible):
                bad.append((i, collision, got, want, res.message))
            if res.feasible:
                assert res.walk_length <= got * (1 + REL)
    assert not bad, bad
    print(kinds)


@pytest.mark.parametrize("chunk", [0, 1, 2] + [pytest.param(c, marks=pytest.mark.slow)
                                                for c in (3, 4, 5)])
def test_matches_brute_force(chunk):
    check_against_brute_force(1000 + chunk, 40, (3, 6))  # 120 scenes here, 240 with slow


@pytest.mark.slow
@pytest.mark.parametrize("chunk", range(4))
def test_matches_brute_force_more(chunk):
    check_against_brute_force(2000 + chunk, 250, (2, 6))
    check_against_brute_force(3000 + chunk, 10, (6, 7))


# Scenes (full mode) whose optimal walk wraps a cluster and touches one obstacle
# twice (in two of them no chromosome gives a feasible path at all).
# Columns: centres, radii, start, goal, rho, robot radius.
REVISITS = [
    ([[5.832, 4.203], [5.104, 4.625], [4.424, 4.548]], [0.364, 1.126, 0.74],
     (6.199, 6.892, 0.457), (4.062, 2.84, 0.952), 0.204, 0.29),
    ([[4.557, 4.474], [5.131, 4.241], [4.458, 5.611], [5.451, 4.051], [4.895, 4.797]],
     [1.187, 0.811, 0.573, 1.31, 0.532], (7.256, 4.217, 1.134), (7.371, 4.111, -2.18),
     0.459, 0.227),
    ([[5.777, 4.776], [4.481, 5.313], [4.227, 5.703]], [0.907, 1.117, 0.668],
     (5.727, 6.746, -0.433), (2.237, 4.224, 2.684), 0.201, 0.224),
    ([[4.651, 5.981], [4.812, 4.085], [4.527, 4.853], [5.996, 5.881], [5.614, 5.432]],
     [1.02, 0.609, 1.399, 0.634, 0.63], (6.365, 4.968, -2.735), (2.053, 5.737, 1.772), 0.222, 0.14),
    ([[4.066, 4.985], [4.224, 5.125], [5.829, 4.384]], [1.171, 1.377, 0.544],
     (6.114, 5.928, -0.973), (5.695, 6.334, 2.536), 0.484, 0.064),
    ([[4.226, 5.042], [4.265, 4.608], [4.989, 5.398]], [0.745, 1.388, 0.689],
     (3.271, 3.177, -1.83), (3.021, 3.365, 2.717), 0.392, 0.228),
    ([[5.763, 4.016], [5.559, 4.862], [5.854, 5.489], [5.524, 4.791], [5.572, 4.599]],
     [0.876, 1.249, 0.496, 0.765, 1.483], (2.098, 3.749, -2.417), (7.641, 4.422, 0.705),
     0.444, 0.065),
    ([[5.697, 5.798], [4.869, 5.111], [4.447, 4.145], [5.254, 4.284]], [0.409, 1.471, 1.253, 1.121],
     (2.53, 6.165, 2.881), (7.276, 4.136, -0.294), 0.428, 0.248),
]


@pytest.mark.parametrize("case", range(len(REVISITS)))
def test_revisiting_walk_and_best_expressible(case):
    sc = scene(*REVISITS[case])
    res = solve(sc, "full")
    assert res.feasible and not res.expressible
    assert res.upper is None and res.path is None
    ids = [o for o, _ in res.touched]
    assert len(set(ids)) < len(ids)
    assert close(segments_length(res.segments), res.walk_length)
    want = brute_force(sc, "full")
    assert close(optimum_over_chromosomes(res), want)
    assert res.walk_length < want
    if res.best_expressible is not None:
        assert res.best_expressible.feasible
        json.dumps(res.to_dict())


# --- hand cases --------------------------------------------------------------

def _mod(a: float) -> float:
    return a % (2 * math.pi)


def dubins_csc(start, goal, rho) -> dict[str, float]:
    """Lengths of the four CSC words (LSL, RSR, LSR, RSL), written from the geometry.

    Left circle centre ``p + rho*(-sin t, cos t)``, right ``p + rho*(sin t, -cos t)``.
    A word whose tangent does not exist is left out.
    """
    (xs, ys, ts), (xg, yg, tg) = start, goal

    def centre(x, y, t, left):
        s = 1.0 if left else -1.0
        return x - s * rho * math.sin(t), y + s * rho * math.cos(t)

    out = {}
    for word in ("LSL", "RSR", "LSR", "RSL"):
        a, b = word[0] == "L", word[2] == "L"
        c1, c2 = centre(xs, ys, ts, a), centre(xg, yg, tg, b)
        dx, dy = c2[0] - c1[0], c2[1] - c1[1]
        d, th = math.hypot(dx, dy), math.atan2(dy, dx)
        if a == b:  # outer tangent, parallel to the centre line
            phi, straight = th, d
        else:
            if d < 2 * rho:
                continue
            straight = math.sqrt(d * d - 4 * rho * rho)
            phi = th + (1 if a else -1) * math.atan2(2 * rho, straight)
        arc1 = _mod(phi - ts) if a else _mod(ts - phi)
        arc2 = _mod(tg - phi) if b else _mod(phi - tg)
        out[word] = rho * (arc1 + arc2) + straight
    return out


def _check_csc(far_obstacle: bool) -> None:
    rng = np.random.default_rng(3)
    labels = {"L": -1, "R": 1}
    for _ in range(25):
        rho = rng.uniform(0.3, 2.0)
        start = (*rng.uniform(-3, 3, 2), rng.uniform(-np.pi, np.pi))
        goal = (*rng.uniform(-3, 3, 2), rng.uniform(-np.pi, np.pi))
        centres = [[100.0, 100.0]] if far_obstacle else np.zeros((0, 2))
        sc = scene(centres, [0.3] if far_obstacle else [], start, goal, rho)
        words = dubins_csc(start, goal, rho)
        best = min(words, key=words.get)
        for collision in ("full", "paper"):
            res = solve(sc, collision)
            assert res.feasible and res.expressible and res.touched == []
            assert close(res.length, words[best]), (words, res.length)
            assert close(res.walk_length, words[best])
            if sorted(words.values())[1] - words[best] > 1e-6:
                assert res.lower[0] == labels[best[0]] and res.lower[-1] == labels[best[2]]


def test_far_obstacle_is_best_csc_word():
    _check_csc(far_obstacle=True)


def test_no_obstacles_is_best_csc_word():
    _check_csc(far_obstacle=False)


def test_coincident_start_and_goal_circles_give_one_arc():
    rho = 1.0  # start on the left circle centred (0, 1); goal a quarter turn on
    sc = scene([[5.0, 5.0]], [0.3], (0.0, 0.0, 0.0), (1.0, 1.0, math.pi / 2), rho)
    res = solve(sc)
    assert close(res.length, math.pi / 2 * rho)
    assert res.lower == [-1, 0, -1] and res.path.feasible
    assert close(brute_force(sc, "full"), res.length)


def test_one_obstacle_blocking_the_straight_line():
    start, goal = (0.0, 0.0, 0.0), (10.0, 0.0, 0.0)
    sc = scene([[5.0, 0.3]], [0.5], start, goal, rho=0.5, robot=0.2)
    straight = evaluate_path(sc, [0], [-1, 0, -1])
    assert straight.violations > 0 and close(straight.length, 10.0)
    res = solve(sc)
    # Centre above the line: pass below it, the obstacle on the left (CCW, -1).
    assert res.touched == [(1, -1)] and res.upper == [0, 1, 2] and res.lower[1] == -1
    assert 10.0 < res.length < 10.0 + 2.0
    assert close(res.length, brute_force(sc, "full"))


def test_side_forced_by_overlapping_obstacle():
    start, goal = (0.0, 0.0, 0.0), (10.0, 0.0, 0.0)
    field = Field(-1.0, 11.0, -3.0, 6.0, keep_inside=True)
    free = scene([[5.0, 0.3]], [0.5], start, goal, field=field)
    assert solve(free).touched == [(1, -1)]  # alone, it is passed below
    # A second obstacle overlaps it from below down to the field's edge.
    sc = scene([[5.0, 0.3], [5.0, -1.5]], [0.5, 1.3], start, goal, field=field)
    r = sc.model_radii
    assert np.hypot(*(sc.centres[0] - sc.centres[1])) < r[0] + r[1]
    assert sc.centres[1, 1] - r[1] < field.ymin + sc.robot_radius
    res = solve(sc)
    assert (1, 1) in res.touched and (1, -1) not in res.touched  # obstacle 1 passed above: CW
    assert all(lab == 1 for _, lab in res.touched)
    assert close(res.length, brute_force(sc, "full"))


def test_exact_path_round_trip():
    rng = np.random.default_rng(11)
    for n in (6, 9, 15):
        for _ in range(3):
            sc = random_scene(rng, n)
            for collision in ("full", "paper"):
                res = solve(sc, collision)
                if not (res.feasible and res.expressible):
                    continue
                perm, labels = from_chromosome(res.upper, res.lower, sc.n)
                again = evaluate_path(sc, perm, labels, collision)
                assert again.violations == 0
                assert close(again.length, res.length) and close(res.walk_length, res.length)
                assert close(segments_length(again.segments), res.length)
                assert close(segments_length(res.segments), res.length)
                assert [t for t in again.touched] == res.touched
                assert res.message == "optimal"
                d = json.loads(json.dumps(res.to_dict()))
                assert d["upper"] == res.upper and d["segments"]


def test_goal_enclosed_by_ring_is_infeasible():
    angles = np.linspace(0, 2 * np.pi, 8, endpoint=False)
    ring = 3.0 * np.stack([np.cos(angles), np.sin(angles)], axis=1)
    sc = scene(ring, np.full(8, 1.3), (-8.0, 0.0, 0.0), (0.0, 0.0, 0.0), rho=0.5, robot=0.2)
    res = solve(sc, "full")
    assert not res.feasible and math.isinf(res.length) and res.message
    assert res.path is None and res.best_expressible is None and res.touched == []
    d = json.loads(json.dumps(res.to_dict()))
    assert d["length"] is None and d["feasible"] is False


def test_bad_collision_mode():
    sc = scene([[5.0, 0.3]], [0.5], (0.0, 0.0, 0.0), (10.0, 0.0, 0.0))
    with pytest.raises(ValueError):
        solve(sc, "nope")


def test_straight_ahead_goal_is_a_straight_line():
    # The tangent arrives at the goal point itself (and leaves at the start point):
    # rounding puts it a hair before or after it; the sweep rule must count 0, not 2*pi.
    rng = np.random.default_rng(5)
    for _ in range(60):
        x, y, t = rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-np.pi, np.pi)
        dist = rng.uniform(0.5, 12.0)
        goal = (x + dist * math.cos(t), y + dist * math.sin(t), t)
        far = [[x + 50.0, y + 50.0]]  # one obstacle out of the way
        sc = scene(far, [0.3], (x, y, t), goal, rho=rng.uniform(0.1, 2.0))
        for collision in ("full", "paper"):
            res = solve(sc, collision)
            assert close(res.length, dist) and close(res.walk_length, dist), res.lower
