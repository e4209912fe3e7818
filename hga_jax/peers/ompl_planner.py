"""What a robotics user would run instead: one of OMPL's sampling planners in its Dubins
state space (a study peer).

The problem as an OMPL user states it: ``DubinsStateSpace(rho)`` forward only, the
start and goal poses, and a state validity checker that accepts a state when its
point lies outside every obstacle's model circle (``R_i``, as in the model) and, when
the field is kept, inside the field shrunk by the robot radius. When the field is
not kept, the sampling bounds are the box around the poses and the model circles,
widened by 4 ``rho`` on each side. OMPL checks motions at its default resolution, so a
returned path may clip an obstacle between checked states: that is why every path is
judged again by the project's model (:mod:`hga_jax.peers.judge`).

A run is *anytime*: the planner is given its time limit in slices that double
(``time_limit / 64, / 64, / 32, ..., / 2``: OMPL's planners go on from where they
stopped when ``solve`` is called again), and the path it holds after each slice is
kept with the planner time spent so far. Planner time excludes the judging.

OMPL's random generator is seeded once per process (OMPL allows no more), and a run
stops on the clock, so OMPL runs are not reproducible run for run; they are measured,
and a study stores them so that it never runs them again. Needs the ``ompl`` package
(the ``compare`` extra). Host code, single-threaded.
"""
from __future__ import annotations

import math
import time
from typing import Any

PLANNERS = ("BITstar", "ABITstar", "AITstar", "EITstar", "RRTstar", "InformedRRTstar",
            "PRMstar")
"""OMPL's asymptotically optimal planners a study may name (those the installed OMPL has)."""

SLICES = 7  # checkpoints per run: time_limit * 2**-6, 2**-5, ..., 1

_seeded = False


def available(planner: str) -> str | None:
    """Why ``planner`` cannot run here (one line), or None."""
    try:
        from ompl import geometric as og
    except ImportError:
        return "OMPL is not installed (pip install 'hga-jax[compare]')"
    if not hasattr(og, planner):
        return f"this OMPL has no {planner}"
    return None


def bounds(sc) -> tuple[float, float, float, float]:
    """``(xmin, xmax, ymin, ymax)`` of the states OMPL samples (m): the kept field
    shrunk by the robot radius, else the box described in the module doc."""
    f, r = sc.field, sc.robot_radius
    if f is not None and f.keep_inside:
        return f.xmin + r, f.xmax - r, f.ymin + r, f.ymax - r
    xs = [sc.start[0], sc.goal[0]] + [c[0] + s * R for c, R in zip(sc.centres, sc.model_radii)
                                      for s in (-1, 1)]
    ys = [sc.start[1], sc.goal[1]] + [c[1] + s * R for c, R in zip(sc.centres, sc.model_radii)
                                      for s in (-1, 1)]
    m = 4 * sc.min_turn_radius
    return min(xs) - m, max(xs) + m, min(ys) - m, max(ys) + m


def plan(sc, planner: str, time_limit: float, seed: int = 0,
         car: str | None = None) -> dict[str, Any]:
    """One anytime run of ``planner`` on scenario ``sc`` for ``time_limit`` seconds, in
    the state space of ``car`` (``"dubins"``: OMPL's ``DubinsStateSpace``, forward only;
    ``"reeds-shepp"``: ``ReedsSheppStateSpace``; None: the scenario's ``[robot] car``).

    Returns ``checkpoints``: per slice ``(planner seconds so far, poses or None)``,
    the poses ``(x, y, heading)`` of the path OMPL holds (None: no exact solution
    yet); ``ompl_length``: OMPL's own length of the last path (m, NaN if none);
    ``checks``: state validity checks made; ``seconds``: planner wall time in all.
    """
    global _seeded
    from ompl import base as ob, geometric as og, util as ou

    ou.setLogLevel(ou.LOG_NONE)
    if not _seeded:
        ou.RNG.setSeed(seed + 1)  # OMPL refuses seed 0
        _seeded = True
    from hga_jax.model import car_model

    reverses = car_model.of_car(sc.car if car is None else car).reverses
    space = (ob.ReedsSheppStateSpace(sc.min_turn_radius) if reverses
             else ob.DubinsStateSpace(sc.min_turn_radius, False))
    box = ob.RealVectorBounds(2)
    xmin, xmax, ymin, ymax = bounds(sc)
    box.setLow(0, xmin)
    box.setHigh(0, xmax)
    box.setLow(1, ymin)
    box.setHigh(1, ymax)
    space.setBounds(box)
    setup = og.SimpleSetup(space)
    obstacles = [(float(c[0]), float(c[1]), float(R) ** 2)
                 for c, R in zip(sc.centres, sc.model_radii)]
    checks = 0

    def valid(state) -> bool:
        nonlocal checks
        checks += 1
        x, y = state.getX(), state.getY()
        return space.satisfiesBounds(state) and all(
            (x - a) ** 2 + (y - b) ** 2 >= rr for a, b, rr in obstacles)

    setup.setStateValidityChecker(valid)
    start, goal = space.allocState(), space.allocState()
    for st, (x, y, h) in ((start, sc.start), (goal, sc.goal)):
        st.setX(float(x))
        st.setY(float(y))
        st.setYaw(float(h))
    setup.setStartAndGoalStates(start, goal)
    setup.setPlanner(getattr(og, planner)(setup.getSpaceInformation()))
    checkpoints, spent, length = [], 0.0, math.nan
    ends = [time_limit * 2.0 ** (i + 1 - SLICES) for i in range(SLICES)]
    for i, end in enumerate(ends):
        dt = end - (ends[i - 1] if i else 0.0)
        t0 = time.perf_counter()
        setup.solve(dt)
        spent += time.perf_counter() - t0
        poses = None
        if setup.haveExactSolutionPath():
            path = setup.getSolutionPath()
            length = path.length()
            poses = [(s.getX(), s.getY(), s.getYaw())
                     for s in (path.getState(j) for j in range(path.getStateCount()))]
        checkpoints.append((spent, poses))
    return {"checkpoints": checkpoints, "ompl_length": length, "checks": checks,
            "seconds": spent}
