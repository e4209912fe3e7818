"""The free-turn model (``turns = "free"``): the exact solver against closed-form Dubins
paths, the tight-rope optimum, and an independent check of every path it returns.

The Dubins closed form below is written from the textbook formulas for the six words
(LSL, RSR, LSR, RSL, RLR, LRL; normalised to rho = 1 with the start turned onto the x
axis), shares no code with hga-jax, and every word it uses is first integrated turn by
turn to confirm that it ends at the goal pose.
"""
from __future__ import annotations

import dataclasses
import math

import _families
import numpy as np
import pytest

from hga_jax import scenario_from_dict
from hga_jax.errors import ModelMismatchError
from hga_jax.model.cars.free_turns import circles, turns
from hga_jax.model.exact import solve

TWO_PI = 2.0 * math.pi
RHO = 0.15


def _m(a: float) -> float:
    return a % TWO_PI


def dubins_words(alpha: float, beta: float, d: float) -> dict[str, tuple[float, float, float]]:
    """The feasible words' three normalised lengths (turns in rad, the straight in rho)."""
    sa, ca, sb, cb = math.sin(alpha), math.cos(alpha), math.sin(beta), math.cos(beta)
    cab = math.cos(alpha - beta)
    out = {}
    p2 = 2 + d * d - 2 * cab + 2 * d * (sa - sb)
    if p2 >= 0:
        th = math.atan2(cb - ca, d + sa - sb)
        out["LSL"] = (_m(-alpha + th), math.sqrt(p2), _m(beta - th))
    p2 = 2 + d * d - 2 * cab + 2 * d * (sb - sa)
    if p2 >= 0:
        th = math.atan2(ca - cb, d - sa + sb)
        out["RSR"] = (_m(alpha - th), math.sqrt(p2), _m(-beta + th))
    p2 = -2 + d * d + 2 * cab + 2 * d * (sa + sb)
    if p2 >= 0:
        p = math.sqrt(p2)
        th = math.atan2(-ca - cb, d + sa + sb) - math.atan2(-2.0, p)
        out["LSR"] = (_m(-alpha + th), p, _m(-_m(beta) + th))
    p2 = -2 + d * d + 2 * cab - 2 * d * (sa + sb)
    if p2 >= 0:
        p = math.sqrt(p2)
        th = math.atan2(ca + cb, d - sa - sb) - math.atan2(2.0, p)
        out["RSL"] = (_m(alpha - th), p, _m(beta - th))
    c = (6 - d * d + 2 * cab + 2 * d * (sa - sb)) / 8
    if abs(c) <= 1:
        p = _m(TWO_PI - math.acos(c))
        t = _m(alpha - math.atan2(ca - cb, d - sa + sb) + p / 2)
        out["RLR"] = (t, p, _m(alpha - beta - t + p))
    c = (6 - d * d + 2 * cab + 2 * d * (sb - sa)) / 8
    if abs(c) <= 1:
        p = _m(TWO_PI - math.acos(c))
        t = _m(-alpha - math.atan2(ca - cb, d + sa - sb) + p / 2)
        out["LRL"] = (t, p, _m(_m(beta) - alpha - t + p))
    return out


def integrate(pose, word: str, lengths, rho: float):
    """The pose after driving ``word`` (L: left turn, R: right, S: straight)."""
    x, y, th = pose
    for ch, u in zip(word, lengths):
        if ch == "S":
            x, y = x + rho * u * math.cos(th), y + rho * u * math.sin(th)
        else:
            s = 1.0 if ch == "L" else -1.0
            cx, cy = x - s * rho * math.sin(th), y + s * rho * math.cos(th)
            th += s * u
            x, y = cx + s * rho * math.sin(th), cy - s * rho * math.cos(th)
    return x, y, th


def dubins(q0, q1, rho: float) -> tuple[float, str]:
    """The shortest Dubins path from pose ``q0`` to ``q1``: (length, word)."""
    dx, dy = q1[0] - q0[0], q1[1] - q0[1]
    dist = math.hypot(dx, dy)
    theta = _m(math.atan2(dy, dx)) if dist > 0 else 0.0
    best, word = math.inf, ""
    for w, u in dubins_words(_m(q0[2] - theta), _m(q1[2] - theta), dist / rho).items():
        x, y, th = integrate(q0, w, u, rho)
        miss = max(abs(x - q1[0]), abs(y - q1[1]), abs(math.remainder(th - q1[2], TWO_PI)))
        assert miss < 1e-9, f"closed form {w} misses the goal by {miss}"
        if rho * sum(u) < best:
            best, word = rho * sum(u), w
    return best, word


