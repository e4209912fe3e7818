"""A replanner for a robot's loop: one compiled program, a warm-started HGA, a plan every frame.

``Replanner(car, bound)`` is built once for a car (:class:`~hga_jax.loop.frame.Car`), a bound
on the robot count and GA settings; ``step(observation)`` returns a :class:`Plan` from the
car's current pose to the goal, every frame, in the time-aware model (docs/model.md,
"Robots that move"). Each frame, inside one compiled program (:func:`frame_step`):

1. the frame's arrays are built on the device (:func:`hga_jax.loop.frame.arrays`);
2. the population carried from the previous frame is **scored again** on this frame (its
   fitness was an earlier frame's: a path that now collides must not stay best), the worst
   ``immigrants`` of it are replaced by fresh random chromosomes, and the best-so-far is the
   best of that population (a chromosome names robots by their slot, which they keep);
3. ``generations`` generations of the GA run (:func:`hga_jax.search.ga.steps`);
4. the best is decoded for the plan.

The first frame (or after :meth:`Replanner.reset`) starts from a fresh population, as a run's
generation 0 does. Several cars plan in one call: the program is vmapped over a leading
axis of observations (``cars``). Robots are padded to ``bound``: a robot that comes or goes
changes the data, not the shapes, so the program compiles once.

Frame ``f`` of car ``k`` with seed ``s`` draws from ``fold_in(fold_in(key(s), k), f)``:
a seeded loop repeats itself exactly.
"""
from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass, field
from typing import Any

import jax
import jax.numpy as jnp
import numpy as np

from hga_jax.jax_compat import fixed_stream
from hga_jax.model.decode import decode_batch
from hga_jax.model.fitness import present_labels
from hga_jax.search import ga, rng
from hga_jax.search.settings import GASettings
from hga_jax.search.state import Best, blank
from hga_jax.search.variation import _draw, _fresh, positional
from . import frame as frames

LOOP = GASettings(selection="tournament", tournament_size=2, elites=2, penalty_weight=10.0)
"""The loop's default GA: the paper's operators and rates with tournament selection of two,
2 elites and ten times the penalty per violation (no operator that reads host-built
tables; the population of 50 the paper's)."""


@dataclass
class Plan:
    """A frame's plan: ``segments`` (the result files' pieces, docs/results.md) from the
    car's pose to the goal, its ``length`` (m) and ``violations`` (in time, float32 search;
    0: clear of every robot as predicted), ``status`` (``"clear"``, ``"collides"``, or
    ``"start inside robot K"``: the car is within robot K's model circle now, and the plan
    is the least-violating way out the search found), the chromosome (``perm``, positional
    ``labels``), ``plan_ms`` (wall time of the step) and ``generations`` (how many ran)."""

    segments: list
    length: float
    violations: int
    status: str
    perm: np.ndarray
    labels: np.ndarray
    plan_ms: float = 0.0
    speed: float = 1.0
    start: tuple = field(default_factory=tuple)
    generations: int = 0

    def poses(self, spacing: float = 0.05) -> np.ndarray:
        """Poses along the plan every ``spacing`` m (and at each piece's ends), as
        :func:`hga_jax.host.poses.poses` and ``RunsResult.best.poses`` give them: a numpy
        structured array with columns ``s, x, y, heading, curvature`` (float64), ``gear``
        (int8, +1 forward, -1 backward) and ``t`` (``s / speed``, s)."""
        from hga_jax.host.poses import sample_poses

        return sample_poses(self.segments, spacing, start=self.start or None, speed=self.speed)


def _segments(circles, arcs, lines, count) -> list:
    """The tight rope's pieces of one decoded path (host, numpy float64 from float32)."""
    segments = []
    for s in range(int(count)):
        cx, cy, r, sign = (float(v) for v in circles[s])
        ax, ay, bx, by, swp = (float(v) for v in arcs[s])
        if swp > 0.0:
            segments.append({"type": "arc", "center": [cx, cy], "radius": r,
                             "start_angle": math.atan2(ay - cy, ax - cx), "sweep": -sign * swp})
        if s < int(count) - 1:
            p1x, p1y, p2x, p2y, _ = (float(v) for v in lines[s])
            if math.hypot(p2x - p1x, p2y - p1y) > 1e-9:
                segments.append({"type": "line", "start": [p1x, p1y], "end": [p2x, p2y]})
    return segments


def _rescored(sa, core, settings: GASettings, key, immigrants: int):
    """The carried population scored on this frame, its worst ``immigrants`` replaced by
    fresh chromosomes, and its best as the best-so-far (a blank state stays blank)."""
    pop = core.pop
    n = sa.centres.shape[0]
    scored = ga._evaluated(sa, pop.perm, pop.labels, pop.legs, settings)
    if immigrants:
        chrom = _fresh(_draw(key, n, settings), n, settings, sa)
        perm, labels, legs = (None if c is None else c[:immigrants] for c in chrom)
        fresh = ga._evaluated(sa, perm, labels, legs, settings)  # only those that come in
        worst = ga.top_indices(-scored.fitness, immigrants)
        scored = jax.tree.map(lambda a, b: a.at[worst].set(b), scored, fresh)
    i = jnp.argmax(scored.fitness)
    best = Best(scored.perm[i], positional(scored.perm[i], scored.labels[i], settings),
                scored.fitness[i], scored.length[i], scored.violations[i], core.generation,
                None)
    warm = core.generation > 0
    pop = jax.tree.map(lambda a, b: jnp.where(warm, a, b), scored, pop)
    best = jax.tree.map(lambda a, b: jnp.where(warm, a, b), best, core.best)
    return core._replace(pop=pop, best=best)


