"""Decoding chromosomes into paths: Dubins words, tolerances, degenerate cases, properties."""
import math

import jax
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hga_jax.model.decode import decode_batch
from hga_jax.model.path import evaluate_path, segments_length
from hga_jax.model.scenario import Field, Scenario

TWO_PI = 2 * math.pi
decode = jax.jit(decode_batch, static_argnames="collision")


def scene(start, goal, centres=(), radii=None, rho=0.2, r=0.09, field=None):
    c = np.asarray(centres, float).reshape(-1, 2)
    rad = np.full(len(c), r) if radii is None else np.asarray(radii, float)
    return Scenario("t", r, rho, tuple(start), tuple(goal), c, rad, field)


def csc_words(start, goal, rho):
    """The four CSC Dubins lengths by heading bookkeeping (independent of the decoder)."""
    (xs, ys, ts), (xg, yg, tg) = start, goal
    left = lambda x, y, t: (x - rho * math.sin(t), y + rho * math.cos(t))  # noqa: E731
    right = lambda x, y, t: (x + rho * math.sin(t), y - rho * math.cos(t))  # noqa: E731
    m = lambda a: a % TWO_PI  # noqa: E731
    out = {}
    for word, c1, c2 in (("LSL", left, left), ("RSR", right, right), ("LSR", left, right),
                         ("RSL", right, left)):
        (ax, ay), (bx, by) = c1(xs, ys, ts), c2(xg, yg, tg)
        d, base = math.hypot(bx - ax, by - ay), math.atan2(by - ay, bx - ax)
        if word in ("LSL", "RSR"):
            phi, straight = base, d
        else:
            if d < 2 * rho:
                continue
            phi = base + (1 if word == "LSR" else -1) * math.asin(2 * rho / d)
            straight = math.sqrt(d * d - 4 * rho * rho)
        turn1 = m(phi - ts) if word[0] == "L" else m(ts - phi)
        turn2 = m(tg - phi) if word[2] == "L" else m(phi - tg)
        out[word] = straight + rho * (turn1 + turn2)
    return out


LABELS = {"LSL": (-1, -1), "RSR": (1, 1), "LSR": (-1, 1), "RSL": (1, -1)}


@pytest.mark.parametrize("seed", range(12))
def test_no_obstacles_matches_csc_dubins_words(seed):
    rng = np.random.default_rng(seed)
    start = (*rng.uniform(-1, 1, 2), rng.uniform(-math.pi, math.pi))
    goal = (*rng.uniform(-1, 1, 2) + [2.0, 0.5], rng.uniform(-math.pi, math.pi))
    rho = rng.uniform(0.1, 0.6)
    sc = scene(start, goal, rho=rho)
    words = csc_words(start, goal, rho)
    for word, (a, b) in LABELS.items():
        p = evaluate_path(sc, [], [a, b])
        if word in words:
            assert p.length == pytest.approx(words[word], rel=1e-12, abs=1e-12), word
            assert p.feasible
        else:
            assert p.violations == 1  # the internal tangent is missing


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_heading_along_the_tangent_gives_zero_arc_not_two_pi(dtype):
    t = 0.3
    start = (0.1, 0.7, t)
    goal = (0.1 + 2.345 * math.cos(t), 0.7 + 2.345 * math.sin(t), t)
    sc = scene(start, goal)
    with jax.enable_x64(dtype == np.float64):
        d = decode(sc.arrays(dtype), np.zeros((2, 0), np.int32),
                   np.array([[-1, -1], [1, 1]], np.int32))
        assert np.allclose(np.asarray(d.length), 2.345, rtol=1e-6)
        assert np.all(np.asarray(d.violations) == 0)


def test_start_and_goal_on_the_same_circle():
    # Left circle of the start has centre (0, 1); the goal is a quarter turn on it.
    sc = scene((0.0, 0.0, 0.0), (1.0, 1.0, math.pi / 2), centres=[(5.0, 5.0)], rho=1.0)
    p = evaluate_path(sc, [0], [-1, 0, -1])
    assert p.length == pytest.approx(math.pi / 2, abs=1e-12)
    assert p.feasible
    assert [s["type"] for s in p.segments] == ["arc"]


def test_missing_tangent_is_penalised_finite_and_deterministic():
    # Obstacles 0 and 1 overlap: CCW around 0 then CW around 1 needs an internal tangent.
    sc = scene((0, 0, 0), (3, 0, 0), centres=[(1.4, 0.3), (1.6, 0.3)])
    a = evaluate_path(sc, [0, 1], [1, -1, 1, 1])
    b = evaluate_path(sc, [0, 1], [1, -1, 1, 1])
    assert a.violations >= 1 and math.isfinite(a.length)
    assert (a.length, a.violations) == (b.length, b.violations)


def test_paper_mode_misses_what_full_mode_catches():
    # Pass over obstacle 0 (CW); obstacle 1 overlaps its top, so the path's arc on 0
    # and the departing segment run inside obstacle 1's model circle, and the segment
    # leaves it without a second crossing.
    sc = scene((0, 0, 0), (3, 0, 0), centres=[(1.5, -0.1), (1.62, 0.12)])
    full = evaluate_path(sc, [0, 1], [1, 1, 0, 1], "full")
    paper = evaluate_path(sc, [0, 1], [1, 1, 0, 1], "paper")
    assert full.length == paper.length
    assert paper.violations == 0
    assert full.violations >= 2  # the arc on 0 and the departing segment


