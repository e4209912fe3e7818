"""A planning scenario: robot, start and goal poses, circular obstacles, field.

Units: metres and radians (configs use degrees in keys named ``*_deg``; the
loader converts). The point robot sees each obstacle as its *model circle* of
radius ``R_i = max(rho, r_i + r)`` (docs/model.md). These are defined here once:
``Scenario.model_radii``, ``Scenario.circles()`` (the model circles and the start
and goal turning circles, oriented) and ``Scenario.bounds`` (the kept field box);
the device arrays, the exact solver and the plots take them from here.

``Scenario`` is host-side (plain floats and numpy arrays, validated by the
loader in :mod:`hga_jax.host.config`). ``Scenario.arrays(dtype)`` gives the
:class:`ScenarioArrays` pytree that device code takes; ``Scenario.search_arrays(dtype,
collision)`` adds the scenario's turn table for that collision mode
(:mod:`hga_jax.model.turns`), which the GA's fitness looks paths up in.

Robots that move (docs/model.md, "Moving robots"): ``Scenario.velocities`` gives each
obstacle's velocity (m/s; None or zeros: every robot stands) and ``Scenario.speed`` the
car's (m/s). The static rules and tables test pieces only against the robots that stand
(``ScenarioArrays.model_radii`` is 0 for one that moves: :attr:`Scenario.blocking_radii`);
a moving robot's clearance is judged in time by :mod:`hga_jax.model.in_time.clearance` from
``ScenarioArrays.motion``. A chromosome may wrap a moving robot: its circle stands in the
tables where the robot is when the car passes it (``wrap_moving = "at-pass"``,
:meth:`Scenario.placement_times`); ``"never"`` makes it a point that a chromosome wraps
only at the cost of a violation (the alternative measured in docs/model.md). With every
velocity 0 the arrays are the static ones, bit for bit.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from hga_jax.model import legs, tangents
from hga_jax.model import turns as turn_tables
from hga_jax.model.in_time import windows


@dataclass(frozen=True)
class Field:
    """Field rectangle in metres; ``keep_inside`` asks every path point to stay
    inside the rectangle shrunk by the robot radius."""

    xmin: float
    xmax: float
    ymin: float
    ymax: float
    keep_inside: bool = False


@dataclass(frozen=True, eq=False)
class Scenario:
    """A validated scenario. Poses are ``(x, y, heading)`` in metres and radians."""

    name: str
    robot_radius: float
    min_turn_radius: float
    start: tuple[float, float, float]
    goal: tuple[float, float, float]
    centres: np.ndarray  # (n, 2) obstacle centres, metres
    radii: np.ndarray  # (n,) physical obstacle radii, metres
    field: Field | None = None
    ga: dict[str, Any] = dataclasses.field(default_factory=dict)  # raw [ga] table, checked by settings
    source: str = "<scenario>"  # file it came from, for messages
    car: str = "dubins"  # "dubins" (forward only) or "reeds-shepp" (also backward)
    velocities: np.ndarray | None = None  # (n, 2) obstacle velocities, m/s (None: all stand)
    speed: float = 1.0  # the car's constant speed along its path, m/s
    wrap_moving: str = "at-best"  # how a chromosome wraps a moving robot (WRAP_MOVING)
    _arrays: dict[Any, "ScenarioArrays"] = dataclasses.field(
        default_factory=dict, init=False, repr=False, compare=False)  # per dtype, built once
    _turns: dict[Any, Any] = dataclasses.field(
        default_factory=dict, init=False, repr=False, compare=False)  # per mode, built once

    @property
    def n(self) -> int:
        """Number of obstacles."""
        return int(self.centres.shape[0])

    @property
    def model_radii(self) -> np.ndarray:
        """Model circle radii ``R_i = max(rho, r_i + r)`` (metres)."""
        return np.maximum(self.min_turn_radius, self.radii + self.robot_radius)

    @property
    def moving(self) -> np.ndarray:
        """(n,) bool: which obstacles move (a non-zero velocity)."""
        if self.velocities is None:
            return np.zeros(self.n, bool)
        return np.any(np.asarray(self.velocities, float).reshape(self.n, 2) != 0.0, axis=1)

    @property
    def has_motion(self) -> bool:
        """Whether some obstacle moves (then feasibility is judged in time)."""
        return bool(self.moving.any())

    @property
    def circle_radii(self) -> np.ndarray:
        """The radii of the obstacles' circles in the tables (m): ``R_i``, and 0 for a
        robot that moves where chromosomes never wrap one (``wrap_moving = "never"``)."""
        if self.wrap_moving == "never":
            return np.where(self.moving, 0.0, self.model_radii)
        return self.model_radii

    def guide_radii(self) -> np.ndarray:
        """The radii the search's per-leg blockers (:mod:`hga_jax.model.legs`: the robots
        that seeding and the repair move wrap) are tested with (m): among robots that
        move, each moving robot's circle where it is placed (:meth:`placement_times`)
        blocks a leg as a standing robot's does, so that those moves wrap robots that
        cross the path; else :attr:`blocking_radii`. The legs' violations (``bad``,
        charged by the guided move) stay those of the static rules, and the fitness
        never reads it: a moving robot is judged in time."""
        if self.has_motion and self.wrap_moving != "never":
            return np.asarray(self.model_radii, np.float64)
        return np.asarray(self.blocking_radii, np.float64)

    @property
    def blocking_radii(self) -> np.ndarray:
        """The radii the static rules test pieces against (m): ``R_i`` for a robot that
        stands, 0 for one that moves (it blocks nothing in space; :mod:`hga_jax.model.in_time.clearance`
        judges it in time)."""
        return np.where(self.moving, 0.0, self.model_radii)

    def placement_times(self) -> np.ndarray:
        """(n,) the moment (s) at which each robot's circle stands in the tables: 0 for a
        robot that stands. For one that moves, where the car passes it on a reference
        path: with ``wrap_moving = "at-best"`` the shortest path known to be feasible in
        time (the exact module's: the certified optimum, or its best path, whose turns
        round a robot's position at some moment give that moment), with ``"at-pass"`` the
        standing robots' shortest path; the moment of closest approach along it. Without
        a reference path: its distance from the start over the speed."""
        def build():
            times = np.zeros(self.n)
            if not self.has_motion or self.wrap_moving == "never":
                return times
            from . import exact
            from .in_time import clearance

            movers = np.flatnonzero(self.moving)
            times[movers] = np.hypot(*(self.centres[movers] - self.start[:2]).T) / self.speed
            ref = exact.solve(self if self.wrap_moving == "at-best" else self.still_scene(),
                              "full")
            if ref.feasible and ref.segments:
                for a in clearance.closest_approach(self, ref.segments, spacing=5e-3):
                    times[a.obstacle] = a.time
                for k, t in clearance.moments_wrapped(self, ref.segments).items():
                    times[k] = t
            return times

        return self.cached("placement times", build)

    def placed_centres(self) -> np.ndarray:
        """(n, 2) the centres of the obstacles' circles in the tables (m): each robot where
        it is at its :meth:`placement_times`."""
        if not self.has_motion:
            return self.centres
        vel = np.asarray(self.velocities, float).reshape(self.n, 2)
        return self.centres + vel * self.placement_times()[:, None]

    def still_scene(self) -> "Scenario":
        """The scenario with only its standing robots (the same poses, field and car):
        its optimum is a lower bound on this one's (docs/model.md, "Moving robots").
        ``self`` when nothing moves."""
        if not self.has_motion:
            return self

        def build():
            keep = ~self.moving
            return dataclasses.replace(self, centres=self.centres[keep], radii=self.radii[keep],
                                       velocities=None)

        return self.cached("still scene", build)

    @property
    def still_index(self) -> np.ndarray:
        """(n_still,) the indices (from 0) of the standing robots: obstacle ``k`` of
        :meth:`still_scene` is obstacle ``still_index[k]`` of this scenario."""
        return np.flatnonzero(~self.moving)

    def motion(self, dtype: Any = np.float64) -> "Motion | None":
        """The moving robots as device arrays in ``dtype`` (None when nothing moves)."""
        if not self.has_motion:
            return None
        idx = np.flatnonzero(self.moving)
        m = idx.size
        pad = -m % MOTION_BLOCK  # far robots that never come near: fewer programs to compile
        vel = np.asarray(self.velocities, float).reshape(self.n, 2)[idx]
        far = np.stack([1e4 + 10.0 * np.arange(pad), np.full(pad, 1e4)], axis=1)
        return Motion(centres=np.asarray(np.concatenate([self.centres[idx], far]), dtype),
                      velocities=np.asarray(np.concatenate([vel, np.zeros((pad, 2))]), dtype),
                      radii=np.asarray(np.concatenate([self.model_radii[idx], np.zeros(pad)]),
                                       dtype),
                      index=np.concatenate([idx, np.full(pad, self.n)]).astype(np.int32),
                      speed=np.asarray(self.speed, dtype),
                      placed=np.asarray(np.concatenate([self.placement_times()[idx],
                                                        np.zeros(pad)]), dtype),
                      wrap_penalty=np.asarray(self.wrap_moving == "never", np.int32))

    @property
    def delta(self) -> float:
        """Penalty per violation, ``2*pi*R`` with the largest model radius (paper 3.2)."""
        big = float(self.model_radii.max()) if self.n else self.min_turn_radius
        return 2.0 * np.pi * max(big, self.min_turn_radius)

    @property
    def bounds(self) -> tuple[float, float, float, float]:
        """The box ``(xmin, xmax, ymin, ymax)`` that every path point must stay within
        (metres): the field shrunk by the robot radius when it is kept, else infinite."""
        f = self.field
        if f is None or not f.keep_inside:
            return (-np.inf, np.inf, -np.inf, np.inf)
        r = self.robot_radius
        return (f.xmin + r, f.xmax - r, f.ymin + r, f.ymax - r)

    def circles(self, dtype: Any = np.float64) -> tuple[np.ndarray, ...]:
        """The scenario's ``C = 2n + 4`` oriented circles in ``dtype``: ``(x, y, r, sign,
        obstacle)``, numbered as in :mod:`hga_jax.model.tangents` (0 start CCW, 1 start
        CW, 2 goal CCW, 3 goal CW, then each obstacle's model circle CW and CCW)."""
        start, goal, centres, model_radii, rho, _ = self._parts(np.dtype(dtype))
        return tangents.oriented_circles(start, goal, centres, model_radii, rho)

    def arrays(self, dtype: Any = np.float32) -> "ScenarioArrays":
        """The scenario as a pytree of arrays for device code, in ``dtype``, with its
        tangent table (built once per dtype; treat the arrays as read-only)."""
        key = np.dtype(dtype)
        if key not in self._arrays:
            self._arrays[key] = self._build_arrays(key)
        return self._arrays[key]

    def search_arrays(self, dtype: Any = np.float32, collision: str = "full",
                      with_legs: bool = False) -> "ScenarioArrays":
        """:meth:`arrays` with the turn table of ``collision`` (``"full"`` or ``"paper"``)
        in ``dtype``, when it is usable and not too large (:func:`hga_jax.model.turns.fits`);
        otherwise without one, and the fitness decodes leg by leg. Built once per mode
        (from the float64 tangent table), cast per dtype. ``with_legs``: also the
        per-leg blockers that the path operators read (:mod:`hga_jax.model.legs`).
        Free-turn chromosomes take :func:`hga_jax.model.cars.free_turns.legs.search_arrays`."""
        sa = self.arrays(dtype)
        name = np.dtype(dtype).name
        if with_legs:
            def built_legs():
                s64 = self.arrays(np.float64)

                def with_radii(radii):
                    built = legs.build(s64.tangents, s64.centres, radii, self.delta)
                    return legs.with_end_arcs(built, s64.tangents, s64.start, s64.goal,
                                              s64.centres, radii, s64.bounds)

                still = with_radii(s64.model_radii)
                if not self.has_motion:
                    return still
                return legs.with_blockers_of(still, with_radii(self.guide_radii()))

            def typed_legs():  # lengths in the search's dtype
                lg = self.cached("legs", built_legs)
                return lg._replace(length=np.asarray(lg.length, dtype),
                                   penalty=np.asarray(lg.penalty, dtype))

            sa = sa._replace(legs=self.cached(("legs", name), typed_legs))

        def turn_table():  # among robots that move: what stands (blocking radii)
            if not turn_tables.fits(self.n):
                return None
            s64 = self.arrays(np.float64)
            built = turn_tables.build(s64.tangents, s64.start, s64.goal, s64.centres,
                                      s64.model_radii, s64.bounds, collision)
            return built.entries if built.usable else None

        table = self.cached(collision, turn_table)
        if table is None:
            return sa
        looked = table
        if self.has_motion:  # each turn's windows in time (hga_jax.model.in_time.windows)
            def timed():
                return windows.for_scenario(self, table, dtype)

            looked = self.cached((collision, "in time", name), timed)
            if looked is None:
                return sa
        if sa.legs is not None:  # with the arcs' own violations, for the guided move
            def arcs():  # once per collision rule
                tb = self.arrays(np.float64).tangents
                return legs.arcs_from_turns(table, tb.violations_full if collision == "full"
                                            else tb.violations_paper)

            def with_arcs():
                return sa.legs._replace(arcs=self.cached(("arcs", collision), arcs))

            sa = sa._replace(legs=self.cached(("legs", name, collision), with_arcs))
        field = "turns_full" if collision == "full" else "turns_paper"
        return sa._replace(**{field: np.asarray(looked, sa.centres.dtype)})

    def cached(self, key: Any, build: Any) -> Any:
        """``build()``, made once per ``key`` and kept with the scenario (the tables that
        other modules derive from it, such as :mod:`hga_jax.model.cars.free_turns.legs`')."""
        if key not in self._turns:
            self._turns[key] = build()
        return self._turns[key]

    def _parts(self, dtype: np.dtype) -> tuple[np.ndarray, ...]:
        """start, goal, centres, model_radii, rho, bounds as numpy arrays of ``dtype``
        (among robots that move: the circles' :meth:`placed_centres` and
        :attr:`circle_radii`)."""
        start, goal = np.asarray(self.start, dtype), np.asarray(self.goal, dtype)
        moves = self.has_motion
        centres = np.asarray(self.placed_centres() if moves else self.centres,
                             dtype).reshape(self.n, 2)
        model_radii = np.asarray(self.circle_radii if moves else self.model_radii,
                                 dtype).reshape(self.n)
        return (start, goal, centres, model_radii, np.asarray(self.min_turn_radius, dtype),
                np.asarray(self.bounds, dtype))

    def _build_arrays(self, dtype: np.dtype) -> "ScenarioArrays":
        start, goal, centres, model_radii, rho, box = self._parts(dtype)
        if not self.has_motion:
            return ScenarioArrays(
                start=start, goal=goal, centres=centres, model_radii=model_radii, rho=rho,
                bounds=box, delta=np.asarray(self.delta, dtype),
                tangents=tangents.build(start, goal, centres, model_radii, rho, box))
        # In time: circles of every robot (where placed), static rules against those that stand.
        blocking = np.asarray(self.blocking_radii, dtype).reshape(self.n)
        circles = tangents.oriented_circles(start, goal, centres, model_radii, rho)
        return ScenarioArrays(
            start=start, goal=goal, centres=centres, model_radii=blocking, rho=rho,
            bounds=box, delta=np.asarray(self.delta, dtype),
            tangents=tangents.table(circles, centres, blocking, box), motion=self.motion(dtype))


class Motion(NamedTuple):
    """The moving robots of a scenario on the device (docs/model.md, "Moving robots"):
    ``m`` robots, the centre of robot ``j`` at time ``t`` being ``centres[j] + t *
    velocities[j]``.

    centres: (m, 2) at time 0 (m). velocities: (m, 2) (m/s). radii: (m,) model radii
    ``R_j`` (m). index: (m,) int32 their obstacle indices in the scenario (from 0); the
    padding's (:data:`MOTION_BLOCK`) is ``n``, its robots far away, standing, of radius 0.
    speed: () the car's speed along its path (m/s). placed: (m,) the moment whose
    position each robot's circle takes in the tables (s, :meth:`Scenario.placement_times`).
    wrap_penalty: () int32, 1 where a chromosome that wraps a moving robot counts a
    violation (``wrap_moving = "never"``), else 0.
    """

    centres: Any
    velocities: Any
    radii: Any
    index: Any
    speed: Any
    placed: Any
    wrap_penalty: Any


WRAP_MOVING = ("at-best", "at-pass", "never")
"""How a chromosome may wrap a moving robot (``Scenario.wrap_moving``, module doc)."""
MOTION_BLOCK = 4
"""The moving robots of :class:`Motion` are padded to a multiple of this (robots far away
that never come near, obstacle index ``n``): scenes whose counts differ by less share a
compiled program."""
"""How a chromosome may wrap a moving robot (``Scenario.wrap_moving``, module doc)."""


class ScenarioArrays(NamedTuple):
    """Device view of a scenario (all arrays share one float dtype).

    start, goal: (3,) pose ``x, y, heading`` (m, m, rad).
    centres: (n, 2) obstacle centres (m). model_radii: (n,) ``R_i`` (m).
    rho: () minimum turning radius (m).
    bounds: (4,) ``xmin, xmax, ymin, ymax`` that path points must stay within
    (already shrunk by the robot radius; infinite when the field is not kept).
    delta: () penalty length per violation (m).
    tangents: the :class:`~hga_jax.model.tangents.TangentTable` of the scenario.
    turns_full, turns_paper: the turn table's entries (:mod:`hga_jax.model.turns`) for
    each collision mode, or None (the fitness then decodes leg by leg); only
    :meth:`Scenario.search_arrays` fills them.
    legs: the per-leg blockers of :mod:`hga_jax.model.legs` (for the path operators), or
    None; filled by ``search_arrays(..., with_legs=True)``.
    tight_legs: under a model with leg genes, the legs of its tangents (what ``legs``
    is for the tight rope: a blocked tangent is blocked even where gene 0 gets round it
    by a free leg), for the ``tight_of_best`` children; else None.
    free_legs: the :class:`~hga_jax.model.cars.free_turns.legs.LegTable` of free-turn chromosomes,
    turns_free: its turn table's entries (or None: decoded leg by leg); both only from
    :func:`hga_jax.model.cars.free_turns.legs.search_arrays`.
    motion: the :class:`Motion` of the moving robots, or None (nothing moves). Among robots
    that move the tight rope's and free turns' turn tables carry each turn's windows in time
    (:mod:`hga_jax.model.in_time.windows`); without one the fitness decodes leg by leg and
    adds the violations in time (:mod:`hga_jax.model.in_time.clearance`).
    present: (n,) bool, which obstacles are there, or None (all): the obstacles of a frame
    padded to a bound (:mod:`hga_jax.loop`); a chromosome never touches one that is not
    (its label reads as 0).
    """

    start: Any
    goal: Any
    centres: Any
    model_radii: Any
    rho: Any
    bounds: Any
    delta: Any
    tangents: Any
    turns_full: Any = None
    turns_paper: Any = None
    legs: Any = None
    tight_legs: Any = None
    free_legs: Any = None
    turns_free: Any = None
    motion: Any = None
    present: Any = None


def scenario_to_dict(s: Scenario) -> dict[str, Any]:
    """The mapping of a scenario file (metres and degrees) that gives ``s`` back
    through :func:`hga_jax.host.config.scenario_from_dict` (headings to within rounding)."""
    def pose(p: tuple[float, float, float]) -> dict[str, float]:
        return {"x": float(p[0]), "y": float(p[1]), "heading_deg": math.degrees(p[2])}

    vel = np.zeros((s.n, 2)) if s.velocities is None else np.asarray(s.velocities, float)

    def velocity(k: int) -> dict[str, float]:
        return {} if not s.moving[k] else {"vx": float(vel[k, 0]), "vy": float(vel[k, 1])}

    out: dict[str, Any] = {
        "name": s.name,
        "robot": {"radius": s.robot_radius, "min_turn_radius": s.min_turn_radius,
                  **({} if s.car == "dubins" else {"car": s.car}),
                  **({} if s.speed == 1.0 else {"speed": float(s.speed)})},
        "start": pose(s.start), "goal": pose(s.goal),
        "obstacles": [{"x": float(x), "y": float(y), "radius": float(r), **velocity(k)}
                      for k, ((x, y), r) in enumerate(zip(s.centres, s.radii))],
    }
    if s.field is not None:
        out["field"] = dataclasses.asdict(s.field)
    if s.ga:
        out["ga"] = dict(s.ga)
    return out
