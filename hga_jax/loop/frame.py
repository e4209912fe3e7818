"""One frame of a replanning loop: what the car sees, padded to a bound, and its arrays built on the device.

A league robot replans on every vision frame from what it observes then: its own pose and
each robot's position and velocity. :class:`Observation` holds that for up to ``bound``
robots (``present`` marks those that are there; the padding stands far away and is never
touched by a chromosome), so that every frame of every robot count below the bound has the
same shapes and runs one compiled program.

:func:`arrays` builds the frame's :class:`~hga_jax.model.scenario.ScenarioArrays` inside
that program (jax, no host table): the car's pose is the start, every robot is judged in
time (a robot that stands is one whose velocity is 0; docs/model.md, "Robots that move"),
each robot's circle stands where it is when the car could first get there
(:func:`placement`), and the tangent table (field and missing tangents only: no robot
stands still for the static rules) is built by :func:`hga_jax.model.tangents.table` from
jax arrays. The fitness then decodes leg by leg and adds the tests in time
(:mod:`hga_jax.model.in_time.clearance`). Units: metres, seconds, radians.
"""
from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

from hga_jax.model import tangents
from hga_jax.model.geometry import xp_of
from hga_jax.model.scenario import Motion, ScenarioArrays

FAR = 1.0e4
"""Where the padding's robots stand (m): beyond any field, with radius 0."""
HORIZON = 5.0
"""The latest moment (s) at which a robot's circle is placed."""
PLACEMENT_STEPS = 3
"""Fixed-point steps of :func:`placement`."""


MARGIN = 0.01
"""Metres the loop keeps between the car's body and a robot's beyond touching (its
:class:`Car`'s default): a tight-rope path runs along model circles, so without a margin
its pieces touch the robots they wrap (and, within the float32 tolerance, overlap)."""


class Car(NamedTuple):
    """What does not change from frame to frame: the car's radius (m), its minimum turning
    radius ``rho`` (m), its speed (m/s), the box its path must stay in (``xmin, xmax,
    ymin, ymax``, already shrunk by the car's radius; infinite without walls) and the
    ``margin`` (m) added to every robot's radius when planning (:data:`MARGIN`)."""

    radius: float
    rho: float
    speed: float
    bounds: tuple[float, float, float, float] = (-np.inf, np.inf, -np.inf, np.inf)
    margin: float = MARGIN


class Observation(NamedTuple):
    """One frame: arrays (any leading batch axes for several cars).

    pose: (3,) the car's ``x, y, heading``. goal: (3,) the goal pose. centres: (N, 2) the
    robots' centres; velocities: (N, 2) (m/s); radii: (N,) their radii (m); present: (N,)
    bool, which of the ``N = bound`` slots hold a robot. A robot keeps its slot from frame
    to frame (a chromosome names robots by slot)."""

    pose: Any
    goal: Any
    centres: Any
    velocities: Any
    radii: Any
    present: Any


def observation(pose, goal, robots, bound: int, dtype: Any = np.float32) -> Observation:
    """An :class:`Observation` from host values: ``robots`` a sequence of ``(x, y, vx, vy,
    r)`` (at most ``bound``; slot ``k`` is the ``k``-th), padded to ``bound``."""
    robots = np.asarray(robots, np.float64).reshape(-1, 5)
    k = robots.shape[0]
    if k > bound:
        raise ValueError(f"{k} robots do not fit a bound of {bound}")
    centres = np.zeros((bound, 2))
    velocities = np.zeros((bound, 2))
    radii = np.zeros(bound)
    centres[:k], velocities[:k], radii[:k] = robots[:, :2], robots[:, 2:4], robots[:, 4]
    present = np.arange(bound) < k
    return Observation(np.asarray(pose, dtype), np.asarray(goal, dtype),
                       np.asarray(centres, dtype), np.asarray(velocities, dtype),
                       np.asarray(radii, dtype), present)


def model_radii(radii, car: Car):
    """The robots' model radii in the loop: ``max(rho, r_i + r + margin)`` (numpy or jax)."""
    xp = xp_of(radii)
    return xp.maximum(car.rho, radii + car.radius + car.margin)


def placement(pose, centres, velocities, speed):
    """(N,) the moment each robot's circle takes: when the car, driving straight at
    ``speed`` from ``pose``, could first reach the robot's centre (a few fixed-point steps
    of ``t = |O + t V - P| / speed``), at most :data:`HORIZON`."""
    import jax.numpy as jnp

    p = pose[:2]
    t = jnp.linalg.norm(centres - p, axis=-1) / speed
    for _ in range(PLACEMENT_STEPS):
        t = jnp.linalg.norm(centres + velocities * t[:, None] - p, axis=-1) / speed
    return jnp.minimum(t, HORIZON)


def arrays(obs: Observation, car: Car) -> ScenarioArrays:
    """The frame's scenario arrays on the device (module doc); jit/vmap-able, the dtype of
    ``obs``."""
    import jax.numpy as jnp

    dt = obs.centres.dtype
    n = obs.centres.shape[0]
    rho = jnp.asarray(car.rho, dt)
    speed = jnp.asarray(car.speed, dt)
    present = jnp.asarray(obs.present, bool)
    far = jnp.stack([FAR + 10.0 * jnp.arange(n, dtype=dt), jnp.full((n,), FAR, dt)], axis=1)
    big_r = jnp.where(present, model_radii(jnp.asarray(obs.radii), car), 0.0).astype(dt)
    centres = jnp.where(present[:, None], obs.centres, far)
    velocities = jnp.where(present[:, None], obs.velocities, 0.0)
    placed = placement(obs.pose, centres, velocities, speed)
    circles_at = jnp.where(present[:, None], centres + velocities * placed[:, None], far)
    bounds = jnp.asarray(car.bounds, dt)  # python floats or (4,) arrays (a batch's cars)
    circles = tangents.oriented_circles(obs.pose, obs.goal, circles_at, big_r, rho)
    none = jnp.zeros((n,), dt)  # no robot blocks by the static rules: all are judged in time
    # (so the table tests its tangents against none: the field and missing tangents only)
    table = tangents.table(circles, circles_at[:0], none[:0], bounds)
    motion = Motion(centres=centres, velocities=velocities, radii=big_r,
                    index=jnp.where(present, jnp.arange(n, dtype=jnp.int32), n),
                    speed=speed, placed=placed, wrap_penalty=jnp.asarray(0, jnp.int32))
    delta = 2.0 * jnp.pi * jnp.maximum(jnp.max(big_r, initial=0.0), rho)
    return ScenarioArrays(start=obs.pose, goal=obs.goal, centres=circles_at, model_radii=none,
                          rho=rho, bounds=bounds, delta=delta.astype(dt), tangents=table,
                          motion=motion, present=present)