def pose_scene(q0, q1, rho=RHO, obstacles=(), field=None) -> dict:
    d = {"name": "pair", "robot": {"radius": 0.09, "min_turn_radius": rho},
         "start": {"x": q0[0], "y": q0[1], "heading_deg": math.degrees(q0[2])},
         "goal": {"x": q1[0], "y": q1[1], "heading_deg": math.degrees(q1[2])},
         "obstacles": [dict(o) for o in obstacles]}
    if field:
        d["field"] = field
    return d


def check_path(sc, segments, length: float) -> None:
    """An independent float64 check of a segment list: it starts at the start pose and
    ends at the goal pose, consecutive pieces meet in position and heading, every arc
    has radius rho or more, the pieces add up to ``length``, and dense samples keep the
    model clearance and stay in the kept field."""
    pose = (float(sc.start[0]), float(sc.start[1]), float(sc.start[2]))
    total = 0.0
    pts = []
    for seg in segments:
        if seg["type"] == "line":
            (x0, y0), (x1, y1) = seg["start"], seg["end"]
            h = math.atan2(y1 - y0, x1 - x0)
            ln = math.hypot(x1 - x0, y1 - y0)
            assert ln > 1e-9, "a phantom line between touching circles"
            head0 = head1 = h
            t = np.linspace(0.0, 1.0, 200)
            pts.append(np.stack([x0 + t * (x1 - x0), y0 + t * (y1 - y0)], 1))
        else:
            (cx, cy), r, a0, sw = seg["center"], seg["radius"], seg["start_angle"], seg["sweep"]
            assert r >= sc.min_turn_radius - 1e-12
            x0, y0 = cx + r * math.cos(a0), cy + r * math.sin(a0)
            x1, y1 = cx + r * math.cos(a0 + sw), cy + r * math.sin(a0 + sw)
            s = 1.0 if sw > 0 else -1.0
            head0, head1 = a0 + s * math.pi / 2, a0 + sw + s * math.pi / 2
            ln = r * abs(sw)
            a = a0 + sw * np.linspace(0.0, 1.0, max(16, int(abs(sw) * 200)))
            pts.append(np.stack([cx + r * np.cos(a), cy + r * np.sin(a)], 1))
        assert math.hypot(x0 - pose[0], y0 - pose[1]) < 1e-9
        assert abs(math.remainder(head0 - pose[2], TWO_PI)) < 1e-7
        pose, total = (x1, y1, head1), total + ln
    assert math.hypot(pose[0] - sc.goal[0], pose[1] - sc.goal[1]) < 1e-9
    assert abs(math.remainder(pose[2] - sc.goal[2], TWO_PI)) < 1e-7
    assert total == pytest.approx(length, rel=1e-9, abs=1e-12)
    if pts and sc.n:
        p = np.concatenate(pts)
        gap = np.hypot(p[:, None, 0] - sc.centres[:, 0], p[:, None, 1] - sc.centres[:, 1])
        assert (gap - sc.model_radii).min() > -1e-7
    if pts:
        p, (x0, x1, y0, y1) = np.concatenate(pts), sc.bounds
        assert p[:, 0].min() > x0 - 1e-7 and p[:, 0].max() < x1 + 1e-7
        assert p[:, 1].min() > y0 - 1e-7 and p[:, 1].max() < y1 + 1e-7


def _pairs(count: int, seed: int):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        r, b = rng.uniform(0.0, 5.0) * RHO, rng.uniform(-math.pi, math.pi)
        x0, y0 = rng.uniform(-1.0, 1.0, 2)
        q0 = (float(x0), float(y0), float(rng.uniform(-math.pi, math.pi)))
        yield q0, (q0[0] + r * math.cos(b), q0[1] + r * math.sin(b),
                   float(rng.uniform(-math.pi, math.pi)))


