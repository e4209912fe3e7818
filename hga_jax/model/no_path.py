"""When a scenario has no feasible path: the one rule, its words, and why, in a line.

Every model says "no feasible path exists" in the same words (:data:`NO_PATH`),
records ``feasible: false`` with no length, and makes no claim about chromosomes.
:func:`why` says what stands in the way, most specific first:

1. a pose that faces an edge of the kept field closer than a turn away from it
   needs, for a car that only drives forward: a path of curvature at most ``1/rho``
   whose heading makes the angle ``theta`` with the edge's outward normal advances at
   least ``rho (1 - sin theta)`` towards the edge before it runs parallel to it, so at
   a distance ``d`` below that every path leaves the field (both turning circles cross
   the edge ahead of the pose). The goal is the same with the car's travel reversed
   (its back to the edge). A car that also reverses backs away instead.
2. a pose that no path of the model leaves (or enters): every piece out of its
   turning circles is blocked. The line names what each turning circle meets first
   and after how many degrees, and what the straight line ahead meets.
3. otherwise the start and the goal are walled apart by obstacles and the field.

Host code (numpy, float64); metres, radians, headings in degrees in messages.
"""
from __future__ import annotations

import math

import numpy as np

from . import car_model
from . import geometry as g
from .graph_search import Graph, search
from .scenario import Scenario

NO_PATH = "no feasible path exists"
TOL = g.tolerances(np.float64)
EDGES = (("left", 0, "x", -1), ("right", 1, "x", +1), ("bottom", 2, "y", -1),
         ("top", 3, "y", +1))  # name, index in Scenario.bounds, axis, outward sign


def model_words(collision: str, turns: str) -> str:
    """``"collision full"``, or ``"collision full, free turns"``: the model a verdict is in
    (the car model's :attr:`~hga_jax.model.car_model.CarModel.words`)."""
    words = car_model.get(turns).words
    return f"collision {collision}" + (f", {words}" if words else "")


def verdict(collision: str, turns: str, reason: str = "") -> str:
    """The one line every model prints for a scene with no feasible path."""
    return f"{NO_PATH} ({model_words(collision, turns)})" + (f": {reason}" if reason else "")


def graph_of(sc: Scenario, collision: str, turns: str) -> Graph:
    """The model's tangent graph (every feasible piece) of ``sc``."""
    return car_model.get(turns).graph(sc, collision)


def exists(sc: Scenario, collision: str = "full", turns: str = car_model.DEFAULT) -> bool:
    """Whether the model holds a feasible path (its tangent graph joins start and goal).
    No decoding, no JAX: milliseconds on the scenes of the paper. The graphs of the
    models it includes (a free-turn path exists wherever a tight-rope one does) are
    tried first: they are smaller."""
    model = car_model.get(turns)
    return any(_joined(graph_of(sc, collision, name)) for name in model.includes + (turns,))


def _joined(gr: Graph) -> bool:
    return bool(search(gr, [0.0] * gr.nx.size, distinct=False)[1])


def why(sc: Scenario, collision: str = "full", turns: str = car_model.DEFAULT,
        gr: Graph | None = None) -> str:
    """Why the model of ``sc`` holds no feasible path, in one line (the caller has found
    none). ``gr``: the model's graph if already built."""
    for pose in ("start", "goal") if not car_model.get(turns).reverses else ():
        facing = _facing_edge(sc, pose)  # a car that backs up is not held by an edge ahead
        if facing:
            return facing
    gr = graph_of(sc, collision, turns) if gr is None else gr
    for pose, nodes, forward in (("start", gr.starts, True), ("goal", gr.goals, False)):
        seen = _reach(gr, nodes, forward)
        poses = np.asarray(gr.ncirc)[list(gr.starts + gr.goals)]  # the poses' circles
        if np.all(np.isin(np.asarray(gr.ncirc)[sorted(seen)], poses)):
            return _boxed(sc, pose, collision)
    return ("paths leave the start and reach the goal, but none joins them: obstacles "
            f"and the field's edges leave no way through for a car turning at rho = "
            f"{sc.min_turn_radius:g} m")


def _pose(sc: Scenario, pose: str) -> tuple[float, float, float, str]:
    """(x, y, heading of travel away from the pose, words): the goal's heading is
    reversed, so that both poses are left forwards."""
    x, y, h = (float(v) for v in (sc.start if pose == "start" else sc.goal))
    words = f"{pose} ({x:g}, {y:g}, heading {math.degrees(h):g} deg)"
    return x, y, (h if pose == "start" else h + math.pi), words


