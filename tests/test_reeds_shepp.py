"""Reeds-Shepp shortest paths (hga_jax.model.cars.reeds_shepp.closed_form) against OMPL, against their
own closed-form kinematics and against hand-computed values."""
import collections
import math

import numpy as np
import pytest

from hga_jax.model import dubins
from hga_jax.model.cars.reeds_shepp import closed_form as rs

RHOS = (0.15, 0.25, 1.0)
TWO_PI = 2.0 * math.pi


def pairs(n, seed, max_dist=6.0):
    """``n`` random ``(p, q, rho)``: q within ``max_dist`` radii of p in any direction,
    any headings (some beyond [-pi, pi], to exercise their normalisation)."""
    rng = np.random.default_rng(seed)
    rho = rng.choice(RHOS, n)
    start = rng.uniform(-5.0, 5.0, (n, 2))
    r = rho * max_dist * np.sqrt(rng.uniform(0.0, 1.0, n))  # uniform over the disc
    a = rng.uniform(-math.pi, math.pi, n)
    heads = rng.uniform(-3.0 * math.pi, 3.0 * math.pi, (n, 2))
    goal = start + np.stack([r * np.cos(a), r * np.sin(a)], axis=1)
    return [((float(start[i, 0]), float(start[i, 1]), float(heads[i, 0])),
             (float(goal[i, 0]), float(goal[i, 1]), float(heads[i, 1])), float(rho[i]))
            for i in range(n)]


def pose_error(a, b):
    """Largest of the position error (m) and the heading error modulo 2 pi (rad)."""
    return max(abs(a[0] - b[0]), abs(a[1] - b[1]), abs(math.remainder(a[2] - b[2], TWO_PI)))


def all_words():
    """The 48 word names, built from the nine families' sign patterns and symmetries."""
    bases = [("LSL", "+++"), ("LSR", "+++"), ("LRL", "+-+"), ("LRL", "+--"), ("LRL", "--+"),
             ("LRLR", "++--"), ("LRLR", "+--+"), ("LRSL", "+---"), ("LRSR", "+---"),
             ("LSRL", "---+"), ("RSRL", "---+"), ("LRSLR", "+---+")]
    words = set()
    for kinds, gears in bases:
        for k in (kinds, kinds.translate(str.maketrans("LR", "RL"))):
            for g in (gears, gears.translate(str.maketrans("+-", "-+"))):
                words.add("".join(a + b for a, b in zip(k, g)))
    return words


def test_there_are_48_words():
    assert len(all_words()) == 48


def test_matches_ompl():
    ob = pytest.importorskip("ompl.base")
    spaces = {rho: ob.ReedsSheppStateSpace(rho) for rho in RHOS}
    a, b = spaces[1.0].allocState(), spaces[1.0].allocState()  # SE(2) states, any rho
    worst, count = 0.0, 0
    for p, q, rho in pairs(10_000, seed=1):
        for state, pose in ((a, p), (b, q)):
            state.setX(pose[0])
            state.setY(pose[1])
            state.setYaw(pose[2])
        ours, theirs = rs.length(p, q, rho), spaces[rho].distance(a, b)
        worst = max(worst, abs(ours - theirs) / max(theirs, rho))
        count += 1
    assert count == 10_000
    assert worst <= 1e-9


def test_shortest_and_every_candidate_land_on_the_goal():
    words = set()
    for p, q, rho in pairs(3_000, seed=2):
        found = rs.candidates(p, q, rho)
        best = rs.shortest(p, q, rho)
        assert best.length == found[0].length == rs.length(p, q, rho)
        assert pose_error(rs.integrate(p, best.pieces, rho), q) <= 1e-9
        names = [w.word for w in found]
        assert len(names) == len(set(names)) and set(names) <= all_words()
        for w in found:
            assert pose_error(rs.integrate(p, w.pieces, rho), q) <= 1e-9, w
            assert w.length == pytest.approx(sum(abs(d) for _, d in w.pieces), rel=1e-12)
            assert w.length >= best.length
            assert "".join(k for k, _ in w.pieces) == w.word[::2]
            words.add(w.word)
            for (_, d), gear in zip(w.pieces, w.word[1::2]):  # lengths carry the gears
                assert d == 0.0 or (d > 0.0) == (gear == "+")
            for kind, d in w.pieces:  # no arc is longer than half a turn
                assert kind == "S" or abs(d) <= math.pi * rho * (1 + 1e-12)
    assert words == all_words()  # every word's formula is exercised


