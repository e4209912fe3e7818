"""Planners behind one interface, for the replanning loop's episodes.

A planner is built once for a car and an episode's bound on the robot count; ``reset()``
forgets what it carried (a new episode), and ``plan(view)`` returns a
:class:`~hga_jax.loop.replanner.Plan`-like :class:`Planned` from the car's pose to the goal
for one :class:`View` (what the car observes at a frame). A planner that finds no path
returns ``segments=None``: the car then goes on along its previous plan.

- ``hga``: the warm-started, time-aware HGA (:class:`~hga_jax.loop.replanner.Replanner`);
- ``hga-cold``: the same with a fresh population every frame (the same budget);
- ``exact``: the exact solver on the robots frozen where they are at the frame (what a
  planner without time does; :func:`hga_jax.model.exact.solve`);
- ``sampler``: a league-style sampler in the same model and time: each frame it judges the
  direct paths (no robot wrapped, the four ways to leave the start and reach the goal),
  last frame's winner and :data:`SAMPLES` random chromosomes, and drives the best (memory
  plus random samples, as TIGERs' and ER-Force's planners keep last frame's winner).
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any, Sequence

import numpy as np

from . import frame as frames
from .replanner import Replanner

PLANNERS = ("hga", "hga-cold", "exact", "sampler")
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


SAMPLES = 100
"""Random chromosomes the sampler judges each frame (ER-Force's planner draws about 100)."""


def _sample_step(key, obs, last, car: frames.Car, samples: int):
    """The sampler's frame (module doc), on the device: ``(winner perm, labels, decoded)``."""
    import jax
    import jax.numpy as jnp

    from hga_jax.model.decode import decode_batch
    from hga_jax.model.fitness import evaluate, present_labels
    from hga_jax.search import label_ops, permutation

    sa = frames.arrays(obs, car)
    n = obs.centres.shape[0]
    words = jax.random.bits(key, (samples, 2 * n + 2), dtype=jnp.uint32)
    perm = permutation.permutation_from_words(words[:, :n])
    labels = label_ops.labels_from_words(words[:, n:])
    ends = jnp.array([[-1, -1], [-1, 1], [1, -1], [1, 1]], jnp.int32)
    direct = jnp.zeros((4, n + 2), jnp.int32).at[:, 0].set(ends[:, 0]).at[:, -1].set(ends[:, 1])
    perm = jnp.concatenate([jnp.tile(jnp.arange(n, dtype=jnp.int32), (4, 1)), last[0][None],
                            perm])
    labels = jnp.concatenate([direct, last[1][None], labels])
    labels = present_labels(sa, perm, labels)
    e = evaluate(sa, perm, labels, "full")
    i = jnp.argmax(e.fitness)
    d = decode_batch(sa._replace(present=None), perm[i][None], labels[i][None], "full")
    return perm[i], labels[i], (d.circles[0], d.arcs[0], d.lines[0], d.count[0], e.length[i],
                                e.violations[i])


class SamplerPlanner:
    """``sampler`` (module doc)."""

    name = "sampler"

    def __init__(self, car: frames.Car, bound: int, seed: int = 0, samples: int = SAMPLES,
                 **_: Any):
        import functools

        import jax

        from hga_jax.search import rng

        self.car, self.bound, self.seed = car, int(bound), int(seed)
        self._step = jax.jit(functools.partial(_sample_step, car=car, samples=int(samples)))
        self._key = rng.key(self.seed)
        self.reset()
        t0 = time.perf_counter()
        self.plan(View((0.0, 0.0, 0.0), (1.0, 0.0, 0.0), np.zeros((0, 5))))
        self.compile_s = time.perf_counter() - t0
        self.reset()

    def reset(self) -> None:
        labels = np.zeros(self.bound + 2, np.int32)
        labels[[0, -1]] = -1  # the direct path, turning left at both ends
        self._last = (np.arange(self.bound, dtype=np.int32), labels)
        self.frame = 0

    def plan(self, view: View) -> Planned:
        import jax

        from .replanner import _segments, _status

        t0 = time.perf_counter()
        obs = frames.observation(view.pose, view.goal, view.robots, self.bound)
        key = jax.random.fold_in(self._key, self.frame)
        perm, labels, out = self._step(key, obs, self._last)
        circles, arcs, lines, count, length, violations = jax.device_get(out)
        self._last = (np.asarray(perm), np.asarray(labels))
        self.frame += 1
        batch = jax.tree.map(lambda a: np.asarray(a)[None], obs)
        status = _status(batch, 0, self.car, int(violations))
        return Planned(_segments(circles, arcs, lines, count), status,
                       (time.perf_counter() - t0) * 1e3, float(length))


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
    if name == "sampler":
        return SamplerPlanner(car, bound, seed)
    raise ValueError(f"planner: must be one of {', '.join(PLANNERS)}, got {name!r}")