def test_pure_dubins_matches_the_closed_form_on_3000_pairs():
    words, checked = {}, 0
    for q0, q1 in _pairs(3000, 1):
        sc = scenario_from_dict(pose_scene(q0, q1), "pair")
        ref, word = dubins(sc.start, sc.goal, RHO)  # the poses as loaded (degrees round trip)
        length, segs, _, free = turns.shortest(sc)
        assert abs(length - ref) <= 1e-9 * RHO, (q0, q1, word, length, ref)
        assert (free > 0) == (word in ("RLR", "LRL")) or abs(length - ref) < 1e-12
        if checked < 300:
            check_path(sc, segs, length)
            checked += 1
        words[word] = words.get(word, 0) + 1
    assert set(words) == {"LSL", "RSR", "LSR", "RSL", "RLR", "LRL"}
    assert words["RLR"] + words["LRL"] > 150  # the turn-turn-turn words are exercised


@pytest.mark.parametrize("family", _families.FAMILIES)
def test_free_turn_optimum_is_checked_and_bounded(family):
    """On scenes with obstacles: never longer than the tight-rope optimum, never shorter
    than the Dubins distance ignoring obstacles, and the path passes the check."""
    for i, d in enumerate(_families.scenes(family, 31, 6)):
        sc = scenario_from_dict(d, f"{family}{i}")
        free = solve(sc, turns="free")  # solves the tight-rope model too
        tight = free.tight_rope_length
        assert free.turns == "free"
        if not math.isfinite(tight):
            continue
        assert free.length <= tight * (1 + 1e-12)
        # The closed form takes square roots of near-zero terms in degenerate scenes
        # (a goal on a start circle), so it is good to about sqrt(rounding) only.
        assert free.length >= dubins(sc.start, sc.goal, sc.min_turn_radius)[0] - 1e-7
        check_path(sc, free.segments, free.length)


def _loop_scene():
    """Goal just beside the start, facing back: a turn-turn-turn word, with obstacles
    that leave the free loop open and a field that holds it."""
    obstacles = [{"x": -0.3, "y": 0.35, "radius": 0.05}, {"x": 0.6, "y": 0.0, "radius": 0.05},
                 {"x": -0.2, "y": -0.4, "radius": 0.04}]
    field = {"xmin": -1.0, "xmax": 1.2, "ymin": -1.0, "ymax": 1.0, "keep_inside": True}
    return scenario_from_dict(pose_scene((0.0, 0.0, 0.0), (0.1, 0.05, math.pi),
                                         obstacles=obstacles, field=field), "loop")


def test_a_free_loop_beats_the_tight_rope_and_is_drawn():
    from hga_jax.host.plots import plot_path
    from hga_jax.host.report import exact_summary

    sc = _loop_scene()
    tight, free = solve(sc), solve(sc, turns="free")
    ref, word = dubins(sc.start, sc.goal, RHO)
    assert word in ("RLR", "LRL") and free.length == pytest.approx(ref, abs=1e-9 * RHO)
    assert free.free_arcs == 1 and free.length < 0.7 * tight.length
    assert not free.expressible and free.best_expressible.length == pytest.approx(tight.length)
    check_path(sc, free.segments, free.length)
    d = free.to_dict()
    assert d["turns"] == "free" and d["tight_rope_length"] == tight.length
    assert sum(bool(s.get("free")) for s in d["segments"]) == 1
    assert f"{tight.length:.6f}" in exact_summary(sc, free)
    fig = plot_path(sc, free.segments)
    assert [ln for ln in fig.axes[0].lines if ln.get_gid() == "free_arc"]


def test_tight_rope_model_is_the_default_and_unchanged():
    sc = _loop_scene()
    a, b = solve(sc), solve(sc, turns="tight-rope")
    da, db = a.to_dict(), b.to_dict()
    da.pop("seconds"), db.pop("seconds")
    assert da == db and a.turns == "tight-rope" and a.free_arcs == 0
    assert not any("free" in s for s in a.segments)
    with pytest.raises(ValueError, match="turns"):
        solve(sc, turns="loose")
    with pytest.raises(ValueError, match="full collision"):
        solve(sc, "paper", turns="free")