@fixed_stream
def frame_step(key, core, obs, car: frames.Car, settings: GASettings, generations: int,
               immigrants: int, live=None):
    """One frame of one car (module doc): ``(core after it, best decoded)``. ``core``: the
    GA state without its problem (:class:`~hga_jax.search.state.GAState`). Pure; vmapped
    over cars by :class:`Replanner`."""
    sa = frames.arrays(obs, car)
    k_imm, k_gen = jax.random.split(key)
    core = _rescored(sa, core, settings.with_rates(core.rates), k_imm, immigrants)
    keys = jax.random.split(k_gen, generations)
    state, _ = ga.steps(keys, core._replace(problem=sa), live)
    best = state.best
    labels = present_labels(sa, best.perm[None], best.labels[None])
    d = decode_batch(sa._replace(present=None), best.perm[None], labels, settings.collision)
    out = (d.circles[0], d.arcs[0], d.lines[0], d.count[0], best.length, best.violations,
           labels[0])
    return state._replace(problem=None), out


@functools.lru_cache(maxsize=None)
def _program(car: frames.Car, settings: GASettings, generations: int, immigrants: int,
             timed: bool = False):
    """The compiled frame program of a car and settings, shared by every replanner of them
    (a new replanner of the same car compiles nothing new). ``timed``: the program takes a
    fourth argument, one bool per generation (the same for every car), and runs only the
    generations it marks (a deadline's budget, :class:`Replanner`)."""
    fn = functools.partial(frame_step, car=car, settings=settings, generations=generations,
                           immigrants=immigrants)
    if timed:
        return jax.jit(jax.vmap(lambda k, c, o, live: fn(k, c, o, live=live),
                                in_axes=(0, 0, 0, None)))
    return jax.jit(jax.vmap(fn))


_frame_keys = jax.jit(jax.vmap(lambda k, f: jax.random.fold_in(k, f), (0, None)))


