"""The Reeds–Shepp car's tangent graph: free turns travelled both ways, with cusps.

A car that also reverses draws the curves of the forward car, arcs of radius at least
rho and tangent lines, but its direction of travel may flip at a *cusp*, where it
stops and changes gear: its heading stays continuous, so the direction of travel
turns by exactly pi there. Driven backward, a turn goes round its circle the other
way. In terms of the curve it draws, the reversing car therefore

- leaves the start on each of its turning circles in both senses (forward: the
  sense of the turn, as the forward car; backward: the other) and arrives on the
  goal's turning circles likewise (circles ``C .. C + 3``, ``C = 2n + 4``: the start's
  left and right turning circles travelled backward, then the goal's);
- may pass from one circle to another where they touch and their directions of
  travel are opposite (one sense touching from outside, opposite senses one inside
  the other): a cusp, a piece of length 0 at the contact point;
- turns on free circles of radius rho held by two contacts, in either sense, since
  a contact may be a cusp (:func:`hga_jax.model.cars.free_turns.circles.free_circles`, ``both``),
  and on *quarter-turn* circles (:func:`quarter_turns`): a free circle met at a cusp
  on one circle, turned a quarter of a turn and left along a tangent to another
  circle, or the same driven the other way (Reeds and Shepp's C|C(pi/2)SC words,
  whose middle arc is a quarter turn at an optimum);
- and drives every Reeds–Shepp word from the start pose to the goal pose that is
  clear of the obstacles and the field (:mod:`hga_jax.model.cars.reeds_shepp.closed_form`), a piece of
  its own, so that with no obstacles the optimum is the closed form.

Free circles are held by the scenario's circles (pose circles, model circles, walls);
two free circles that touch each other are not joined. The gear is part of the state:
the graph is laid out twice, once per gear (nodes ``0 .. N - 1`` forward, ``N .. 2N - 1``
backward). A walk begins forward at the start point on a start circle travelled in the
sense of its turn, or backward on one travelled the other way; it ends likewise at the
goal; a cusp passes to the other gear, every other piece stays in its gear, and a word
goes from the gear of its first piece to the gear of its last (its pieces carry their
own). Host code (numpy, float64); metres and radians.
"""
from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from hga_jax.model import circle_ids as ids
from hga_jax.model import collision as col
from hga_jax.model import geometry as g
from hga_jax.model import tangent_graph
from hga_jax.model.cars.free_turns import circles as free_circles
from hga_jax.model.cars.free_turns import turns as free_turns
from hga_jax.model.graph_search import Graph, search
from hga_jax.model.scenario import Scenario
from hga_jax.model.touch import Touch

TOL = g.tolerances(np.float64)


class Pieces(NamedTuple):
    """The straight pieces of the graph, in order: tangents, then cusps, then words.
    ``words``: per word piece its segments (result-file dicts, gears included)."""

    pieces: tuple
    tangents: int
    cusps: int
    words: list[list[dict[str, Any]]]


GRID = 720  # contact angles tried per pair of circles for a quarter-turn circle


class Quarter(NamedTuple):
    """Quarter-turn routes (:func:`quarter_routes`), one row each: the anchor ``a`` (a
    pose circle) and the circle ``b`` the route joins, whether it ``leaves`` the anchor
    (a start circle) or arrives on it (a goal circle), the contact point P on ``a``, the
    free circle's centre F and sense (``a``'s), the tangent between F and ``b`` (as
    :func:`hga_jax.model.geometry.tangent` gives it, from ``b`` to F when arriving) and
    its length, and the sweep on F between P and the tangent (rad)."""

    a: np.ndarray
    b: np.ndarray
    leaves: np.ndarray
    px: np.ndarray
    py: np.ndarray
    fx: np.ndarray
    fy: np.ndarray
    sign: np.ndarray
    t1x: np.ndarray
    t1y: np.ndarray
    t2x: np.ndarray
    t2y: np.ndarray
    length: np.ndarray
    sweep: np.ndarray


