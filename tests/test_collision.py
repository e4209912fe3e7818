"""The feasibility rule of the path model, stated once, and every consumer held to it.

The rule (docs/model.md, "Feasibility"; :mod:`hga_jax.model.collision`). A path's
violations are, summed over its pieces:

- each (segment, obstacle) pair where the segment comes closer than ``R_k - tol``
  to the obstacle's centre (``"full"``), or crosses its model circle in two
  distinct points inside the segment (``"paper"``);
- each (arc, obstacle) pair where the arc comes closer than ``R_k - tol`` to the
  centre, never the arc's own obstacle (``"full"`` only);
- one for each piece that leaves the kept field (the field shrunk by the robot
  radius) by more than ``tol``, however many sides it crosses;
- one for each missing tangent (a leg between coincident centres counts only that).

Touching (distance exactly ``R_k``) is never a violation. :func:`rule` below says
this in code from the single-pair tests, and the decoder (float64), the turn table,
the float64 path's located violations and the exact solver must agree with it.
"""
from __future__ import annotations

import math

import jax
import numpy as np
import pytest

from hga_jax.host.config import load_scenario, scenario_from_dict
from hga_jax.model import collision as col
from hga_jax.model import geometry as g
from hga_jax.model.exact import solve
from hga_jax.model.fitness import evaluate
from hga_jax.model.path import decode64, evaluate_path
from hga_jax.model.scenario import Field, Scenario

from _families import chromosomes, scenes

F8 = np.float64
TOL = g.tolerances(F8)
INF_BOX = np.array([-np.inf, np.inf, -np.inf, np.inf])


def _obstacles(*circles):
    """Obstacles for scalar pieces from ``(x, y, R)`` triples."""
    c = np.asarray(circles, F8).reshape(-1, 3)
    return col.obstacles(c[:, :2], c[:, 2])


# Worked examples, computed by hand.

@pytest.mark.parametrize("collision", col.COLLISIONS)
def test_a_segment_grazing_a_circle_is_not_a_violation_one_through_it_is(collision):
    unit = _obstacles((0.0, 0.0, 1.0))
    grazing = (-2.0, 1.0, 2.0, 1.0)  # y = 1 touches the unit circle at (0, 1)
    through = (-2.0, 0.5, 2.0, 0.5)  # y = 0.5 passes 0.5 m from the centre
    assert not col.segment_obstacles(grazing, unit, TOL.length, collision)[0]
    assert col.segment_obstacles(through, unit, TOL.length, collision)[0]
    # A hair inside the tolerance is still touching; beyond it, a violation.
    assert not col.segment_obstacles((-2.0, 1 - 0.5e-7, 2.0, 1 - 0.5e-7), unit, TOL.length,
                                     collision)[0]
    assert col.segment_obstacles((-2.0, 1 - 2e-7, 2.0, 1 - 2e-7), unit, TOL.length, collision)[0]
    # The same in float32 on the device, with the float32 tolerance (1e-5 m).
    tol32 = g.tolerances(np.float32).length
    q = col.obstacles(jax.numpy.zeros((1, 2)), jax.numpy.ones(1))
    ends = [jax.numpy.float32(v) for v in (-2.0, 1.0, 2.0, 1.0)]
    assert not bool(col.segment_obstacles(ends, q, tol32, collision)[0])


def test_the_criteria_differ_only_on_a_segment_ending_inside():
    unit = _obstacles((0.0, 0.0, 1.0))
    ending_inside = (-2.0, 0.0, 0.0, 0.0)  # ends at the centre: one crossing, not two
    assert col.segment_obstacles(ending_inside, unit, TOL.length, "full")[0]
    assert not col.segment_obstacles(ending_inside, unit, TOL.length, "paper")[0]


