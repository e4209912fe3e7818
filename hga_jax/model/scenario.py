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
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from hga_jax.model import legs, tangents
from hga_jax.model import turns as turn_tables


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
        Free-turn chromosomes take :func:`hga_jax.model.free_legs.search_arrays`."""
        sa = self.arrays(dtype)
        name = np.dtype(dtype).name
        if with_legs:
            def built_legs():
                s64 = self.arrays(np.float64)
                built = legs.build(s64.tangents, s64.centres, s64.model_radii, self.delta)
                return legs.with_end_arcs(built, s64.tangents, s64.start, s64.goal,
                                          s64.centres, s64.model_radii, s64.bounds)

            def typed_legs():  # lengths in the search's dtype
                lg = self.cached("legs", built_legs)
                return lg._replace(length=np.asarray(lg.length, dtype),
                                   penalty=np.asarray(lg.penalty, dtype))

            sa = sa._replace(legs=self.cached(("legs", name), typed_legs))

        def turn_table():
            if not turn_tables.fits(self.n):
                return None
            s64 = self.arrays(np.float64)
            built = turn_tables.build(s64.tangents, s64.start, s64.goal, s64.centres,
                                      s64.model_radii, s64.bounds, collision)
            return built.entries if built.usable else None

        table = self.cached(collision, turn_table)
        if table is None:
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
        return sa._replace(**{field: np.asarray(table, sa.centres.dtype)})

    def cached(self, key: Any, build: Any) -> Any:
        """``build()``, made once per ``key`` and kept with the scenario (the tables that
        other modules derive from it, such as :mod:`hga_jax.model.free_legs`')."""
        if key not in self._turns:
            self._turns[key] = build()
        return self._turns[key]

    def _parts(self, dtype: np.dtype) -> tuple[np.ndarray, ...]:
        """start, goal, centres, model_radii, rho, bounds as numpy arrays of ``dtype``."""
        start, goal = np.asarray(self.start, dtype), np.asarray(self.goal, dtype)
        centres = np.asarray(self.centres, dtype).reshape(self.n, 2)
        model_radii = np.asarray(self.model_radii, dtype).reshape(self.n)
        return (start, goal, centres, model_radii, np.asarray(self.min_turn_radius, dtype),
                np.asarray(self.bounds, dtype))

    def _build_arrays(self, dtype: np.dtype) -> "ScenarioArrays":
        start, goal, centres, model_radii, rho, box = self._parts(dtype)
        return ScenarioArrays(
            start=start, goal=goal, centres=centres, model_radii=model_radii, rho=rho,
            bounds=box, delta=np.asarray(self.delta, dtype),
            tangents=tangents.build(start, goal, centres, model_radii, rho, box),
        )


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
    free_legs: the :class:`~hga_jax.model.free_legs.LegTable` of free-turn chromosomes,
    turns_free: its turn table's entries (or None: decoded leg by leg); both only from
    :func:`hga_jax.model.free_legs.search_arrays`.
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


def scenario_to_dict(s: Scenario) -> dict[str, Any]:
    """The mapping of a scenario file (metres and degrees) that gives ``s`` back
    through :func:`hga_jax.host.config.scenario_from_dict` (headings to within rounding)."""
    def pose(p: tuple[float, float, float]) -> dict[str, float]:
        return {"x": float(p[0]), "y": float(p[1]), "heading_deg": math.degrees(p[2])}

    out: dict[str, Any] = {
        "name": s.name,
        "robot": {"radius": s.robot_radius, "min_turn_radius": s.min_turn_radius,
                  **({} if s.car == "dubins" else {"car": s.car})},
        "start": pose(s.start), "goal": pose(s.goal),
        "obstacles": [{"x": float(x), "y": float(y), "radius": float(r)}
                      for (x, y), r in zip(s.centres, s.radii)],
    }
    if s.field is not None:
        out["field"] = dataclasses.asdict(s.field)
    if s.ga:
        out["ga"] = dict(s.ga)
    return out