def quarter_routes(sc: Scenario, circ, back: int, bound: float = math.inf) -> Quarter:
    """The quarter-turn routes of the circles ``circ`` (``(x, y, r, sign, own)``: the
    scenario's, and from ``back`` on the four pose circles driven backward). For every
    start circle A (either sense) and every other circle B, a free circle F of radius
    rho touches A from outside at the contact angle phi and turns in A's sense (a cusp
    at the contact); from the contact F turns a quarter turn to where the tangent from
    F to B leaves it. For every goal circle A, likewise driven the other way: the
    tangent from B arrives on F a quarter turn before the contact. (The cusps of a
    parking manoeuvre; a quarter turn between two obstacles is not held.) A route is
    kept only when it can be part of a path shorter than ``bound`` (m): the start
    point to the route, the route's tangent and quarter turn, and on to the goal point,
    in straight lines, add up to ``bound`` or less. The angles phi are the roots of that
    condition on a grid of :data:`GRID` angles, refined by bisection."""
    x, y, r, sg, own = circ
    rho = float(sc.min_turn_radius)
    out = []
    for leaving, poses in ((True, ids.START), (False, ids.GOAL)):
        anchors = np.r_[poses, back + np.asarray(poses)]
        a, b = (m.ravel() for m in np.meshgrid(anchors, np.arange(x.size), indexing="ij"))
        keep = (a != b) & (np.hypot(x[b] - x[a], y[b] - y[a]) > r[a] + r[b] + TOL.eps)
        a, b = a[keep], b[keep]

        def route(phi, a=a, b=b, leaving=leaving):
            """The contact point P, F's centre and the tangent between F and B at contact
            angles ``phi``; the sweep on F between P and the tangent's end there."""
            ux, uy = np.cos(phi), np.sin(phi)
            fx, fy = x[a] + (r[a] + rho) * ux, y[a] + (r[a] + rho) * uy
            px, py = x[a] + r[a] * ux, y[a] + r[a] * uy
            one = np.ones_like(fx)
            if leaving:
                t = g.tangent(fx, fy, rho * one, sg[a], x[b], y[b], r[b], sg[b], one, 0 * one,
                              TOL.eps)
                swp = g.sweep(px - fx, py - fy, t.p1x - fx, t.p1y - fy, sg[a], 0.0)
            else:
                t = g.tangent(x[b], y[b], r[b], sg[b], fx, fy, rho * one, sg[a], one, 0 * one,
                              TOL.eps)
                swp = g.sweep(t.p2x - fx, t.p2y - fy, px - fx, py - fy, sg[a], 0.0)
            return (px, py), (fx, fy), t, swp

        def miss(phi, a=a, b=b, leaving=leaving):
            *_, t, swp = route(phi, a, b, leaving)
            off = np.remainder(swp - math.pi / 2 + math.pi, 2.0 * math.pi) - math.pi
            return np.where(t.exists, off, np.nan)

        phi = np.linspace(0.0, 2.0 * math.pi, GRID + 1)
        h = miss(phi[:, None], a[None], b[None], leaving)  # (GRID + 1, pairs)
        k, j = np.nonzero((np.sign(h[:-1]) * np.sign(h[1:]) < 0)
                          & (np.abs(h[:-1]) < 0.5) & (np.abs(h[1:]) < 0.5))
        lo, hi = phi[k], phi[k + 1]
        flo = h[k, j]
        for _ in range(48):  # bisection to rounding
            mid = 0.5 * (lo + hi)
            fm = miss(mid, a[j], b[j], leaving)
            left = np.sign(fm) == np.sign(flo)
            lo, hi, flo = np.where(left, mid, lo), np.where(left, hi, mid), np.where(left, fm, flo)
        mid = 0.5 * (lo + hi)
        (px, py), (fx, fy), t, swp = route(mid, a[j], b[j], leaving)
        # The route's shortest way: the start point to P (or to the tangent's start on
        # B), the tangent, the quarter turn, on to the goal point (or from P).
        sx, sy, gx, gy = sc.start[0], sc.start[1], sc.goal[0], sc.goal[1]
        first = np.hypot(px - sx, py - sy) if leaving else np.hypot(t.p1x - sx, t.p1y - sy)
        last = np.hypot(t.p2x - gx, t.p2y - gy) if leaving else np.hypot(px - gx, py - gy)
        near = first + t.length + rho * math.pi / 2 + last <= bound
        out.append(Quarter(a[j], b[j], np.full(j.size, leaving), px, py, fx, fy, sg[a[j]],
                           t.p1x, t.p1y, t.p2x, t.p2y, t.length, swp))
        out[-1] = Quarter(*(v[near] for v in out[-1]))
    return Quarter(*(np.concatenate(v) for v in zip(*out)))


def quarter_turns(sc: Scenario, circ, back: int, bound: float = math.inf):
    """``(x, y, sign)`` of the quarter-turn circles (:func:`quarter_routes`) of the
    circles ``circ``, leaving ones first."""
    q = quarter_routes(sc, circ, back, bound)
    return q.fx, q.fy, q.sign


