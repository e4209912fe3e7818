"""Degenerate geometry: half-circle arcs, touching circles, ends exactly on circles.

Regression cases of defects found by a differential check against an independent
implementation, then metamorphic properties (rotating, translating or mirroring a
whole scene changes no length and no violation count), a clearance property checked
by dense sampling (no path called feasible comes closer than its model radii or
leaves the field) and the exact solver against every random feasible chromosome.
``-m slow`` runs the same properties over a million chromosomes.
"""
from __future__ import annotations

import math

import jax
import numpy as np
import pytest

from hga_jax.model import exact
from hga_jax import scenario_from_dict, solve
from hga_jax.model import collision as col
from hga_jax.model import geometry as g
from hga_jax.model.decode import decode_batch
from hga_jax.errors import ModelMismatchError
from hga_jax.model.path import Path, decode64, evaluate_path, from_chromosome

from _families import FAMILIES, chromosomes, mirror, rotate, scenes, translate
from _oracle import clearance

decode = jax.jit(decode_batch, static_argnames="collision")
DTYPES = [np.float32, np.float64]
CLEAR = -1e-6  # m: a feasible path may touch its circles, never enter them by more

UTURN = {"name": "uturn", "robot": {"radius": 0.09, "min_turn_radius": 0.25},
         "start": {"x": 1.1505372644021583, "y": 0.8494638877366353, "heading_deg": 0.123},
         "goal": {"x": 1.1522546670669953, "y": 0.049465731158705006, "heading_deg": 0.123},
         "obstacles": [{"x": 1.1478538227383503, "y": 2.0994610073896514},
                       {"x": 1.1471024590724843, "y": 2.449460200892496}]}
KEEP = {"xmin": 0.0, "xmax": 2.7, "ymin": 0.0, "ymax": 2.25, "keep_inside": True}
GRID_FIELD = {"name": "grid", "robot": {"radius": 0.09, "min_turn_radius": 0.09},
              "start": {"x": 0.99, "y": 1.35, "heading_deg": 225.0},
              "goal": {"x": 1.08, "y": 2.07, "heading_deg": 135.0},
              "obstacles": [{"x": 1.98, "y": 1.26}, {"x": 0.09, "y": 1.62}, {"x": 0.54, "y": 1.98}],
              "field": KEEP}
WALL = {"name": "wall", "robot": {"radius": 0.09, "min_turn_radius": 0.09},
        "start": {"x": 0.09, "y": 1.8, "heading_deg": 180.0},
        "goal": {"x": 1.26, "y": 1.98, "heading_deg": 315.0},
        "obstacles": [{"x": 1.17, "y": 1.44}], "field": KEEP}
TOUCH = {"name": "grid", "robot": {"radius": 0.09, "min_turn_radius": 0.135},
         "start": {"x": 0.36, "y": 0.36, "heading_deg": 180.0},
         "goal": {"x": 0.9, "y": 0.18, "heading_deg": 270.0},
         "obstacles": [{"x": 0.72, "y": 0.18}], "field": KEEP}
ON_CIRCLE = {"name": "degen0", "robot": {"radius": 0.09, "min_turn_radius": 0.09},
             "start": {"x": 1.9566588789871195, "y": 1.3076108418323824,
                       "heading_deg": 133.46870183384962},
             "goal": {"x": 1.8260238284754755, "y": 1.1837783599149945,
                      "heading_deg": 313.46870183384965},
             "obstacles": [], "field": {"xmin": 0.0, "xmax": 2.8, "ymin": 0.0, "ymax": 2.3,
                                        "keep_inside": True}}
PAPER_END = {"name": "grid", "robot": {"radius": 0.09, "min_turn_radius": 0.18},
             "start": {"x": 1.98, "y": 0.63, "heading_deg": 315.0},
             "goal": {"x": 1.17, "y": 1.35, "heading_deg": 45.0},
             "obstacles": [{"x": 1.62, "y": 0.9}, {"x": 0.72, "y": 1.08}, {"x": 0.54, "y": 1.26}]}