def _facing_edge(sc: Scenario, pose: str) -> str | None:
    """Case 1 of the module doc for ``pose``, else None."""
    bounds = sc.bounds
    if not all(map(math.isfinite, bounds)):
        return None
    x, y, h, words = _pose(sc, pose)
    rho = sc.min_turn_radius
    for name, i, axis, out in EDGES:
        d = out * (bounds[i] - (x if axis == "x" else y))  # distance inside the edge
        c = out * (math.cos(h) if axis == "x" else math.sin(h))  # cos theta
        need = rho * (1.0 - math.sqrt(max(0.0, 1.0 - c * c)))
        if c > 0.0 and d < need - TOL.length:
            where = "ahead of it" if pose == "start" else "behind it"
            act = "faces" if pose == "start" else "backs onto"
            turn = "turning away" if pose == "start" else "arriving"
            return (f"the {words} {act} the kept field's {name} edge ({axis} = "
                    f"{bounds[i]:g} m) {d:.3g} m away, and {turn} needs {need:.3g} m at "
                    f"rho = {rho:g} m: both its turning circles cross that edge {where}")
    return None


def _reach(gr: Graph, nodes, forward: bool) -> set[int]:
    """Nodes reachable from ``nodes`` (``forward``) or from which ``nodes`` are reached."""
    indptr, dst = gr.indptr, gr.dst
    if forward:
        nxt = {u: dst[indptr[u]:indptr[u + 1]] for u in range(len(indptr) - 1)}
    else:
        nxt: dict[int, list[int]] = {}
        for u in range(len(indptr) - 1):
            for v in dst[indptr[u]:indptr[u + 1]]:
                nxt.setdefault(v, []).append(u)
    seen, todo = set(nodes), list(nodes)
    while todo:
        for v in nxt.get(todo.pop(), ()):
            if v not in seen:
                seen.add(v)
                todo.append(v)
    return seen


def _boxed(sc: Scenario, pose: str, collision: str) -> str:
    """Case 2 of the module doc: what each turning circle and the line ahead meet first."""
    x, y, h, words = _pose(sc, pose)
    rho = sc.min_turn_radius
    parts = []
    for s in (1.0, -1.0):  # turning left, right, in the direction of travel away
        cx, cy = x - s * rho * math.sin(h), y + s * rho * math.cos(h)
        a0 = math.atan2(y - cy, x - cx)
        phi = np.linspace(0.0, 2.0 * math.pi, 3601)[1:]
        px, py = cx + rho * np.cos(a0 + s * phi), cy + rho * np.sin(a0 + s * phi)
        what, k = _first_hit(sc, px, py, collision != "full")
        side = "left" if (s > 0) == (pose == "start") else "right"  # the goal's, not reversed
        parts.append(f"its {side} turning circle meets {what} after {math.degrees(phi[k]):.0f} deg"
                     if what else f"its {side} turning circle is clear all round")
    t = np.linspace(0.0, 1.0, 2001)[1:] * _span(sc)
    what, k = _first_hit(sc, x + t * math.cos(h), y + t * math.sin(h), False)
    line = "the line ahead" if pose == "start" else "the line behind it"
    parts.append(f"{line} meets {what} after {t[k]:.3g} m" if what else f"{line} is clear")
    verb, way = (("leaves", "") if pose == "start" else
                 ("reaches", " (followed back from the goal)"))
    return (f"no path {verb} the {words}: {', '.join(parts)}{way}, and no tangent gets "
            "away in between")


def _span(sc: Scenario) -> float:
    """A length beyond which the line ahead meets nothing of the scene (m)."""
    pts = np.concatenate([np.asarray(sc.centres, float).reshape(-1, 2),
                          [sc.start[:2], sc.goal[:2]]])
    box = [b for b in sc.bounds if math.isfinite(b)]
    reach = float(np.ptp(pts, axis=0).max()) + 2.0 * float(np.max(sc.model_radii, initial=0.0))
    return max(reach, (max(box) - min(box)) if box else 0.0) + 2.0 * sc.min_turn_radius


def _first_hit(sc: Scenario, px: np.ndarray, py: np.ndarray,
               field_only: bool) -> tuple[str | None, int]:
    """What the points ``px, py`` (in travel order) meet first, and its index: an edge
    of the kept field or an obstacle's model circle (``field_only``: the field only)."""
    x0, x1, y0, y1 = sc.bounds
    tol = TOL.length
    hits = []
    for name, out_of in (("left", px < x0 - tol), ("right", px > x1 + tol),
                         ("bottom", py < y0 - tol), ("top", py > y1 + tol)):
        if out_of.any():
            axis, value = ("x", x0 if name == "left" else x1) if name in ("left", "right") \
                else ("y", y0 if name == "bottom" else y1)
            hits.append((int(np.argmax(out_of)),
                         f"the kept field's {name} edge ({axis} = {value:g} m)"))
    if not field_only:
        for k, ((qx, qy), big) in enumerate(zip(np.asarray(sc.centres, float).reshape(-1, 2),
                                                 sc.model_radii)):
            inside = np.hypot(px - qx, py - qy) < big - tol
            if inside.any():
                hits.append((int(np.argmax(inside)), f"obstacle {k + 1}"))
    if not hits:
        return None, -1
    k, what = min(hits, key=lambda h: h[0])
    return what, k
