"""The windows in time of the turn table among robots that move (hga_jax/model/in_time/windows.py):
each window by hand and against the tests it stands for, and the table's look-ups against
the decoder's tests in time, chromosome by chromosome."""
from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path

import jax
import numpy as np
import pytest

from hga_jax.model import car_model
from hga_jax.model.decode import decode_batch
from hga_jax.model.fitness import evaluate
from hga_jax.model.in_time import clearance
from hga_jax.model.in_time import windows as tw

ROOT = Path(__file__).resolve().parents[1]


def _fuzz():
    spec = importlib.util.spec_from_file_location(
        "fuzz_moving", ROOT / "experiments" / "fuzz_moving.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


fuzz = _fuzz()


def test_a_robot_crossing_a_line_by_hand():
    """The car drives (0, 0) -> (3, 0) in 3 s; a robot starts at (1.5, -1.5) going up at
    1 m/s, R = 0.2. Started at T, the offset u = tau - 1.5 gives the squared distance u^2 +
    (u + T)^2, least T^2 / 2: the start times within 0.2 sqrt(2) of 0 collide."""
    lo, hi = tw.line_window(0.0, 0.0, 3.0, 0.0, 3.0, 1.5, -1.5, 0.0, 1.0, 0.2)
    assert float(lo) == pytest.approx(-0.2 * math.sqrt(2.0), abs=1e-12)
    assert float(hi) == pytest.approx(0.2 * math.sqrt(2.0), abs=1e-12)


def test_a_robot_that_never_comes_near_has_no_window():
    """A robot driving parallel to the line 0.5 m away (R = 0.2): no start time collides."""
    lo, hi = tw.line_window(0.0, 0.0, 3.0, 0.0, 3.0, 0.0, 0.5, 1.0, 0.0, 0.2)
    assert not float(lo) < float(hi)


def test_line_windows_agree_with_the_clamped_quadratic():
    """Random chords and robots: a start time inside the window comes closer than the reach
    (clearance.chord_reach), one outside does not, away from the window's ends."""
    rng = np.random.default_rng(3)
    k = 4000
    x0, y0, x1, y1 = rng.uniform(-1, 1, (4, k))
    h = rng.uniform(0.0, 2.0, k)
    ox, oy = rng.uniform(-2, 2, (2, k))
    vx, vy = rng.uniform(-1.5, 1.5, (2, k))
    vx[:50] = vy[:50] = 0.0  # standing centres too
    x1[50:100], y1[50:100], h[50:100] = x0[50:100], y0[50:100], 0.0  # points
    reach = rng.uniform(0.05, 0.5, k)
    lo, hi = tw.line_window(x0, y0, x1, y1, h, ox, oy, vx, vy, reach)
    times = np.linspace(-6.0, 6.0, 601)[:, None]
    d2 = clearance.chord_reach(x0, y0, x1, y1, times, h, ox, oy, vx, vy)
    close = d2 < reach * reach
    inside = (lo < times) & (times < hi)
    clear = (np.abs(times - lo) > 1e-9) & (np.abs(times - hi) > 1e-9)
    assert np.array_equal(close[clear], inside[clear])
    assert close.any() and (~close).any()


def test_merge_keeps_the_largest_gap():
    lo = np.array([[5.0, 0.0, 2.0, 3.0, 9.0]])
    hi = np.array([[6.0, 1.0, 3.0, 1.0, 9.0]])  # the last two are empty
    mlo, mhi = tw.merge(lo, hi, 2)
    assert mlo.tolist() == [[0.0, 5.0]] and mhi.tolist() == [[3.0, 6.0]]
    mlo, mhi = tw.merge(lo, hi, 3)  # room for every piece of the union
    assert mlo.tolist() == [[0.0, 2.0, 5.0]] and mhi.tolist() == [[1.0, 3.0, 6.0]]
    mlo, mhi = tw.merge(np.array([[0.0, 1.0]]), np.array([[2.0, 3.0]]), 2)  # overlapping
    assert mlo[0, 0] == 0.0 and mhi[0, 0] == 3.0 and not mlo[0, 1] < mhi[0, 1]
    mlo, mhi = tw.merge(np.array([[1.0, 1.0]]), np.array([[0.0, 1.0]]), 2)  # none
    assert not (mlo < mhi).any()


def test_merged_windows_hold_the_union_and_are_exact_when_few():
    """Random unions of 8 intervals: every point of the union is in the merged windows;
    where the union has at most 2 pieces nothing else is."""
    rng = np.random.default_rng(5)
    lo = rng.uniform(0, 10, (3000, 8))
    hi = lo + rng.uniform(-1.0, 2.0, (3000, 8))
    mlo, mhi = tw.merge(lo, hi, 2)
    x = np.linspace(-1, 13, 1401)
    union = ((lo[..., None] < x) & (x < hi[..., None])).any(1)
    held = ((mlo[..., None] < x) & (x < mhi[..., None])).any(1)
    assert not (union & ~held).any()
    pieces = np.array([_pieces(a, b) for a, b in zip(lo, hi)])
    few = pieces <= 2
    assert few.sum() > 100 and (~few).sum() > 100
    assert np.array_equal(union[few], held[few])


def _pieces(lo, hi) -> int:
    """How many disjoint open intervals the union of ``(lo, hi)`` is (counted exactly)."""
    spans = sorted((a, b) for a, b in zip(lo, hi) if a < b)
    count, end = 0, -math.inf
    for a, b in spans:
        if a >= end:
            count += 1
        end = max(end, b)
    return count


def test_own_windows_agree_with_the_own_reach_bound():
    """An arc of radius r round a moving robot's circle placed at time 0.7: every start time
    inside the windows makes clearance.own_reach call the sub-arc too close, and none outside."""
    r, k, tol = 0.2, 8, 1e-5
    rng = np.random.default_rng(11)
    held = 0
    for _ in range(40):
        a0, swp = rng.uniform(0, 2 * math.pi), rng.uniform(0.1, 2 * math.pi - 0.1)
        vx, vy = rng.uniform(-1.5, 1.5, 2)
        speed, placed = rng.uniform(1.0, 2.0), 0.7
        ang = a0 + swp * np.arange(k + 1) / k  # counter-clockwise
        px, py = r * np.cos(ang), r * np.sin(ang)
        h = r * swp / k / speed
        times = np.linspace(-1.0, 3.0, 2001)
        for i in range(k):
            mx, my = 0.5 * (px[i] + px[i + 1]), 0.5 * (py[i] + py[i + 1])
            norm = math.hypot(mx, my)
            lo, hi = tw.own_windows(mx / norm, my / norm, vx, vy, r, h, i, placed, swp, k, tol)
            inside = ((lo[:, None] < times) & (times < hi[:, None])).any(0)
            bound = clearance.own_reach([px[i], px[i + 1]], [py[i], py[i + 1]], 0.0, 0.0, r,
                                     times + i * h, h, vx, vy, placed, swp / k, tol)
            # (sub-arc i alone: it starts i h after the arc; its angle is swp / k)
            clear = ((np.abs(times[:, None] - lo) > 1e-9) & (np.abs(times[:, None] - hi) > 1e-9)).all(1)
            assert np.array_equal(inside[clear], np.asarray(bound)[clear])
            held += int(inside.sum())
    assert held > 1000  # the robot's own circle does come too close, at some times


def _lookups_and_decoder(d: dict, model: str, collision: str, rows: int, seed: int):
    """The table, the look-ups' evaluation, and the violations in time of each: the
    look-ups' less those of the table's static columns alone, and the decoder's tests in
    time (its static part reads the float32 tangent table, the turn table the float64 one:
    they may differ on the paper's criterion in near-degenerate geometry)."""
    sc = fuzz.build(d)
    sa = car_model.get(model).search_arrays(sc, np.float32, collision)
    rng = np.random.default_rng(seed)
    perm, labels, legs = fuzz.chromosomes(rng, model, sc.n, rows)
    field = "turns_free" if legs is not None else (
        "turns_full" if collision == "full" else "turns_paper")
    table = getattr(sa, field)

    def ev(arrays):
        return jax.jit(lambda p, lab, lg: evaluate(arrays, p, lab, collision, lg))(
            perm, labels, legs)

    e = ev(sa)
    e0 = ev(sa._replace(**{field: np.asarray(table)[:, :2]}))
    untimed = sa._replace(motion=None, **{field: None})
    dec = jax.jit(lambda p, lab, lg: decode_batch(untimed, p, lab, collision, lg))(
        perm, labels, legs)
    motion = jax.tree.map(jax.numpy.asarray, sa.motion)
    in_time = jax.jit(lambda d: clearance.violations(d, motion, sc.n))(dec)
    # A wrap's violation (wrap_moving "never") is in the table's static columns.
    mover = np.isin(np.asarray(dec.obstacle), np.asarray(motion.index))
    real = np.arange(mover.shape[1])[None] < np.asarray(dec.count)[:, None]
    wraps = int(motion.wrap_penalty) * (mover & real).sum(1)
    return (table, e, np.asarray(e.violations) - np.asarray(e0.violations), dec,
            np.asarray(in_time) - wraps)


CASES = [("tight-rope", "full", "at-pass"), ("tight-rope", "full", "given"),
         ("tight-rope", "full", "never"), ("tight-rope", "paper", "at-pass"),
         ("tight-rope", "paper", "given"), ("free", "full", "given"),
         ("free", "full", "never")]
"""(The Reeds–Shepp car's turn table at 9 robots is too large to be given windows
(``windows.fits``): its fitness decodes, as the fuzz of tests/test_moving.py checks.)"""


@pytest.mark.parametrize(("model", "collision", "mode"), CASES)
def test_lookups_count_what_the_decoder_counts(model, collision, mode):
    """Random scenes of 9 robots, 5 moving, and 2,000 random chromosomes each: the table's
    look-ups (windows in time) give the decoder's length and violations in time (its
    sub-arc tests): the same count on every chromosome but the rare one whose float32
    times fall within rounding of a window's end."""
    rng = np.random.default_rng(CASES.index((model, collision, mode)))
    same = total = clear = 0
    for s in range(2):
        _, d = fuzz.scene(rng, fuzz.car_of(model), n=9, m=5)
        if mode == "given":
            d["placed"] = rng.uniform(0.0, 3.0, 9).tolist()
        else:
            d["wrap_moving"] = mode
        table, e, v1, dec, v2 = _lookups_and_decoder(d, model, collision, 2000, s)
        assert table is not None and table.shape[1] > 2  # windows in time
        assert np.allclose(np.asarray(e.length), np.asarray(dec.length), atol=2e-5)
        same += int((v1 == v2).sum())
        total += v1.size
        clear += int((v2 == 0).sum())
    assert same >= total - 2, (same, total)
    assert 0 < clear < total


def test_the_table_keeps_only_the_windows_that_hold_a_time():
    """The bundled scene of moving robots: every turn keeps at most the columns of its
    busiest, a multiple of tw.BLOCK, and the windows dropped were empty."""
    from hga_jax import load_scenario

    sc = load_scenario(ROOT / "configs" / "scenarios" / "moving_robots.toml")
    sa64 = sc.arrays(np.float64)
    static = sc.search_arrays(np.float64, "full")
    table = np.asarray(static.turns_full)
    c = np.asarray(sa64.tangents.circles).shape[0]
    full = tw.build(sa64.tangents, np.asarray(sa64.start), np.asarray(sa64.goal), sa64.motion,
                    _movers(sc), clearance.SUBARCS_64, 1e-7,
                    arrival=tw.soonest(table[:, 0], c))
    wide = full.reshape(full.shape[0], -1, 2)
    kept = table[:, 2:].reshape(table.shape[0], -1, 2)
    real = (wide[..., 0] < wide[..., 1]).sum(1)
    assert kept.shape[1] % tw.BLOCK == 0 and kept.shape[1] < wide.shape[1]
    assert kept.shape[1] - tw.BLOCK < real.max() <= kept.shape[1]
    assert np.array_equal((kept[..., 0] < kept[..., 1]).sum(1), real)


def _movers(sc):
    out = np.full(sc.n, -1)
    idx = np.flatnonzero(sc.moving)
    out[idx] = np.arange(idx.size)
    return out


def test_no_path_arrives_sooner_than_the_bound():
    """Random tight-rope chromosomes on a random scene: the metres each path has driven when
    it arrives on each circle of it are at least tw.soonest's bound for that (leg, circle),
    less the margin the table takes off it, and the bound is reached by some (the start
    circles' rows are 0)."""
    from hga_jax.model.decode import _path_circles

    rng = np.random.default_rng(9)
    _, d = fuzz.scene(rng, n=7, m=3)
    sc = fuzz.build(d)
    sa64 = sc.arrays(np.float64)
    static = np.asarray(sc.search_arrays(np.float64, "full").turns_full)
    c = np.asarray(sa64.tangents.circles).shape[0]
    bound = tw.soonest(static[:, 0], c)
    perm, labels, _ = fuzz.chromosomes(rng, "tight-rope", sc.n, 3000)
    dec = decode_batch(sa64._replace(motion=None), perm, labels, "full")
    count, ids, _ = _path_circles(jax.numpy.asarray(perm), jax.numpy.asarray(labels))
    ids, count = np.asarray(ids).T, np.asarray(count)  # (B, S)
    arcs, lines = np.asarray(dec.arcs), np.asarray(dec.lines)
    r = np.asarray(dec.circles)[..., 2]
    piece = r[:, :-1] * arcs[:, :-1, 4] + np.hypot(lines[:, :, 2] - lines[:, :, 0],
                                                   lines[:, :, 3] - lines[:, :, 1])
    driven = np.concatenate([np.zeros((piece.shape[0], 1)), np.cumsum(piece, axis=1)], axis=1)
    slack = []
    for k in range(perm.shape[0]):
        for s in range(1, int(count[k])):
            slack.append(driven[k, s] - bound[ids[k, s - 1], ids[k, s]])
    slack = np.array(slack)
    assert slack.min() > -tw.SOONEST_MARGIN / 2
    assert np.isclose(slack, 0.0, atol=1e-6).any()
    assert bound[c, 0] == 0.0 and bound[c, 1] == 0.0