def decoded(sc, perm, labels, dtype, collision="full"):
    """Decoded arrays of a batch in ``dtype`` (numpy)."""
    perm, labels = np.asarray(perm, np.int32), np.asarray(labels, np.int32)
    if dtype == np.float64:
        return decode64(sc, perm, labels, collision)
    return jax.tree.map(np.asarray, decode(sc.arrays(np.float32), perm, labels, collision=collision))


def one(mapping, upper, lower, dtype, collision="full"):
    sc = scenario_from_dict(mapping)
    perm, labels = from_chromosome(upper, lower, sc.n)
    d = decoded(sc, perm[None], labels[None], dtype, collision)
    return sc, d, float(d.length[0]), int(d.violations[0])


# --- the defects, one by one -------------------------------------------------------------


@pytest.mark.parametrize("dtype", DTYPES)
def test_half_circle_arc_into_an_obstacle_is_a_violation(dtype):
    sc, d, _, violations = one(UTURN, [0, 1, 2, 3], [-1, -1, 0, -1], dtype)
    assert violations == 1
    # The path really drives 0.15 m into obstacle 1 (0-based index 0).
    obstacle_gap, _ = clearance(sc.arrays(np.float64), decoded(sc, [[0, 1]], [[-1, -1, 0, -1]],
                                                               np.float64))
    assert obstacle_gap[0] == pytest.approx(-0.15, abs=0.01)


@pytest.mark.parametrize("dtype", DTYPES)
def test_half_circle_u_turn_rotated_through_360_angles_never_feasible(dtype):
    about = (UTURN["start"]["x"], UTURN["start"]["y"])
    perm, labels = from_chromosome([0, 1, 2, 3], [-1, -1, 0, -1], 2)
    bad = [deg for deg in range(360)
           if decoded(scenario_from_dict(rotate(UTURN, deg + 0.5, about)), perm[None], labels[None],
                      dtype).violations[0] != 1]
    assert bad == []


@pytest.mark.parametrize("dtype", DTYPES)
def test_half_circle_arc_leaving_the_field_is_counted(dtype):
    # Two pieces leave the field (one of them 0.18 m) and one arc enters obstacle 3.
    _, _, _, violations = one(GRID_FIELD, [0, 1, 2, 3, 4], [1, -1, 1, -1, 1], dtype)
    assert violations == 3


@pytest.mark.parametrize("collision", ["full", "paper"])
def test_start_facing_the_wall_has_no_feasible_path(collision):
    sc = scenario_from_dict(WALL)
    # Brute force: with one obstacle every chromosome is one of 2 * 3 * 2 label choices.
    lab = np.array([[a, b, c] for a in (-1, 1) for b in (-1, 0, 1) for c in (-1, 1)], np.int32)
    d = decoded(sc, np.zeros((len(lab), 1), np.int32), lab, np.float64, collision)
    assert (d.violations > 0).all()
    opt = solve(sc, collision)
    assert not opt.feasible and opt.length == math.inf


@pytest.mark.parametrize("dtype", DTYPES)
def test_touching_circles_give_no_spurious_loop(dtype):
    sc, d, length, violations = one(TOUCH, [0, 1, 2], [1, 1, -1], dtype)
    assert violations == 0
    # The obstacle touches the goal circle exactly at the goal point: no goal arc.
    assert float(d.arcs[0, 2, 4]) < 1e-6
    opt = solve(sc)
    assert length == pytest.approx(opt.length, rel=1e-6 if dtype == np.float32 else 1e-12)
    # The same walk; the goal's turning direction does not matter with no goal arc.
    assert opt.lower[:2] == [1, 1]
    assert length < 2.003 - 2 * math.pi * 0.135 + 1e-3  # the defect added a 2*pi*rho loop


@pytest.mark.parametrize("dtype", DTYPES)
def test_goal_on_the_start_circle_is_half_a_turn(dtype):
    # The goal is the contact point of the start's CCW circle and the goal's CW circle.
    _, _, length, violations = one(ON_CIRCLE, [0, 1], [-1, 1], dtype)
    assert violations == 0
    assert length == pytest.approx(math.pi * 0.09, rel=1e-6 if dtype == np.float32 else 1e-12)


def test_goal_on_the_start_circle_optimum_agrees_with_its_walk():
    opt = solve(scenario_from_dict(ON_CIRCLE))
    assert opt.length == pytest.approx(math.pi * 0.09, rel=1e-12)
    assert opt.walk_length == pytest.approx(opt.length, rel=1e-12)