def circles(sc: Scenario, bound: float = math.inf, quarter: bool = True
            ) -> tuple[tuple[np.ndarray, ...], int]:
    """``((x, y, r, sign, own), back)``: the scenario's circles, the four pose circles
    travelled backward from ``back = C`` on (the start's left and right, then the
    goal's: the same circles, the other sense), then the free circles of either sense
    that a path shorter than ``bound`` (m) can reach."""
    c = ids.count(sc.n)
    x, y, r, sign, own = free_circles.circles(sc, bound, both=True)
    pose = slice(0, ids.POSES)

    def with_back(v, w):
        return np.concatenate([v[:c], w[pose], v[c:]])

    circ = (with_back(x, x), with_back(y, y), with_back(r, r), with_back(sign, -sign),
            with_back(own, own).astype(np.int32))
    if not quarter:
        return circ, c
    fixed = tuple(v[:c + ids.POSES] for v in circ)
    qx, qy, qs = quarter_turns(sc, fixed, c, bound)
    rho = float(sc.min_turn_radius)
    return (np.concatenate([circ[0], qx]), np.concatenate([circ[1], qy]),
            np.concatenate([circ[2], np.full(qx.size, rho)]), np.concatenate([circ[3], qs]),
            np.concatenate([circ[4], np.full(qx.size, -1)]).astype(np.int32)), c


def _cusps(sc: Scenario, circ, back: int, bound: float):
    """Cusps, ``(S, T, px, py, px, py, 0)``: pairs of circles that touch with opposite
    directions of travel at the contact point P, among the scenario's and the backward
    pose circles, and between those and the free circles (which they hold)."""
    x, y, r, sg, own = circ
    fixed = np.arange(back + ids.POSES)
    a, b = (m.ravel() for m in np.meshgrid(fixed, np.arange(x.size), indexing="ij"))
    a, b = np.r_[a, b[b >= fixed.size]], np.r_[b, a[b >= fixed.size]]  # both ways
    keep = (a != b) & ~((own[a] == own[b]) & (own[a] >= 0))
    a, b = a[keep], b[keep]
    d = np.hypot(x[b] - x[a], y[b] - y[a])
    outer = (sg[a] == sg[b]) & (np.abs(d - (r[a] + r[b])) <= TOL.eps)
    inner = (sg[a] != sg[b]) & (np.abs(d - np.abs(r[a] - r[b])) <= TOL.eps) & (d > TOL.eps)
    a, b, d, outer = (v[outer | inner] for v in (a, b, d, outer))
    # P at r[a] from a's centre: towards b when they touch from outside or b lies inside.
    toward = np.where(outer | (r[a] >= r[b]), 1.0, -1.0) * r[a] / d
    px, py = x[a] + toward * (x[b] - x[a]), y[a] + toward * (y[b] - y[a])
    lo, hi = sc.bounds[0::2], sc.bounds[1::2]
    ok = ((px >= lo[0] - TOL.length) & (px <= hi[0] + TOL.length)
          & (py >= lo[1] - TOL.length) & (py <= hi[1] + TOL.length))
    if math.isfinite(bound):
        ok &= (np.hypot(px - sc.start[0], py - sc.start[1])
               + np.hypot(px - sc.goal[0], py - sc.goal[1]) <= bound)
    a, b, px, py = a[ok], b[ok], px[ok], py[ok]
    return a, b, px, py, px, py, np.zeros(a.size)


def clear(sc: Scenario, segments: list[dict[str, Any]]) -> bool:
    """Whether a chain of result-file segments keeps clear of every obstacle and in the
    field (the full rule of :mod:`hga_jax.model.collision`; arcs here belong to no
    obstacle)."""
    sa = sc.arrays(np.float64)
    centres, radii = np.asarray(sa.centres), np.asarray(sa.model_radii)
    obstacles = col.obstacles(centres, radii, ndim=1)
    for seg in segments:
        if seg["type"] == "line":
            (ax, ay), (bx, by) = seg["start"], seg["end"]
            ends = tuple(np.array([v]) for v in (ax, ay, bx, by))
            if col.segment_violations(ends, np.array([True]), obstacles, sa.bounds,
                                      TOL.length, "full")[0]:
                return False
            continue
        (cx, cy), rad, a0, swp = seg["center"], seg["radius"], seg["start_angle"], seg["sweep"]
        circ = tuple(np.array([v]) for v in (cx, cy, rad, -math.copysign(1.0, swp), -1))
        arc = tuple(np.array([v]) for v in (
            cx + rad * math.cos(a0), cy + rad * math.sin(a0),
            cx + rad * math.cos(a0 + swp), cy + rad * math.sin(a0 + swp), abs(swp)))
        if not col.arcs_clear(circ, np.array([0]), arc, centres, radii, sa.bounds,
                              TOL.length)[0]:
            return False
    return True