def test_free_circles_are_pinned_by_two_contacts():
    sc = _loop_scene()
    fx, fy, fs = circles.free_circles(sc)
    x, y, r, _, _ = sc.circles(np.float64)
    anchors = np.concatenate([np.stack([x[:4], y[:4], r[:4]], 1),
                              np.stack([x[4::2], y[4::2], r[4::2]], 1)])
    b = sc.bounds
    for cx, cy in zip(fx, fy):
        gaps = np.abs(np.hypot(anchors[:, 0] - cx, anchors[:, 1] - cy) - anchors[:, 2] - RHO)
        walls = np.abs(np.array([cx - b[0], b[1] - cx, cy - b[2], b[3] - cy]) - RHO)
        assert (gaps < 1e-9).sum() + (walls < 1e-9).sum() >= 2
    assert set(np.unique(fs)) <= {-1.0, 1.0}


def test_a_longer_free_optimum_is_a_bug_not_an_answer(monkeypatch):
    sc = _loop_scene()
    monkeypatch.setattr(turns, "shortest", lambda s, bound=None: (99.0, [], [], 0))
    with pytest.raises(ModelMismatchError):
        solve(sc, turns="free")


def test_exact_command_with_free_turns(tmp_path, capsys):
    import json

    from hga_jax.host.cli import main
    from hga_jax.study.scenes import to_toml

    d = pose_scene((0.0, 0.0, 0.0), (0.1, 0.05, math.pi), obstacles=[
        {"x": -0.3, "y": 0.35, "radius": 0.05}, {"x": 0.6, "y": 0.0, "radius": 0.05},
        {"x": -0.2, "y": -0.4, "radius": 0.04}])
    path = tmp_path / "loop.toml"
    path.write_text(to_toml(d))
    out = tmp_path / "free"
    assert main(["exact", str(path), "--turns", "free", "--out", str(out), "--plot"]) == 0
    printed = capsys.readouterr().out
    tight = solve(scenario_from_dict(d, "loop")).length
    assert "free-turn optimum" in printed and f"tight-rope optimum {tight:.6f} m" in printed
    data = json.loads((out / "result.json").read_text())
    assert data["settings"]["turns"] == "free"
    assert data["summary"]["tight_rope_length"] == pytest.approx(tight)
    assert data["summary"]["free_to_tight_rope"] < 0.7
    assert [s for s in data["optimum"]["segments"] if s.get("free")]
    assert (out / "path.png").stat().st_size > 10_000
    assert data["best"]["feasible"] and data["best"]["upper"] is None  # no chromosome
    from hga_jax.host.report import redraw

    fig = redraw(str(out / "result.json"))
    assert [ln for ln in fig.axes[0].lines if ln.get_gid() == "free_arc"]
    assert "no feasible path" not in fig.axes[0].get_title()
    capsys.readouterr()
    code = main(["exact", str(path), "--turns", "free", "--collision", "paper",
                 "--out", str(tmp_path / "p")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and "collision" in err[0] and "--turns" in err[0]
    assert not (tmp_path / "p").exists()


def test_run_measures_gaps_against_the_free_turn_optimum(tmp_path):
    from hga_jax import run_many
    from hga_jax.host.report import run_summary

    sc = _loop_scene()
    res = run_many(sc, "paper", runs=4, seed=3, turns="free")
    tight = solve(sc).length
    assert res.optimum.turns == "free" and res.optimum_length < 0.7 * tight
    assert not res.hit.any() and (res.gap[res.feasible] > 0.4).all()
    s = res.summary()
    assert s["optimum_turns"] == "free" and s["tight_rope_length"] == tight
    text = run_summary(res)
    assert "free-turn optimum" in text and f"tight-rope optimum {tight:.6f} m" in text
    with pytest.raises(Exception, match="full collision"):
        run_many(sc, dataclasses.replace(res.settings, collision="paper"), turns="free")


@pytest.mark.slow  # a study run; the free-turn optimum's own tests stay in the default lane
def test_a_study_can_take_the_free_turn_optimum_as_its_yardstick(tmp_path):
    from hga_jax.errors import ConfigError
    from hga_jax.study.config import load_study
    from hga_jax.study.run import run_study
    from hga_jax.study.scenes import to_toml

    d = pose_scene((0.0, 0.0, 0.0), (0.1, 0.05, math.pi), obstacles=[
        {"x": 0.6, "y": 0.0, "radius": 0.05}])
    (tmp_path / "loop.toml").write_text(to_toml(d))
    text = ('name = "free_yard"\nseed = 1\nruns = 3\nscenarios = ["loop.toml"]\n'
            'yardstick = "free"\n[ga]\ngenerations = 3\n[[configs]]\nlabel = "paper"\n')
    (tmp_path / "s.toml").write_text(text)
    out = run_study(str(tmp_path / "s.toml"), out=str(tmp_path / "o"), progress=False,
                    figures=False)
    assert out.cells_run == 1
    md = (tmp_path / "o" / "summary.md").read_text()
    assert "free-turn optimum" in md
    import json
    cell = json.loads(next((tmp_path / "o" / "cells").iterdir()).read_text())
    tight = solve(scenario_from_dict(d, "loop")).length
    assert cell["yardstick"] == "free" and cell["tight_rope_optimum"] == pytest.approx(tight)
    assert cell["optimum"] < 0.7 * tight and not any(cell["columns"]["hit"])
    assert run_study(str(tmp_path / "s.toml"), out=str(tmp_path / "o"), progress=False,
                     figures=False).cells_run == 0
    (tmp_path / "bad.toml").write_text(text.replace('"free"', '"loose"'))
    with pytest.raises(ConfigError, match=r"bad\.toml: yardstick: must be one of"):
        load_study(str(tmp_path / "bad.toml"))
    (tmp_path / "paper.toml").write_text(text + 'collision = "paper"\n')
    with pytest.raises(ConfigError, match="yardstick: free turns need the full collision"):
        load_study(str(tmp_path / "paper.toml"))


WALLS = {"xmin": 0.0, "xmax": 2.8, "ymin": 0.0, "ymax": 2.3, "keep_inside": True}


@pytest.mark.parametrize("q0, q1, tight_feasible", [
    ((0.2916205192563336, 0.5715561548830335, 1.473891711134418),
     (0.3445059186125689, 0.5284886189003957, 0.10518166948605545), True),
    ((0.29486555656721924, 1.4220862708320046, 1.387152451979829),
     (0.29211857783247897, 1.4289117753871088, -0.4135617734543251), False),
])
def test_a_free_loop_held_by_a_wall(q0, q1, tight_feasible):
    """Poses near the field's edge: the loop that turns the car round is pinned by the
    wall (its centre rho from the shrunk field), so the path is longer than the Dubins
    distance but shorter than any tight rope (or the only feasible path at all)."""
    sc = scenario_from_dict(pose_scene(q0, q1, field=WALLS), "wall")
    free = solve(sc, turns="free")
    check_path(sc, free.segments, free.length)
    assert free.length > dubins(sc.start, sc.goal, RHO)[0] + 1e-3
    assert math.isfinite(free.tight_rope_length) == tight_feasible
    if tight_feasible:
        assert free.length < free.tight_rope_length - 1e-3
    b = sc.bounds
    held = [min(abs(s["center"][0] - b[0]), abs(b[1] - s["center"][0]),
                abs(s["center"][1] - b[2]), abs(b[3] - s["center"][1])) - RHO
            for s in free.segments if s.get("free")]
    assert held and min(abs(h) for h in held) < 1e-9


def test_free_legs_express_every_dubins_word():
    """A chromosome with one gene per leg (straight, or a free circle touching both
    neighbours) reaches the Dubins distance between any two poses."""
    from hga_jax.model.cars.free_turns import leg_space

    for q0, q1 in _pairs(400, 5):
        sc = scenario_from_dict(pose_scene(q0, q1), "pair")
        length, segs, _, _ = leg_space.shortest(sc)
        assert abs(length - dubins(sc.start, sc.goal, RHO)[0]) <= 1e-9 * RHO
        check_path(sc, segs, length)


@pytest.mark.parametrize("family", ["grid", "random"])
def test_free_legs_lie_between_the_two_optima(family):
    from hga_jax.model.cars.free_turns import leg_space
    from hga_jax.model.cars.free_turns import legs as free_legs

    for i, d in enumerate(_families.scenes(family, 31, 6)):
        sc = scenario_from_dict(d, f"{family}{i}")
        free = solve(sc, turns="free")
        length, segs, _, arcs = leg_space.shortest(sc)
        assert free.length <= length + 1e-9 and length <= free.tight_rope_length + 1e-9
        if math.isfinite(length):
            check_path(sc, segs, length)
        if arcs:  # only a free leg beats the tight rope
            assert length < free.tight_rope_length
    legs = free_legs.table(_loop_scene())
    assert legs.S.size and np.all(legs.sign == -np.asarray(_loop_scene().circles()[3])[legs.S])