def arc_end(seg):
    a = seg["start_angle"] + seg["sweep"]
    c, r = seg["center"], seg["radius"]
    return c[0] + r * math.cos(a), c[1] + r * math.sin(a)


def headings(seg):
    """The car's heading at the start and end of a segment (its travel direction, turned
    round when it drives backward)."""
    back = math.pi if seg.get("reverse") else 0.0
    if seg["type"] == "line":
        h = math.atan2(seg["end"][1] - seg["start"][1], seg["end"][0] - seg["start"][0])
        return h + back, h + back
    turn = math.copysign(math.pi / 2.0, seg["sweep"])  # travel is tangent to the circle
    a = seg["start_angle"]
    return a + turn + back, a + seg["sweep"] + turn + back


def ends(seg):
    if seg["type"] == "line":
        return tuple(seg["start"]), tuple(seg["end"])
    c, r, a = seg["center"], seg["radius"], seg["start_angle"]
    return (c[0] + r * math.cos(a), c[1] + r * math.sin(a)), arc_end(seg)


def test_segments_join_and_measure_the_word():
    for p, q, rho in pairs(2_000, seed=3):
        best = rs.shortest(p, q, rho)
        segs = rs.segments(p, best.pieces, rho)
        total = sum(s["radius"] * abs(s["sweep"]) if s["type"] == "arc"
                    else math.dist(s["start"], s["end"]) for s in segs)
        assert total == pytest.approx(best.length, rel=1e-12, abs=1e-12)
        pose = p
        for seg in segs:
            (start, end), (h0, h1) = ends(seg), headings(seg)
            assert pose_error((*start, h0), pose) <= 1e-9
            if seg["type"] == "arc":
                assert seg["radius"] == rho
                assert math.dist(seg["center"], start) == pytest.approx(rho, rel=1e-12)
            pose = (*end, h1)
        assert pose_error(pose, q) <= 1e-9
        # Cusps: gear changes between consecutive pieces, in the word and in the segments.
        signs = [d > 0.0 for _, d in best.pieces if abs(d) >= rs.TINY]
        gear_changes = sum(a != b for a, b in zip(signs, signs[1:]))
        flags = [bool(s.get("reverse")) for s in segs]
        assert flags == [not s for s in signs]
        assert gear_changes == sum(a != b for a, b in zip(flags, flags[1:]))
        if len(signs) == len(best.pieces):
            assert gear_changes == best.family.count("|")


def test_straight_lines_forward_and_backward():
    p = (1.0, 2.0, math.pi / 6.0)
    u = (math.cos(p[2]), math.sin(p[2]))
    for rho in RHOS:
        for d in (3.0, -3.0, 0.01, -0.01):
            q = (p[0] + d * u[0], p[1] + d * u[1], p[2])
            best = rs.shortest(p, q, rho)
            assert best.length == pytest.approx(abs(d), rel=1e-12)
            moving = [(k, x) for k, x in best.pieces if abs(x) >= rs.TINY]
            assert len(moving) == 1 and moving[0][0] == "S"
            assert moving[0][1] == pytest.approx(d, rel=1e-12)
            [seg] = rs.segments(p, best.pieces, rho)
            assert seg["type"] == "line" and seg.get("reverse", False) == (d < 0)
            assert seg["end"] == pytest.approx([q[0], q[1]], abs=1e-12)


