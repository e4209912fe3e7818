"""Tangent geometry against hand-computed values (numpy float64 and jax float32)."""
import math

import jax.numpy as jnp
import numpy as np
import pytest

from hga_jax.model import collision as col
from hga_jax.model import geometry as g

S3 = math.sqrt(3.0)

# (c1, r1, s1, c2, r2, s2) -> (length, P1, P2); worked out by hand in the comments.
CASES = [
    # CCW -> CCW, equal radii: external tangent below both circles, heading +x.
    (((0, 0), 1, -1, (4, 0), 1, -1), (4.0, (0, -1), (4, -1))),
    # CW -> CW: external tangent above both circles.
    (((0, 0), 1, 1, (4, 0), 1, 1), (4.0, (0, 1), (4, 1))),
    # CCW -> CW: k = -2, direction +30 deg, length sqrt(16 - 4).
    (((0, 0), 1, -1, (4, 0), 1, 1), (math.sqrt(12), (0.5, -S3 / 2), (3.5, S3 / 2))),
    # CW -> CCW: k = +2, direction -30 deg.
    (((0, 0), 1, 1, (4, 0), 1, -1), (math.sqrt(12), (0.5, S3 / 2), (3.5, -S3 / 2))),
    # CCW -> CCW, radii 1 and 2: k = 1, direction -asin(1/5), u = (sqrt(.96), -0.2),
    # left(u) = (0.2, sqrt(.96)), P_j = c_j - r_j left(u); length sqrt(25 - 1).
    (((0, 0), 1, -1, (5, 0), 2, -1), (math.sqrt(24), (-0.2, -math.sqrt(0.96)),
                                      (5 - 0.4, -2 * math.sqrt(0.96)))),
]


@pytest.mark.parametrize("xp,dtype,tol", [(np, np.float64, 1e-12), (jnp, jnp.float32, 1e-5)])
@pytest.mark.parametrize("case,expected", CASES)
def test_four_tangent_kinds(case, expected, xp, dtype, tol):
    (c1, r1, s1, c2, r2, s2) = case
    a = lambda v: xp.asarray(v, dtype)  # noqa: E731
    t = g.tangent(a(c1[0]), a(c1[1]), a(r1), a(s1), a(c2[0]), a(c2[1]), a(r2), a(s2),
                  a(1.0), a(0.0), 1e-9)
    length, p1, p2 = expected
    assert bool(t.exists)
    assert float(t.length) == pytest.approx(length, abs=tol)
    assert (float(t.p1x), float(t.p1y)) == pytest.approx(p1, abs=tol)
    assert (float(t.p2x), float(t.p2y)) == pytest.approx(p2, abs=tol)
    # The segment joins the touch points along the unit direction.
    assert float(t.p2x - t.p1x) == pytest.approx(float(t.length * t.ux), abs=tol)


@pytest.mark.parametrize("c2,r2,s1,s2", [
    ((1.5, 0.0), 1.0, -1, 1),  # overlapping circles have no internal tangent
    ((0.5, 0.0), 0.5, -1, -1),  # nested circles have no tangent at all
    ((0.0, 0.0), 0.5, -1, -1),  # concentric, different radius
])
def test_missing_tangent_is_flagged_finite_and_deterministic(c2, r2, s1, s2):
    args = (0.0, 0.0, 1.0 if c2 != (0.5, 0.0) else 2.0, s1, c2[0], c2[1], r2, s2, 1.0, 0.0, 1e-9)
    t1, t2 = g.tangent(*map(np.float64, args)), g.tangent(*map(np.float64, args))
    assert not t1.exists
    assert all(np.isfinite(v) for v in t1)
    # The stand-in joins its two touch points.
    assert t1.length == pytest.approx(math.hypot(t1.p2x - t1.p1x, t1.p2y - t1.p1y), abs=1e-12)
    assert tuple(t1) == tuple(t2)


def test_coincident_equal_circles_give_zero_tangent_at_arrival():
    # Fallback direction (0, 1) is the CCW heading at (1, 0) on the unit circle.
    t = g.tangent(*map(np.float64, (0, 0, 1, -1, 0, 0, 1, -1, 0, 1, 1e-9)))
    assert t.exists and t.length == 0.0
    assert (t.p1x, t.p1y) == pytest.approx((1.0, 0.0)) and (t.p2x, t.p2y) == pytest.approx((1.0, 0.0))


@pytest.mark.parametrize("a,b,sign,expected", [
    ((1, 0), (0, 1), -1, math.pi / 2),  # CCW quarter turn
    ((1, 0), (0, 1), 1, 3 * math.pi / 2),  # CW the long way round
    ((1, 0), (1, 0), -1, 0.0),
    ((1, 0), (1, -1e-12), -1, 0.0),  # 2*pi minus rounding counts as 0
    ((1, 0), (-1, 0), 1, math.pi),
])
def test_sweep(a, b, sign, expected):
    got = g.sweep(*map(np.float64, (*a, *b, sign, 1e-9)))
    assert got == pytest.approx(expected, abs=1e-12)


def test_turning_circles():
    cx, cy = g.turning_circle(np.float64(1.0), np.float64(2.0), np.float64(0.0), np.float64(0.5),
                              np.float64(-1))
    assert (cx, cy) == pytest.approx((1.0, 2.5))  # left of a pose heading +x
    cx, cy = g.turning_circle(np.float64(1.0), np.float64(2.0), np.float64(math.pi / 2),
                              np.float64(0.5), np.float64(1))
    assert (cx, cy) == pytest.approx((1.5, 2.0))  # right of a pose heading +y


def test_paper_criterion_misses_a_segment_starting_inside():
    f = np.float64
    seg = (f(0.0), f(0.0), f(2.0), f(0.0))
    inside_start = (f(0.1), f(0.05), f(0.2))
    assert col.segment_hits(*seg, *inside_start, 1e-9)
    assert not col.segment_hits_paper(*seg, *inside_start, 1e-9)
    crossing = (f(1.0), f(0.1), f(0.2))  # crosses twice: both criteria
    assert col.segment_hits(*seg, *crossing, 1e-9) and col.segment_hits_paper(*seg, *crossing, 1e-9)
    tangent = (f(1.0), f(0.2), f(0.2))  # touches: neither
    assert not col.segment_hits(*seg, *tangent, 1e-9)
    assert not col.segment_hits_paper(*seg, *tangent, 1e-9)


def test_arc_clearance():
    f = np.float64
    # Quarter arc CCW on the unit circle from (1, 0) to (0, 1).
    arc = (f(0), f(0), f(1), f(1), f(0), f(0), f(1), f(math.pi / 2), f(-1))
    assert col.arc_hits(*arc, f(0.7), f(0.7), f(0.3), 1e-9)  # on the arc's side
    assert not col.arc_hits(*arc, f(-0.7), f(-0.7), f(0.3), 1e-9)  # opposite side
    assert col.arc_hits(*arc, f(1.2), f(-0.1), f(0.3), 1e-9)  # near the start point only
    box = np.array([-2.0, 2.0, -2.0, 0.95])
    circle, piece = arc[:3] + arc[8:], arc[3:8]
    assert col.arc_leaves_field(circle, piece, box, 1e-9)  # the arc reaches y = 1 at (0, 1)
    assert not col.arc_leaves_field(circle, piece, np.array([-2.0, 2.0, -2.0, 1.0]), 1e-9)