def _words(sc: Scenario, back: int, bound: float):
    """The Reeds–Shepp words from the start pose to the goal pose that are clear and no
    longer than ``bound``: pieces from the start point to the goal point, on the start's
    left circle in the sense of the word's first gear (circle 0 forward, ``back``
    backward) to the goal's left circle in the sense of its last (2 or ``back + 2``), and
    their segments."""
    from hga_jax.model.cars.reeds_shepp import closed_form

    rho = float(sc.min_turn_radius)
    (sx, sy, _), (gx, gy, _) = sc.start, sc.goal
    kept, segs, first, last = [], [], [], []
    for word in closed_form.candidates(sc.start, sc.goal, rho):
        if word.length > bound:
            continue
        seg = closed_form.segments(sc.start, word.pieces, rho)
        if seg and clear(sc, seg):
            kept.append(word.length)
            segs.append(seg)
            first.append(back if seg[0].get("reverse") else 0)
            last.append(back + ids.GOAL[0] if seg[-1].get("reverse") else ids.GOAL[0])
    k = len(kept)
    return (np.asarray(first, np.int64), np.asarray(last, np.int64), np.full(k, float(sx)),
            np.full(k, float(sy)), np.full(k, float(gx)), np.full(k, float(gy)),
            np.asarray(kept, float)), segs


def build(sc: Scenario, bound: float = math.inf, quarter: bool = True
          ) -> tuple[Graph, Pieces]:
    """The graph (module doc) and its pieces; with a finite ``bound`` (m) without what no
    path shorter than it can use (pass the free-turn optimum, a little raised).
    ``quarter``: with the quarter-turn circles."""
    circ, back = circles(sc, bound, quarter)
    tangents = free_turns._tangents(sc, circ, bound)
    cusps = _cusps(sc, circ, back, bound)
    words, segs = _words(sc, back, bound)
    pieces = tuple(np.concatenate(parts) for parts in zip(tangents, cusps, words))
    more = tuple((back + k, k < 2) for k in range(ids.POSES))
    gr = tangent_graph.assemble(sc.arrays(np.float64), circ, pieces, "rings", "full",
                                more_poses=more)
    parts = Pieces(pieces, tangents[0].size, cusps[0].size, segs)
    return _geared(gr, parts, back), parts


def _geared(gr: Graph, parts: Pieces, back: int) -> Graph:
    """``gr`` laid out once per gear (module doc): nodes ``u`` forward, ``u + N``
    backward."""
    n = gr.nx.size
    src = np.asarray(gr.src)
    dst, w = np.asarray(gr.dst, np.int64), np.asarray(gr.w)
    first_cusp = ids.POSES + parts.tangents
    first_word = first_cusp + parts.cusps
    end_words = first_word + len(parts.words)
    piece = np.asarray(gr.arc_circle) < 0  # arcs leave a piece's start node too
    cusp = piece & (src >= first_cusp) & (src < first_word)
    word = piece & (src >= first_word) & (src < end_words)
    # Every edge in both gears, a cusp to the other gear; a word once, between its gears.
    lay = ~word
    es = [src[lay], src[lay] + n]
    ed = [dst[lay] + n * cusp[lay], dst[lay] + n * ~cusp[lay]]
    k = np.flatnonzero(word)
    if k.size:
        j = src[k] - first_word
        fwd_in = np.array([not parts.words[i][0].get("reverse") for i in j])
        fwd_out = np.array([not parts.words[i][-1].get("reverse") for i in j])
        es.append(src[k] + n * ~fwd_in)
        ed.append(dst[k] + n * ~fwd_out)
    pick = np.r_[np.flatnonzero(lay), np.flatnonzero(lay), k]
    es, ed = np.concatenate(es), np.concatenate(ed)
    srt = np.argsort(es, kind="stable")
    pick = pick[srt]
    indptr = np.concatenate([[0], np.cumsum(np.bincount(es, minlength=2 * n))])
    back_start = [u for u in gr.starts if gr.ncirc[u] >= back]
    back_goal = [u for u in gr.goals if gr.ncirc[u] >= back]
    return Graph(gr.circles, np.r_[gr.nx, gr.nx], np.r_[gr.ny, gr.ny],
                 np.r_[gr.ncirc, gr.ncirc], indptr.tolist(), ed[srt].tolist(),
                 w[pick].tolist(), np.asarray(gr.enter)[pick].tolist(), es[srt],
                 np.asarray(gr.arc_circle)[pick], np.asarray(gr.sweep)[pick],
                 tuple(u for u in gr.starts if gr.ncirc[u] < back)
                 + tuple(u + n for u in back_start),
                 tuple(u for u in gr.goals if gr.ncirc[u] < back)
                 + tuple(u + n for u in back_goal))