def test_u_turn_is_half_a_circle():
    for rho in RHOS:
        p = (0.5, -1.0, 0.3)
        left = (-math.sin(p[2]), math.cos(p[2]))
        q = (p[0] + 2 * rho * left[0], p[1] + 2 * rho * left[1], p[2] + math.pi)
        best = rs.shortest(p, q, rho)
        assert best.length == pytest.approx(math.pi * rho, rel=1e-12)
        [seg] = rs.segments(p, best.pieces, rho)
        assert seg["type"] == "arc" and "reverse" not in seg
        assert seg["sweep"] == pytest.approx(math.pi, rel=1e-12)  # forward left: CCW
        assert seg["center"] == pytest.approx([p[0] + rho * left[0], p[1] + rho * left[1]])
        # Back from q to p: half of the same circle (forward or backward, a tie).
        [seg] = rs.segments(q, rs.shortest(q, p, rho).pieces, rho)
        assert seg["type"] == "arc" and abs(seg["sweep"]) == pytest.approx(math.pi, rel=1e-12)
        assert seg["center"] == pytest.approx([p[0] + rho * left[0], p[1] + rho * left[1]])


def test_arc_sweeps_follow_turn_and_gear():
    p, rho = (0.0, 0.0, 0.0), 0.5
    expected = {("L", 1.0): 2.0, ("L", -1.0): -2.0, ("R", 1.0): -2.0, ("R", -1.0): 2.0}
    for (kind, d), sweep in expected.items():
        [seg] = rs.segments(p, [(kind, d)], rho)
        assert seg["sweep"] == pytest.approx(sweep)
        assert seg["center"] == pytest.approx([0.0, rho if kind == "L" else -rho])
        assert seg["start_angle"] == pytest.approx(-math.pi / 2 if kind == "L" else math.pi / 2)
        assert seg.get("reverse", False) == (d < 0)
        end = rs.integrate(p, [(kind, d)], rho)
        assert arc_end(seg) == pytest.approx(end[:2], abs=1e-12)
        assert end[2] == pytest.approx(sweep)  # heading turns with the sweep


def test_same_pose_and_bad_radius():
    for p in [(0.0, 0.0, 0.0), (3.0, -2.0, 5.0)]:
        best = rs.shortest(p, p, 0.25)
        assert best.length == 0.0 and rs.segments(p, best.pieces, 0.25) == []
    assert rs.length((0, 0, 0), (0, 0, TWO_PI), 1.0) == 0.0
    for rho in (0.0, -1.0, float("nan")):
        with pytest.raises(ValueError, match="rho"):
            rs.length((0, 0, 0), (1, 0, 0), rho)


def test_rigid_motions_symmetry_and_the_dubins_bound():
    rng = np.random.default_rng(4)
    for p, q, rho in pairs(1_000, seed=5):
        d = rs.length(p, q, rho)
        a, tx, ty = rng.uniform(-math.pi, math.pi), *rng.uniform(-3.0, 3.0, 2)
        c, s = math.cos(a), math.sin(a)

        def move(z):
            return (c * z[0] - s * z[1] + tx, s * z[0] + c * z[1] + ty, z[2] + a)

        assert rs.length(move(p), move(q), rho) == pytest.approx(d, rel=1e-9, abs=1e-12)
        assert rs.length(q, p, rho) == pytest.approx(d, rel=1e-9, abs=1e-12)  # drive it back
        assert d <= dubins.length(p, q, rho) * (1 + 1e-12) + 1e-12
        assert d >= math.dist(p[:2], q[:2]) * (1 - 1e-12)


def test_every_family_and_word_is_shortest_somewhere():
    """Each family is the one chosen for some pair, and each of the 48 words ties for the
    shortest for some pair (C|C|C words tie in pairs, so only one of each is chosen)."""
    chosen, tying = collections.Counter(), set()
    for p, q, rho in pairs(8_000, seed=6, max_dist=6.0) + pairs(8_000, seed=7, max_dist=2.0):
        found = rs.candidates(p, q, rho)
        chosen[found[0].family] += 1
        tying |= {w.word for w in found if w.length <= found[0].length * (1 + 1e-12)}
    assert set(chosen) == set(rs.FAMILIES.values()), chosen
    assert tying == all_words(), all_words() - tying