def test_field_kept():
    sc = scene((0.5, 0.5, 0.0), (2.5, 0.5, 0.0), field=Field(0, 3, 0, 1, True))
    assert evaluate_path(sc, [], [-1, -1]).feasible
    sc = scene((0.5, 0.3, math.pi), (2.5, 0.5, 0.0), rho=0.2, field=Field(0, 3, 0, 1, True))
    # Turning left from heading -x at y = 0.3 (circle centre (0.5, 0.1)) sweeps past the
    # circle's bottom at y = -0.1 < r, and the tangent leaves it from y = -0.092 < r:
    # the arc and the segment are one violation each.
    assert evaluate_path(sc, [], [-1, -1]).violations == 2
    assert evaluate_path(sc, [], [1, -1]).feasible  # turning right stays inside


@st.composite
def scenes_and_chromosomes(draw):
    n = draw(st.integers(0, 6))
    fl = st.floats(-2, 2, allow_nan=False)
    centres = [(draw(fl), draw(fl)) for _ in range(n)]
    radii = [draw(st.floats(0.01, 0.3)) for _ in range(n)]
    start = (draw(fl), draw(fl), draw(st.floats(-4, 4)))
    goal = (draw(fl), draw(fl), draw(st.floats(-4, 4)))
    rho = draw(st.floats(0.05, 0.8))
    perm = draw(st.permutations(range(n)))
    ends = st.sampled_from([-1, 1])
    labels = [draw(ends)] + [draw(st.sampled_from([-1, 0, 1])) for _ in range(n)] + [draw(ends)]
    keep = draw(st.booleans())
    sc = scene(start, goal, centres, radii, rho=rho, field=Field(-3, 3, -3, 3, keep))
    return sc, perm, labels


def _end_pose(seg):
    if seg["type"] == "line":
        (x0, y0), (x1, y1) = seg["start"], seg["end"]
        return x1, y1, math.atan2(y1 - y0, x1 - x0)
    (cx, cy), r, a, s = seg["center"], seg["radius"], seg["start_angle"], seg["sweep"]
    e = a + s
    return cx + r * math.cos(e), cy + r * math.sin(e), e + math.copysign(math.pi / 2, s)


def _start_point(seg):
    if seg["type"] == "line":
        return tuple(seg["start"])
    (cx, cy), r, a = seg["center"], seg["radius"], seg["start_angle"]
    return cx + r * math.cos(a), cy + r * math.sin(a)


def _same_heading(a, b):
    return abs((a - b + math.pi) % TWO_PI - math.pi) < 1e-6



@settings(max_examples=24)  # each example compiles its own scene size
@given(scenes_and_chromosomes())
def test_paths_are_finite_continuous_and_end_at_the_goal(case):
    sc, perm, labels = case
    for collision in ("full", "paper"):
        p = evaluate_path(sc, perm, labels, collision)
        assert math.isfinite(p.length) and p.violations >= 0
        assert segments_length(p.segments) == pytest.approx(p.length, rel=1e-9, abs=1e-9)
    if p.segments and all(s["type"] == "arc" or s["start"] != s["end"] for s in p.segments):
        x, y, t = sc.start
        assert _start_point(p.segments[0]) == pytest.approx((x, y), abs=1e-7)
        for prev, seg in zip(p.segments, p.segments[1:]):
            ex, ey, _ = _end_pose(prev)
            assert _start_point(seg) == pytest.approx((ex, ey), abs=1e-7)
        gx, gy, gt = _end_pose(p.segments[-1])
        assert (gx, gy) == pytest.approx(sc.goal[:2], abs=1e-7)
        if p.violations == 0:  # a real tight rope keeps its heading at the goal
            assert _same_heading(gt, sc.goal[2])


@pytest.mark.parametrize("collision", ["full", "paper"])
def test_float32_search_agrees_with_float64(collision):
    rng = np.random.default_rng(7)
    sc = scene((0, 0, 0.2), (2.5, 1.0, -0.5), rng.uniform(0.2, 2.3, (9, 2)))
    perm = np.stack([rng.permutation(9) for _ in range(200)]).astype(np.int32)
    labels = rng.choice([-1, 0, 1], (200, 11)).astype(np.int32)
    labels[:, [0, -1]] = rng.choice([-1, 1], (200, 2))
    d32 = decode(sc.arrays(np.float32), perm, labels, collision=collision)
    with jax.enable_x64(True):
        d64 = decode(sc.arrays(np.float64), perm, labels, collision=collision)
        len64, v64 = np.asarray(d64.length), np.asarray(d64.violations)
    assert np.allclose(np.asarray(d32.length), len64, rtol=1e-5)
    assert np.mean(np.asarray(d32.violations) == v64) > 0.99


@pytest.mark.parametrize("length", [2, 3, 5, 11, 27])
def test_compaction_keeps_active_rows_in_order(length):
    from hga_jax.model.decode import _compact

    rng = np.random.default_rng(length)
    active = rng.random((length, 300)) < 0.5
    active[0] = active[-1] = True
    values = rng.integers(0, 1000, (length, 300))
    count, (out,) = _compact(jax.numpy.asarray(active), jax.numpy.asarray(values))
    for b in range(300):
        expected = values[active[:, b], b]
        assert int(count[b]) == len(expected)
        assert np.array_equal(np.asarray(out)[: len(expected), b], expected)