@pytest.mark.parametrize("dtype", DTYPES)
def test_paper_criterion_segment_ending_on_another_circle(dtype):
    # The segment (1.62, 1.08) -> (0.54, 1.08) ends on obstacle 2's circle and runs
    # through its centre: two crossings in the paper's sense, in both precisions.
    _, _, _, violations = one(PAPER_END, [0, 1, 3, 2, 4], [1, -1, 1, 0, 1], dtype, "paper")
    assert violations == 1


def test_solver_raises_when_the_decoder_disagrees(monkeypatch):
    real = exact.evaluate_path

    def one_violation_more(*args, **kwargs):
        p = real(*args, **kwargs)
        return Path(p.length, p.violations + 1, p.upper, p.lower, p.segments, p.touched)

    monkeypatch.setattr(exact, "evaluate_path", one_violation_more)
    with pytest.raises(ModelMismatchError, match="violation"):
        solve(scenario_from_dict(TOUCH))


def all_chromosomes(n):
    """Every (perm, labels) of ``n`` obstacles (brute force for small n)."""
    import itertools

    perms, labels = [], []
    for p in itertools.permutations(range(n)):
        for lab in itertools.product((-1, 1), *([(-1, 0, 1)] * n), (-1, 1)):
            perms.append(p)
            labels.append(lab)
    return np.asarray(perms, np.int32).reshape(len(labels), n), np.asarray(labels, np.int32)


@pytest.mark.parametrize("collision", ["full", "paper"])
@pytest.mark.parametrize("scene", [UTURN, GRID_FIELD, WALL, TOUCH, ON_CIRCLE, PAPER_END],
                         ids=["uturn", "grid-field", "wall", "touch", "on-circle", "paper-end"])
def test_exact_optimum_of_each_defect_scene_is_the_brute_force_minimum(scene, collision):
    sc = scenario_from_dict(scene)
    perm, labels = all_chromosomes(sc.n)
    d = decoded(sc, perm, labels, np.float64, collision)
    ok = d.violations == 0
    opt = solve(sc, collision)  # raises ModelMismatchError if graph and decoder disagree
    assert opt.feasible == bool(ok.any())
    if ok.any() and opt.expressible:
        assert opt.length == pytest.approx(d.length[ok].min(), rel=1e-12)
    if collision == "full" and ok.any():
        gaps = clearance(sc.arrays(np.float64), d)
        assert min(gaps[0][ok].min(), gaps[1][ok].min()) >= CLEAR


# --- the primitives at their edges -----------------------------------------------------------


@pytest.mark.parametrize("dtype", DTYPES)
@pytest.mark.parametrize("sign", [-1.0, 1.0])
def test_in_span_of_a_half_circle(dtype, sign):
    # A = (0, 1), B = (0, -1) up to rounding, sweep pi: CCW passes (-1, 0), CW (1, 0).
    rot = np.linspace(0, 2 * np.pi, 97)
    c, s = np.cos(rot), np.sin(rot)
    a = (np.zeros_like(rot), np.ones_like(rot))
    b = (np.full_like(rot, 1e-17), -np.ones_like(rot))
    ax, ay = (a[0] * c - a[1] * s).astype(dtype), (a[0] * s + a[1] * c).astype(dtype)
    bx, by = (b[0] * c - b[1] * s).astype(dtype), (b[0] * s + b[1] * c).astype(dtype)
    swp = g.sweep(ax, ay, bx, by, np.asarray(sign, dtype), 1e-9)
    frame = g.arc_frame(ax, ay, bx, by, swp, np.asarray(sign, dtype))
    mid = (np.asarray(sign) * c, np.asarray(sign) * s)  # rotated (sign, 0)
    assert np.all(g.in_span(frame, mid[0].astype(dtype), mid[1].astype(dtype)))
    assert not np.any(g.in_span(frame, -mid[0].astype(dtype), -mid[1].astype(dtype)))