def test_an_arc_is_never_tested_against_its_own_circle_but_against_every_other():
    # Obstacle 0 at the origin (R = 1), obstacle 1 at (1.5, 0) (R = 1): overlapping.
    obs = _obstacles((0.0, 0.0, 1.0), (1.5, 0.0, 1.0))
    # A CCW half circle on obstacle 0's circle from (0, -1) through (1, 0) to (0, 1);
    # (1, 0) lies 0.5 m from obstacle 1's centre, inside its model circle.
    circle, arc = (0.0, 0.0, 1.0, -1.0), (0.0, -1.0, 0.0, 1.0, math.pi)
    on_0 = col.arc_obstacles(circle, 0, arc, obs, TOL.length, "full")
    assert on_0.tolist() == [False, True]
    # The exemption goes by index: named as obstacle 1's arc, it would skip obstacle 1.
    assert col.arc_obstacles(circle, 1, arc, obs, TOL.length, "full").tolist() == [False, False]
    assert col.arc_violations(circle, 0, arc, obs, INF_BOX, TOL.length, "full") == 1
    # The other half (CCW from (0, 1) to (0, -1) through (-1, 0)) stays clear of obstacle 1.
    other = (0.0, 1.0, 0.0, -1.0, math.pi)
    assert col.arc_violations(circle, 0, other, obs, INF_BOX, TOL.length, "full") == 0
    # "paper": arcs meet no obstacle.
    assert col.arc_violations(circle, 0, arc, obs, INF_BOX, TOL.length, "paper") == 0
    assert not col.arc_obstacles(circle, 0, arc, obs, TOL.length, "paper").any()


def test_an_arc_on_a_start_circle_is_tested_against_every_obstacle():
    obs = _obstacles((0.0, 0.0, 1.0), (1.5, 0.0, 1.0))
    circle, arc = (0.0, 0.0, 1.0, -1.0), (0.0, -1.0, 0.0, 1.0, math.pi)
    assert col.arc_obstacles(circle, -1, arc, obs, TOL.length, "full").tolist() == [False, True]


def test_a_piece_leaving_the_field_is_one_violation():
    box = np.array([0.0, 2.0, 0.0, 1.5])
    none = _obstacles()
    assert col.segment_violations((1.0, 1.0, 2.5, 1.0), True, none, box, TOL.length, "full") == 1
    # Across both sides: still one violation.
    assert col.segment_violations((-0.5, 1.0, 2.5, 1.0), True, none, box, TOL.length, "full") == 1
    # On the edge (within the tolerance) is inside.
    assert col.segment_violations((1.0, 1.0, 2.0 + 5e-8, 1.0), True, none, box, TOL.length,
                                  "paper") == 0
    # A CCW half circle (centre (1, 1), r = 0.9) from (1.9, 1) over the top (1, 1.9) to
    # (0.1, 1): both ends inside, its top above y = 1.5. The CW half passes (1, 0.1).
    circle, ends = (1.0, 1.0, 0.9, -1.0), (1.9, 1.0, 0.1, 1.0)
    assert col.arc_violations(circle, -1, ends + (math.pi,), none, box, TOL.length, "paper") == 1
    cw = (1.0, 1.0, 0.9, 1.0)
    assert col.arc_violations(cw, -1, ends + (math.pi,), none, box, TOL.length, "full") == 0


def test_a_missing_tangent_is_one_violation_and_the_counts_add_up():
    obs = _obstacles((1.0, 0.0, 0.3), (2.0, 0.0, 0.3), (2.0, 3.0, 0.3))
    box = np.array([-1.0, 2.5, -1.0, 1.0])
    ends = (0.0, 0.0, 3.0, 0.0)  # through obstacles 0 and 1, out of the box at x = 2.5
    assert col.segment_obstacles(ends, obs, TOL.length, "full").tolist() == [True, True, False]
    assert col.segment_violations(ends, True, obs, box, TOL.length, "full") == 3
    assert col.segment_violations(ends, False, obs, box, TOL.length, "full") == 4
    assert col.segment_violations((0.0, 0.5, 0.1, 0.5), False, obs, box, TOL.length, "full") == 1


def test_the_decoder_counts_each_piece_leaving_the_shrunk_field_once():
    # Start (0.5, 0.5) heading up, goal (2.5, 0.5) heading down, rho = 0.45, both CW
    # (centres (0.95, 0.5) and (2.05, 0.5)): a quarter arc up to the start circle's top
    # (y = 0.95), the segment y = 0.95 from x = 0.95 to 2.05, a quarter arc down to the
    # goal. The field reaches y = 1.0; shrunk by r = 0.1 it ends at 0.9, below all
    # three pieces' tops.
    def scene(ymax, keep):
        return Scenario("shrunk", 0.1, 0.45, (0.5, 0.5, math.pi / 2), (2.5, 0.5, -math.pi / 2),
                        np.zeros((0, 2)), np.zeros(0), Field(0.0, 3.0, 0.0, ymax, keep))

    assert scene(1.0, True).bounds == (0.1, 2.9, 0.1, 0.9)
    assert scene(1.0, False).bounds == (-np.inf, np.inf, -np.inf, np.inf)
    labels = np.array([[1, 1]], np.int32)
    perm = np.zeros((1, 0), np.int32)
    for ymax, keep, expected in ((1.0, True, 3), (1.0, False, 0), (1.06, True, 0)):
        d = decode64(scene(ymax, keep), perm, labels)
        assert d.length[0] == pytest.approx(0.45 * math.pi + 1.1, abs=1e-12)
        assert d.violations[0] == expected, (ymax, keep)
    p = evaluate_path(scene(1.0, True), perm[0], labels[0])
    assert [v["kind"] for v in p.violations_at] == ["field"] * 3
    assert [v["segment"] for v in p.violations_at] == [0, 1, 2]