def shortest(sc: Scenario, bound: float = math.inf):
    """The Reeds–Shepp optimum of the model: ``(length, segments, touched, cusps)``,
    segments in the result files' format with ``"reverse": true`` on every piece driven
    backward; ``length`` inf and empty lists when no path exists (or none shorter than
    ``bound``)."""
    # The graph without quarter turns first (small): its optimum bounds the full graph's,
    # which holds every path of it, so the second search finds that one or a shorter one.
    gr, parts = build(sc, bound, quarter=False)
    h = np.hypot(gr.nx - float(sc.goal[0]), gr.ny - float(sc.goal[1])).tolist()
    length, edges, _ = search(gr, h, distinct=False)
    if edges:
        full, full_parts = build(sc, min(bound, length * (1.0 + 1e-9) + 1e-12))
        h2 = np.hypot(full.nx - float(sc.goal[0]), full.ny - float(sc.goal[1])).tolist()
        length2, edges2, _ = search(full, h2, distinct=False)
        if edges2 and length2 <= length:
            gr, parts, length, edges = full, full_parts, length2, edges2
    if not edges:
        return math.inf, [], [], 0
    segs, touched = _walk(gr, parts, edges, back=ids.count(sc.n))
    segs = tidy(segs)
    cusps = sum(1 for s, t in zip(segs, segs[1:]) if s.get("reverse") != t.get("reverse"))
    return float(length), segs, touched, cusps


TINY = 1e-12  # m: a piece this short is rounding (two cusps at one point, say)


def tidy(segs: list[dict[str, Any]]) -> list[dict[str, Any]]:
    """``segs`` without pieces shorter than :data:`TINY` and with arcs that go on along
    one circle in one gear and sense joined: the same path, its cusps where it turns."""
    out: list[dict[str, Any]] = []
    for seg in segs:
        if seg["type"] == "arc":
            if seg["radius"] * abs(seg["sweep"]) <= TINY:
                continue
        elif math.hypot(seg["end"][0] - seg["start"][0], seg["end"][1] - seg["start"][1]) <= TINY:
            continue
        last = out[-1] if out else None
        if (last is not None and seg["type"] == last["type"] == "arc"
                and last["center"] == seg["center"] and last["radius"] == seg["radius"]
                and bool(last.get("reverse")) == bool(seg.get("reverse"))
                and bool(last.get("free")) == bool(seg.get("free"))
                and (last["sweep"] > 0) == (seg["sweep"] > 0)):
            last["sweep"] += seg["sweep"]
            continue
        out.append(dict(seg))
    return out


def _walk(gr: Graph, parts: Pieces, edges: list[int], back: int):
    """Segments (with gears) and touched obstacles of a walk (:func:`shortest`)."""
    x, y, r, sg, own = gr.circles
    n = gr.nx.size // 2  # nodes per gear
    first_word = ids.POSES + parts.tangents + parts.cusps
    end_words = first_word + len(parts.words)
    segs: list[dict[str, Any]] = []
    touched: list[Touch] = []
    arc_on = -1
    for k in edges:
        u, v, c = int(gr.src[k]), gr.dst[k], int(gr.arc_circle[k])
        backward = u >= n
        if c >= 0:
            if gr.sweep[k] <= 0.0:
                continue
            if arc_on != c:
                segs.append({"type": "arc", "center": [float(x[c]), float(y[c])],
                             "radius": float(r[c]), "sweep": 0.0, "start_angle": float(
                                 np.arctan2(gr.ny[u] - y[c], gr.nx[u] - x[c]))})
                if c >= back + ids.POSES:  # a free circle
                    segs[-1]["free"] = True
                if backward:
                    segs[-1]["reverse"] = True
                touch = Touch(int(own[c]) + 1, int(sg[c]))
                if own[c] >= 0 and c < back and touched[-1:] != [touch]:  # not split arcs
                    touched.append(touch)
            segs[-1]["sweep"] -= float(sg[c] * gr.sweep[k])
            arc_on = c
            continue
        arc_on = -1
        if first_word <= u % n < end_words:
            segs += [dict(s) for s in parts.words[u % n - first_word]]
        elif gr.w[k] > 0.0:
            segs.append({"type": "line", "start": [float(gr.nx[u]), float(gr.ny[u])],
                         "end": [float(gr.nx[v]), float(gr.ny[v])]})
            if backward:
                segs[-1]["reverse"] = True
    return segs, touched
