"""The exact optimum of the path model: the shortest walk in the tangent graph.

Oriented circles: the two start circles (left ``-1`` and right ``+1``, radius rho),
the two goal circles, and every obstacle's model circle clockwise (``+1``) and
counter-clockwise (``-1``). Nodes are points on an oriented circle: the start point
on each start circle, the goal point on each goal circle, and both touch points of
every feasible directed tangent. Edges (docs/model.md, "The optimum of the model"):

- tangent: the directed tangent segment from a source circle (start or obstacle) to a
  target circle (obstacle or goal); never between an obstacle and itself; a missing
  tangent is no edge;
- arc: along each oriented circle between consecutive nodes in the circle's direction
  (on a start circle from the start point on, on a goal circle ending at the goal
  point); two nodes within the angle tolerance also get a zero-length reverse edge,
  since the decoder counts a sweep within it of 2*pi as 0;
- coincident start and goal circles: the arc from the start point to the goal point.

Each piece is judged by the decoder's rules (:mod:`hga_jax.model.collision`, float64
tolerances): segments against every obstacle, arcs against every obstacle but their
own circle (``"full"`` mode only), the field box in both modes. So a walk touching
each obstacle at most once is feasible iff the chromosome listing its circles decodes
without violation, with the same length; :func:`solve` checks this on every
path it returns and raises :class:`~hga_jax.errors.ModelMismatchError` where it
fails (a bug, never a feasible answer). Search: A* bounded by the straight-line
distance to the goal point. A walk touching one obstacle twice has no chromosome; a
label-setting search with the visited obstacles in its state then gives the best
chromosome-expressible path. Coincident circles other than a start and a goal circle
are not joined. Units: metres and radians.
"""
from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hga_jax.model import geometry as g
from hga_jax.errors import ModelMismatchError
from . import car_model
from . import circle_ids as ids
from .collision import COLLISIONS
from . import tangent_graph
from .graph_search import MAX_LABELS, Graph, search, walk
from .path import Path, Touch, chromosome, evaluate_path, touch_list
from .scenario import Scenario

TOL = g.tolerances(np.float64)