# The rule in code, from the single-pair tests, and the consumers against it.

def rule(sc: Scenario, d, row: int, collision: str) -> int:
    """Violations of decoded row ``row`` (float64) by the rule of the module doc."""
    sa = sc.arrays(F8)
    qx, qy, qr, box, tol = sa.centres[:, 0], sa.centres[:, 1], sa.model_radii, sa.bounds, TOL.length
    seg_hits = col.segment_hits if collision == "full" else col.segment_hits_paper
    total, count = 0, int(d.count[row])
    for s in range(count):
        cx, cy, r, sign = (float(v) for v in d.circles[row, s])
        ax, ay, bx, by, swp = (float(v) for v in d.arcs[row, s])
        own = int(d.obstacle[row, s])
        if collision == "full":
            for k in range(sc.n):
                if k != own:
                    total += bool(col.arc_hits(cx, cy, r, ax, ay, bx, by, swp, sign,
                                               qx[k], qy[k], qr[k], tol))
        total += bool(col.arc_leaves_field((cx, cy, r, sign), (ax, ay, bx, by, swp), box, tol))
        if s == count - 1:
            continue
        p1x, p1y, p2x, p2y, exists = (float(v) for v in d.lines[row, s])
        total += exists < 0.5
        nxt = d.circles[row, s + 1]
        if math.hypot(nxt[0] - cx, nxt[1] - cy) < TOL.eps:
            continue  # coincident centres: no segment
        for k in range(sc.n):
            total += bool(seg_hits(p1x, p1y, p2x, p2y, qx[k], qy[k], qr[k], tol))
        total += bool(col.segment_leaves_field((p1x, p1y, p2x, p2y), box, tol))
    return total


def _scenes():
    out = [load_scenario("configs/scenarios/robocup_paper.toml"),
           load_scenario("configs/scenarios/overlapping.toml")]
    for family in ("grid", "overlapping", "degenerate", "random"):
        out += [scenario_from_dict(m) for m in scenes(family, 3, 1)]
    return out


@pytest.mark.parametrize("collision", col.COLLISIONS)
def test_decoder_turn_table_path_and_exact_solver_follow_the_rule(collision):
    for i, sc in enumerate(_scenes()):
        rng = np.random.default_rng(i)
        perm, labels = chromosomes(rng, sc.n, 128, p_zero=0.3)
        d = decode64(sc, perm, labels, collision)
        expected = np.array([rule(sc, d, k, collision) for k in range(len(perm))])
        assert np.array_equal(d.violations, expected), (sc.name, collision)
        assert expected.max() > 0 and (sc.n < 3 or expected.max() > expected.min())
        # The turn table's lookups (float64) count the same.
        with jax.enable_x64(True):
            sa = sc.search_arrays(F8, collision)
            if (sa.turns_full if collision == "full" else sa.turns_paper) is not None:
                e = jax.jit(lambda a, p, l: evaluate(a, p, l, collision))(sa, perm, labels)
                assert np.array_equal(np.asarray(e.violations), expected), sc.name
        # The float64 path locates one violation per counted one.
        for k in range(8):
            p = evaluate_path(sc, perm[k], labels[k], collision)
            assert len(p.violations_at) == expected[k], (sc.name, k)
        # The exact optimum is feasible by the rule, and no rule-feasible chromosome
        # of the batch is shorter.
        ex = solve(sc, collision)
        if ex.path is not None:
            pe, le = (np.asarray(v, np.int32)[None] for v in ex_chromosome(ex))
            assert rule(sc, decode64(sc, pe, le, collision), 0, collision) == 0
        if ex.feasible:
            shortest = d.length[expected == 0].min(initial=math.inf)
            assert shortest >= ex.length - 1e-9 * max(1.0, ex.length), sc.name


def ex_chromosome(ex):
    """Internal ``(perm, labels)`` of an exact result's optimal chromosome."""
    return [u - 1 for u in ex.upper[1:-1]], ex.lower
