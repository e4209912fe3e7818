"""Planners behind one interface, for the replanning loop's episodes.

A planner is built once for a car and an episode's bound on the robot count; ``reset()``
forgets what it carried (a new episode), and ``plan(view)`` returns a
:class:`~hga_jax.loop.replanner.Plan`-like :class:`Planned` from the car's pose to the goal
for one :class:`View` (what the car observes at a frame). A planner that finds no path
returns ``segments=None``: the car then goes on along its previous plan.

- ``hga``: the warm-started, time-aware HGA (:class:`~hga_jax.loop.replanner.Replanner`);
- ``hga-cold``: the same with a fresh population every frame (the same budget);
- ``exact``: the exact solver on the robots frozen where they are at the frame (what a
  planner without time does; :func:`hga_jax.model.exact.solve`).
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from . import frame as frames
from .replanner import Replanner

PLANNERS = ("hga", "hga-cold", "exact")
"""The planners :func:`make` builds."""


@dataclass
class View:
    """What the car observes at a frame: its pose ``(x, y, heading)``, the goal pose, and
    each robot's ``(x, y, vx, vy, r)`` in the scene's order (possibly noisy)."""

    pose: Sequence[float]
    goal: Sequence[float]
    robots: np.ndarray


@dataclass
class Planned:
    """A frame's answer: ``segments`` (None: no path), ``status``, ``plan_ms``."""

    segments: list | None
    status: str
    plan_ms: float
    length: float = float("nan")


class HGAPlanner:
    """``hga`` / ``hga-cold`` (module doc)."""

    def __init__(self, car: frames.Car, bound: int, seed: int = 0, warm: bool = True,
                 generations: int = 5, **options: Any):
        self.name = "hga" if warm else "hga-cold"
        self.replanner = Replanner(car, bound, generations=generations, seed=seed, warm=warm,
                                   **options)
        self.compile_s = self.replanner.warm_up()

    def reset(self) -> None:
        self.replanner.reset()

    def plan(self, view: View) -> Planned:
        obs = frames.observation(view.pose, view.goal, view.robots, self.replanner.bound,
                                 self.replanner.dtype)
        p = self.replanner.step(obs)[0]
        return Planned(p.segments, p.status, p.plan_ms, p.length)


class ExactFrozenPlanner:
    """``exact``: the exact optimum among the robots standing where they are now (each
    robot's radius widened by the car's ``margin``, as the HGA's)."""

    name = "exact"

    def __init__(self, car: frames.Car, bound: int, field: Any = None, **_: Any):
        self.car, self.field = car, field

    def reset(self) -> None:
        pass

    def plan(self, view: View) -> Planned:
        from hga_jax import scenario_from_dict
        from hga_jax.errors import ConfigError
        from hga_jax.model import exact

        t0 = time.perf_counter()
        d = {"name": "frame", "robot": {"radius": self.car.radius,
                                         "min_turn_radius": self.car.rho,
                                         "speed": self.car.speed},
             "start": _pose(view.pose), "goal": _pose(view.goal),
             "obstacles": [{"x": float(x), "y": float(y), "radius": float(r) + self.car.margin}
                           for x, y, _, _, r in np.asarray(view.robots).reshape(-1, 5)]}
        if self.field is not None:
            d["field"] = self.field
        try:
            res = exact.solve(scenario_from_dict(d, "frame"))
        except ConfigError as e:  # a robot on the start or the goal: no plan this frame
            return Planned(None, f"no plan: {e}", (time.perf_counter() - t0) * 1e3)
        ms = (time.perf_counter() - t0) * 1e3
        if not res.feasible:
            return Planned(None, "no path among the frozen robots", ms)
        return Planned(list(res.segments), "clear", ms, float(res.length))


def _pose(p) -> dict:
    return {"x": float(p[0]), "y": float(p[1]), "heading_deg": float(np.degrees(p[2]))}


def make(name: str, car: frames.Car, bound: int, seed: int = 0, field: Any = None,
         generations: int = 5) -> Any:
    """The planner called ``name`` (:data:`PLANNERS`)."""
    if name == "hga":
        return HGAPlanner(car, bound, seed, True, generations)
    if name == "hga-cold":
        return HGAPlanner(car, bound, seed, False, generations)
    if name == "exact":
        return ExactFrozenPlanner(car, bound, field)
    raise ValueError(f"planner: must be one of {', '.join(PLANNERS)}, got {name!r}")