@dataclass
class ExactResult:
    """The model's optimum for one scenario and collision mode.

    length: the optimum (m); when expressible, the decoder's float64 length of the
      optimal chromosome (equal to ``walk_length`` to 1e-9), else ``walk_length``;
      ``math.inf`` when no feasible path exists.
    walk_length: the shortest walk in the tangent graph (m). seconds: time of the graph
    build and search (s); the decoder's float64 re-check of the path is not counted.
    upper, lower: the optimal chromosome (docs/model.md), None when not expressible.
    touched: :class:`~hga_jax.model.path.Touch` ``(obstacle number from 1, label)`` along
      the optimal walk, in travel order.
    expressible: False when the optimal walk touches one obstacle twice; then
      ``best_expressible`` is the best chromosome-expressible feasible path (None if none).
    path: ``evaluate_path`` of the optimal chromosome (None when not expressible; then
      ``best_expressible`` is that path). segments: docs/model.md segments of the optimal walk.
    Infeasible scenes (every model alike, :func:`no_path`): ``feasible`` False, ``length``
      inf, ``expressible`` True, no paths, and ``message`` says why in a line.
    turns: the car model's name (:mod:`hga_jax.model.car_model`): ``"tight-rope"`` (the
      paper's) or ``"free"`` (turns on circles of radius rho in free space too,
      :mod:`hga_jax.model.cars.free_turns.model`). Under free turns
      ``tight_rope_length`` is the tight-rope optimum (m) and ``free_arcs`` the number of
      free arcs on the path; a path with free arcs has no chromosome (``expressible``
      False, ``best_expressible`` the tight-rope optimum's path) and its arcs on free
      circles carry ``"free": true`` in ``segments``. ``details``: what a car model
      records beside (:meth:`~hga_jax.model.car_model.CarModel.extras` writes them).
    Among robots that move (:mod:`hga_jax.model.in_time.optimum`): ``optimal`` False when
      the path is only the shortest known feasible in time, and ``lower_bound`` the
      standing robots' optimum (m); result files carry both keys for such scenes only.
    """

    length: float
    feasible: bool
    collision: str
    walk_length: float
    expressible: bool
    upper: list[int] | None
    lower: list[int] | None
    touched: list[Touch]
    path: Path | None
    best_expressible: Path | None
    segments: list[dict[str, Any]] = field(default_factory=list)
    seconds: float = 0.0
    message: str = ""
    turns: str = car_model.DEFAULT
    tight_rope_length: float | None = None
    free_arcs: int = 0
    details: dict[str, Any] = field(default_factory=dict)
    optimal: bool = True
    lower_bound: float | None = None

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready summary (length is null when infeasible)."""
        best = self.best_expressible
        return {
            "length": self.length if self.feasible else None,
            "feasible": self.feasible, "touched": touch_list(self.touched),
            "upper": self.upper, "lower": self.lower,
            "expressible": self.expressible if self.feasible else None,
            "walk_length": self.walk_length if self.feasible else None,
            "best_expressible": None if best is None else best.to_dict(),
            "seconds": self.seconds, "collision": self.collision, "message": self.message,
            "segments": self.segments, "turns": self.turns,
            **car_model.get(self.turns).extras(self),
            **({} if self.optimal and self.lower_bound is None else
               {"optimal": self.optimal, "lower_bound": self.lower_bound})}


def _tangents(sa, full: bool):
    """Every directed tangent (source, target) from the scenario's tangent table, and
    which are feasible edges: sources are start and obstacle circles, targets obstacle
    and goal circles (:mod:`hga_jax.model.circle_ids`), never an obstacle to itself."""
    tb = sa.tangents
    obs, nc = tb.obstacle, tb.obstacle.size
    S, T = (a.ravel() for a in np.meshgrid(ids.sources(nc), ids.targets(nc), indexing="ij"))
    keep = (obs[S] != obs[T]) | (obs[S] < 0)
    S, T = S[keep], T[keep]
    t = g.Tangent(None, None, tb.length[S, T], tb.p1x[S, T], tb.p1y[S, T], tb.p2x[S, T],
                  tb.p2y[S, T], tb.exists[S, T])
    violations = (tb.violations_full if full else tb.violations_paper)[S, T]
    coincident = tb.coincident[S, T]
    ok = (violations == 0) & ~coincident
    return S, T, t, ok


def tight_rope_graph(sc: Scenario, collision: str) -> Graph:
    """The tangent graph of ``sc`` (:func:`hga_jax.model.tangent_graph.assemble`, the
    poses' circles travelled from the start point and to the goal point) with every
    infeasible piece left out."""
    sa = sc.arrays(np.float64)
    tb = sa.tangents
    circ = (*tb.circles.T, tb.obstacle)
    S, T, t, ok = _tangents(sa, collision == "full")
    pieces = (S[ok], T[ok], t.p1x[ok], t.p1y[ok], t.p2x[ok], t.p2y[ok], t.length[ok])
    s_c = np.asarray(ids.START)
    g_c = ids.GOAL[0] + s_c  # one start circle on the goal circle of its sign
    coincident = tb.coincident[s_c, g_c] & tb.exists[s_c, g_c]
    return tangent_graph.assemble(sa, circ, pieces, "ends", collision, enter=tb.obstacle[T[ok]],
                                  coincident=coincident)


def _chromosome(n: int, circs: list[int], circles) -> tuple[list[int], list[int]]:
    """Internal (perm, labels) of a walk through distinct obstacles."""
    sg, obs = circles[3], circles[4]
    seen = [int(obs[c]) for c in circs[1:-1]]
    perm = seen + [i for i in range(n) if i not in set(seen)]
    labels = [int(sg[circs[0]])] + [int(sg[c]) for c in circs[1:-1]]
    return perm, labels + [0] * (n - len(seen)) + [int(sg[circs[-1]])]


def _check_agreement(scenario: Scenario, path: Path | None, walk_length: float) -> None:
    """Raise :class:`ModelMismatchError` unless the decoder's float64 figures of ``path``
    match the graph's walk: no violation and the same length (to 1e-9, relative).

    The graph and the decoder judge every piece with the same functions, so a
    mismatch is a bug in hga-jax; it is never reported as a feasible optimum.
    """
    if path is None or (not path.violations
                        and abs(path.length - walk_length) <= 1e-9 * max(1.0, walk_length)):
        return
    raise ModelMismatchError(
        f"{scenario.source}: the exact solver's walk (length {walk_length!r}) decodes to "
        f"length {path.length!r} with {path.violations} violation(s), chromosome upper "
        f"{path.upper} lower {path.lower}")


def solve(scenario: Scenario, collision: str = "full", turns: str = car_model.DEFAULT,
          car: str | None = None) -> ExactResult:
    """The exact optimum of ``scenario`` under ``collision`` (``"full"`` or ``"paper"``)
    in the car model ``turns`` (:func:`hga_jax.model.car_model.names`: ``"tight-rope"``,
    the paper's, :func:`solve_tight_rope`; ``"free"``, free turns; ``"reeds-shepp"``)
    of the car ``car`` (``"dubins"``, forward only, or ``"reeds-shepp"``, which also
    reverses; None: the scenario's ``[robot] car``)."""
    try:
        turns = car_model.resolve(turns, scenario.car if car is None else car)
    except ValueError as e:
        raise ValueError(f"car: {e}") from None
    if collision not in COLLISIONS:
        raise ValueError(f"collision: must be one of {', '.join(COLLISIONS)}, got {collision!r}")
    problem = car_model.problem(turns, collision)
    if problem:
        raise ValueError(f"turns: {problem}")
    model = car_model.get(turns)
    if scenario.has_motion:  # a lower bound, certified when clear in time
        from .in_time import optimum

        if car is not None and car != scenario.car:
            scenario = dataclasses.replace(scenario, car=car)
        return scenario.cached(("moving optimum", collision, turns), lambda: optimum.solve(
            scenario, collision, lambda scene: model.solve(scene, collision)))
    return model.solve(scenario, collision)


def solve_tight_rope(scenario: Scenario, collision: str = "full") -> ExactResult:
    """The tight-rope optimum (module doc): the shortest walk in :func:`tight_rope_graph`,
    re-checked by the decoder."""
    t0 = time.perf_counter()
    gr = tight_rope_graph(scenario, collision)
    gx, gy = float(scenario.goal[0]), float(scenario.goal[1])
    h = np.hypot(gr.nx - gx, gr.ny - gy).tolist()
    walk_length, edges, _ = search(gr, h, distinct=False)
    if not edges:
        return no_path(scenario, collision, car_model.DEFAULT, time.perf_counter() - t0, gr)
    circs, segs = walk(gr, edges)
    obs, sg = gr.circles[4], gr.circles[3]
    touched = [Touch(int(obs[c]) + 1, int(sg[c])) for c in circs[1:-1]]
    expressible = len({o for o, _ in touched}) == len(touched)
    upper = lower = path = best = None
    length, message = walk_length, "optimal"
    spent = time.perf_counter() - t0
    if not expressible:
        best_length, best_edges, complete = search(gr, h, distinct=True)
        spent = time.perf_counter() - t0
        if best_edges:
            best = evaluate_path(scenario, *_chromosome(scenario.n, walk(gr, best_edges)[0],
                                                        gr.circles), collision)
        message = ("optimal walk touches an obstacle twice: no chromosome expresses it; "
                   + ("best_expressible is the best chromosome path" if best else
                      "no chromosome expresses a feasible path" if complete else
                      f"label budget ({MAX_LABELS}) ran out: best_expressible unknown"))
        _check_agreement(scenario, best, best_length)
    else:
        perm, labels = _chromosome(scenario.n, circs, gr.circles)
        path = best = evaluate_path(scenario, perm, labels, collision)
        upper, lower = chromosome(perm, labels)
        segs, length = path.segments, path.length
        _check_agreement(scenario, path, walk_length)
    return ExactResult(length, True, collision, walk_length, expressible, upper, lower, touched,
                       path, best, segs, spent, message)


def no_path(scenario: Scenario, collision: str, turns: str, seconds: float,
            gr: Any = None) -> ExactResult:
    """The answer of every model for a scene with no feasible path: ``feasible`` False,
    ``length`` inf, no chromosome, and in ``message`` why (:func:`hga_jax.model.no_path.why`;
    ``gr``: the model's graph, if built)."""
    from .no_path import why

    return ExactResult(math.inf, False, collision, math.inf, True, None, None, [], None, None,
                       seconds=seconds, message=why(scenario, collision, turns, gr), turns=turns)