@pytest.mark.parametrize("dtype", DTYPES)
def test_touching_circles_touch_at_the_contact_point(dtype):
    f = lambda v: np.asarray(v, dtype)  # noqa: E731
    tol = g.tolerances(dtype)
    # CW circle r = 0.18 at (0.72, 0.18), CCW circle r = 0.135 at (0.9 + 0.135, 0.18).
    t = g.tangent(f(0.72), f(0.18), f(0.18), f(1), f(0.9 + 0.135), f(0.18), f(0.135), f(-1),
                  f(1), f(0), tol.eps)
    assert bool(t.exists) and float(t.length) == 0.0
    for x, y in ((t.p1x, t.p1y), (t.p2x, t.p2y)):
        assert (float(x), float(y)) == pytest.approx((0.9, 0.18), abs=4 * float(np.finfo(dtype).eps))


def test_paper_criterion_counts_an_end_on_the_circle_as_outside():
    f = np.float64
    # From (2, 0) to (0, 0) through the centre of the unit circle at (1, 0): both ends lie
    # on the circle, so it crosses it, whichever way the ends round.
    for end in (0.0, 1e-12, -1e-12):
        seg = (f(2.0), f(0.0), f(end), f(0.0))
        assert col.segment_hits_paper(*seg, f(1.0), f(0.0), f(1.0), 1e-7)
    # An end inside by more than the tolerance is missed, as in the paper.
    assert not col.segment_hits_paper(f(2.0), f(0.0), f(0.5), f(0.0), f(1.0), f(0.0), f(1.0), 1e-7)


# --- metamorphic properties ----------------------------------------------------------------


def _transforms(scene, rng):
    """Whole-scene transforms (name, mapping, labels flip) that keep every length."""
    quarter = "field" in scene  # a kept field stays axis-aligned only under quarter turns
    deg = float(rng.integers(1, 4) * 90) if quarter else float(rng.uniform(-180, 180))
    about = tuple(rng.uniform(0, 2.5, 2))
    return [("rotate", rotate(scene, deg, about), False),
            ("translate", translate(scene, *rng.uniform(-1.3, 1.3, 2)), False),
            ("mirror", mirror(scene), True)]


def metamorphic_mismatches(scene, perm, labels, dtype, collision, rng):
    """Rows whose violation count or length changes under a whole-scene transform."""
    sc = scenario_from_dict(scene)
    base = decoded(sc, perm, labels, dtype, collision)
    rel = 1e-9 if dtype == np.float64 else 2e-5
    bad = []
    for name, moved, flip in _transforms(scene, rng):
        lab = -labels if flip else labels
        d = decoded(scenario_from_dict(moved), perm, lab, dtype, collision)
        wrong = (d.violations != base.violations) | ~np.isclose(d.length, base.length, rtol=rel,
                                                                atol=rel)
        bad += [(name, int(i)) for i in np.flatnonzero(wrong)]
    return bad


@pytest.mark.parametrize("family", [  # one family in the default lane
    pytest.param(f, marks=pytest.mark.slow) if f != "random" else f for f in FAMILIES])
@pytest.mark.parametrize("dtype", [  # float64 in the default lane
    pytest.param(d, marks=pytest.mark.slow) if d is np.float32 else d for d in DTYPES])
def test_rotation_translation_and_mirroring_keep_lengths_and_violations(family, dtype):
    rng = np.random.default_rng(11)
    for i, scene in enumerate(scenes(family, 1, 6)):
        n = len(scene.get("obstacles", []))
        perm, labels = chromosomes(rng, n, 64)
        for collision in ("full", "paper"):
            bad = metamorphic_mismatches(scene, perm, labels, dtype, collision, rng)
            assert bad == [], (family, i, collision, bad[:5])


# --- clearance and optimum --------------------------------------------------------------


@pytest.mark.parametrize("family", FAMILIES)
def test_feasible_paths_keep_their_clearance_and_never_beat_the_optimum(family):
    rng = np.random.default_rng(5)
    feasible = 0
    for scene in scenes(family, 2, 8):
        sc = scenario_from_dict(scene)
        perm, labels = chromosomes(rng, sc.n, 256, p_zero=0.6)
        d = decoded(sc, perm, labels, np.float64)
        obstacle_gap, field_gap = clearance(sc.arrays(np.float64), d)
        ok = d.violations == 0
        feasible += int(ok.sum())
        assert np.all(obstacle_gap[ok] >= CLEAR) and np.all(field_gap[ok] >= CLEAR)
        opt = solve(sc)  # raises ModelMismatchError if graph and decoder disagree
        if ok.any():
            assert opt.feasible and opt.length <= d.length[ok].min() + 1e-9
        if opt.path is not None:
            o = decoded(sc, *from_chromosome(opt.upper, opt.lower, sc.n), np.float64)
            assert min(gap[0] for gap in clearance(sc.arrays(np.float64), o)) >= CLEAR
    assert feasible >= 100  # the property is not vacuous