class Replanner:
    """Plans every frame for ``cars`` cars among at most ``bound`` robots (module doc).

    ``settings``: the GA (default :data:`LOOP`; no operator that reads host-built tables);
    ``generations``: per frame; ``immigrants``: the share of the population replaced by fresh
    chromosomes each frame; ``seed``: the loop's seed. ``warm=False`` starts every frame
    from a fresh population (a cold planner with the same budget).

    ``deadline_ms``: a budget in wall time instead: each frame runs as many generations,
    from 1 to ``generations``, as the frame's time model says fit (a fixed cost plus a cost
    per generation, measured at :meth:`warm_up` and followed frame by frame); the plan says
    how many ran (``Plan.generations``). The number then depends on the machine's speed, so
    a seed no longer fixes the plans."""

    def __init__(self, car: frames.Car, bound: int, settings: GASettings | None = None,
                 generations: int = 5, immigrants: float = 0.15, seed: int = 0,
                 cars: int = 1, warm: bool = True, dtype: Any = np.float32,
                 deadline_ms: float | None = None):
        self.car, self.bound, self.cars, self.warm = car, int(bound), int(cars), bool(warm)
        self.settings = (settings or LOOP).replace(generations=max(int(generations), 1))
        if self.settings.uses_legs or self.settings.model.genes:
            raise ValueError("the loop's GA takes the tight rope's operators that read no "
                             "host-built table (no path_mutation, no seeding)")
        self.generations = int(generations)
        self.immigrants = int(round(immigrants * self.settings.population))
        self.seed, self.dtype = int(seed), np.dtype(dtype)
        self.frame = 0
        if deadline_ms is not None and not (math.isfinite(deadline_ms) and deadline_ms > 0):
            raise ValueError(f"deadline_ms: must be a number > 0, got {deadline_ms!r}")
        self.deadline_ms = None if deadline_ms is None else float(deadline_ms)
        self._timed = self.deadline_ms is not None
        self._cost = [0.5, 0.5]  # ms: the frame's fixed cost and its cost per generation
        self._program = _program(car, self.settings.structure(), self.generations,
                                 self.immigrants, self._timed)
        self._programs: dict = {}  # the compiled programs, by the observations' shapes
        self._keys = _frame_keys
        self._base = jax.vmap(lambda k: jax.random.fold_in(rng.key(self.seed), k))(
            jnp.arange(self.cars))
        self.reset()

    def reset(self) -> None:
        """Forget the population: the next frame starts fresh (a new episode)."""
        if getattr(self, "_blank", None) is None:
            obs = frames.observation([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [], self.bound,
                                     self.dtype)
            sa = jax.eval_shape(lambda o: frames.arrays(o, self.car), obs)
            one = blank(jax.tree.map(lambda s: np.zeros(s.shape, s.dtype), sa), self.settings)
            one = one._replace(problem=None)
            core = jax.tree.map(lambda a: np.broadcast_to(a, (self.cars,) + np.shape(a)).copy()
                                if isinstance(a, np.ndarray) else a, one)
            # on the device as the program's own output is, so that it compiles once
            self._blank = jax.device_put(core, jax.devices()[0])
        self._core = self._blank
        self.frame = 0

    def warm_up(self) -> float:
        """Compile the frame program (one frame on an empty field, then :meth:`reset`):
        its seconds. The loop's frames then run without compiling."""
        t0 = time.perf_counter()
        obs = frames.observation([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [], self.bound, self.dtype)
        batch = jax.tree.map(lambda a: np.broadcast_to(a, (self.cars,) + a.shape), obs)
        self.step(batch)
        seconds = time.perf_counter() - t0
        if self._timed:  # the time model: frames of 1 and of every generation, measured
            one = [self._step_ms(batch, 1) for _ in range(5)]
            full = [self._step_ms(batch, self.generations) for _ in range(5)]
            per = max((np.median(full) - np.median(one)) / max(self.generations - 1, 1), 1e-3)
            self._cost = [max(float(np.median(one)) - per, 0.0), float(per)]
        self.reset()
        return seconds

    def _step_ms(self, batch, generations: int) -> float:
        t0 = time.perf_counter()
        self.step(batch, generations)
        return (time.perf_counter() - t0) * 1e3

    def budget(self) -> int:
        """The generations the next frame runs: all of them without a deadline; with one,
        as many as the time model says fit (at least 1)."""
        if not self._timed:
            return self.generations
        fixed, per = self._cost
        return int(np.clip(np.floor((self.deadline_ms - fixed) / per), 1, self.generations))

    def compiles(self) -> int:
        """How many frame programs this replanner has built so far (compiled, or loaded from
        the program folder of :mod:`hga_jax.compiled`, or reused from another replanner of
        the same car and settings in this process): one per bound and car count, whatever
        robots come and go."""
        return len(self._programs)

    def _executable(self, keys, core, obs):
        """The compiled frame program for these shapes, through :func:`hga_jax.compiled.program`
        (kept on disk as the GA's are: a later process loads it instead of compiling)."""
        from hga_jax import compiled

        shapes = tuple((tuple(a.shape), str(a.dtype)) for a in jax.tree.leaves(obs))
        exe = self._programs.get(shapes)
        if exe is None:
            key = ("loop-frame", repr(self.car), repr(self.settings.structure()),
                   self.generations, self.immigrants, self.cars, shapes, self._timed)
            args = (keys, core, obs) + ((np.ones(self.generations, bool),) if self._timed
                                        else ())
            exe = compiled.program(key, lambda: self._program.lower(*args))
            self._programs[shapes] = exe
        return exe

    def step(self, observations: frames.Observation,
             generations: int | None = None) -> list[Plan]:
        """One frame: a :class:`Plan` per car (``observations`` with a leading axis of
        ``cars``, or one car's without it). ``generations``: this frame's budget, where a
        deadline was set (default :meth:`budget`)."""
        t0 = time.perf_counter()
        g = self.budget() if generations is None or not self._timed else int(generations)
        obs = jax.tree.map(lambda a: np.asarray(a), observations)
        if np.ndim(obs.pose) == 1:
            obs = jax.tree.map(lambda a: a[None], obs)
        if not self.warm:
            self.reset()
        keys = self._keys(self._base, self.frame)
        live = (np.arange(self.generations) < g,) if self._timed else ()
        self._core, out = self._executable(keys, self._core, obs)(keys, self._core, obs, *live)
        circles, arcs, lines, count, length, violations, labels = jax.device_get(out)
        ms = (time.perf_counter() - t0) * 1e3
        if self._timed and generations is None:  # follow the machine: the fixed cost
            self._cost[0] = 0.8 * self._cost[0] + 0.2 * max(ms - g * self._cost[1], 0.0)
        self.frame += 1
        best_perm = np.asarray(self._core.best.perm)
        plans = []
        for k in range(obs.pose.shape[0]):
            plans.append(Plan(_segments(circles[k], arcs[k], lines[k], count[k]),
                              float(length[k]), int(violations[k]),
                              _status(obs, k, self.car, int(violations[k])),
                              best_perm[k], labels[k], ms, float(self.car.speed),
                              tuple(float(v) for v in obs.pose[k]), g))
        return plans


def _status(obs, k: int, car: frames.Car, violations: int) -> str:
    """``"start inside robot J"`` where the car is within a robot's model circle now, else
    ``"clear"`` or ``"collides"`` by the plan's violations."""
    there = np.asarray(obs.present[k], bool)
    d = np.hypot(*(np.asarray(obs.centres[k], float) - np.asarray(obs.pose[k][:2], float)).T)
    big_r = frames.model_radii(np.asarray(obs.radii[k], float), car)
    inside = np.flatnonzero(there & (d < big_r))
    if inside.size:
        return f"start inside robot {int(inside[0])}"
    return "clear" if violations == 0 else "collides"