@pytest.mark.parametrize("family", ["grid", "degenerate"])
def test_exact_solver_paths_decode_without_violation_in_both_modes(family):
    for scene in scenes(family, 3, 25):
        sc = scenario_from_dict(scene)
        for collision in ("full", "paper"):
            opt = solve(sc, collision)  # raises ModelMismatchError on any disagreement
            path = opt.path or opt.best_expressible
            if path is not None:
                again = evaluate_path(sc, *from_chromosome(path.upper, path.lower, sc.n), collision)
                assert again.violations == 0 and again.length == pytest.approx(path.length, rel=1e-12)


# --- the deep run, on demand ------------------------------------------------------------------


@pytest.mark.slow
def test_deep_no_false_feasibility_over_a_million_chromosomes():
    rng = np.random.default_rng(2026)
    total = feasible = false_feasible = meta_bad = beaten = false32 = 0
    worst = np.inf
    per_family = {}
    for family in ("grid", "overlapping", "degenerate"):
        count = 0
        for scene in scenes(family, 7, 120):
            sc = scenario_from_dict(scene)
            perm, labels = chromosomes(rng, sc.n, 3000, p_zero=float(rng.uniform(0.3, 0.8)))
            d = decoded(sc, perm, labels, np.float64)
            obstacle_gap, field_gap = clearance(sc.arrays(np.float64), d)
            ok = d.violations == 0
            gap = np.minimum(obstacle_gap, field_gap)[ok]
            worst = min(worst, gap.min(initial=np.inf))
            false_feasible += int((gap < CLEAR).sum())
            d32 = decoded(sc, perm, labels, np.float32)
            false32 += int(((d32.violations == 0) & (np.minimum(obstacle_gap, field_gap) < -1e-4)).sum())
            feasible += int(ok.sum())
            total += len(ok)
            count += len(ok)
            meta_bad += len(metamorphic_mismatches(scene, perm[:500], labels[:500], np.float64,
                                                   "full", rng))
            opt = solve(sc)
            if ok.any() and (not opt.feasible or opt.length > d.length[ok].min() + 1e-9):
                beaten += 1
        per_family[family] = count
    print(f"\ndeep degenerate run: {total} chromosomes {per_family}, {feasible} feasible in float64, "
          f"{false_feasible} false feasible (sampled clearance below {CLEAR} m), worst clearance of a "
          f"feasible path {worst:.3g} m, {meta_bad} metamorphic mismatches, {beaten} scenes where a "
          "random chromosome beat the exact optimum; float32: "
          f"{false32} paths called feasible that enter a circle or leave the field by over 0.1 mm")
    assert total >= 1_000_000
    assert false_feasible == 0 and meta_bad == 0 and beaten == 0


@pytest.mark.parametrize("scene", [TOUCH, ON_CIRCLE, UTURN], ids=["touch", "on-circle", "uturn"])
def test_float32_search_reports_only_float64_truths(scene):
    # The search runs in float32; every run's best is re-evaluated in float64, and what
    # is called feasible keeps its clearance, near-tangent pieces included.
    from hga_jax import GASettings, run_many

    sc = scenario_from_dict(scene)
    res = run_many(sc, GASettings(population=20, generations=10), seed=3, runs=64)
    d = decoded(sc, res.perm, res.labels, np.float64)
    np.testing.assert_array_equal(d.violations, res.violations)
    obstacle_gap, field_gap = clearance(sc.arrays(np.float64), d)
    ok = res.violations == 0
    assert ok.any()
    assert np.all(obstacle_gap[ok] >= CLEAR) and np.all(field_gap[ok] >= CLEAR)
    assert res.best.feasible and res.best.length >= res.optimum.length - 1e-9
