"""Episodes: frames every ``dt`` in which a planner replans, the car drives its plan and robots move.

An episode starts from a scenario (the car's start and goal poses, the robots with their
velocities, the field). Each frame (docs/model.md, "Replanning episodes"):

1. the planner observes the car's pose and every robot's position and velocity (plus
   Gaussian noise of ``noise`` metres and metres per second, seeded, when asked) and
   returns a plan to the goal (:mod:`hga_jax.loop.planners`); without one the car goes on
   along its previous plan (straight on past its end);
2. the car drives exactly along the plan for ``dt`` at its constant speed; the robots move
   by the episode's true motion (:data:`MOTIONS`) at their velocity through the frame;
3. a **contact** is when the physical discs overlap at some moment of the frame,
   ``|p - c_i| < r + r_i`` (sampled every :data:`CONTACT_SPACING` m of the car's way, the
   robots where they are at that moment): the episode ends ``collided``; it ends
   ``reached`` in the frame whose plan ends at the goal pose (the car drives it exactly:
   the pose is the goal's to rounding, within ``tolerance``), and ``timeout`` at
   ``time_limit``.

Motions (the robots' velocities change between frames only):

- ``constant``: straight on at the scenario's velocity, reflected at the field's edges
  (a robot's disc stays inside the field when there is one);
- ``random``: each frame a seeded random acceleration of at most ``accel`` (uniform in the
  disc), the speed capped at ``max_speed``;
- ``chase``: each robot steers toward the car, its velocity changing by at most
  ``accel * dt`` a frame toward ``max_speed`` straight at the car.

:func:`run` plays one episode and returns its :class:`Episode`, whose :meth:`Episode.to_dict`
is the ``episode.json`` of the command line (``hga-jax episode``). Host code (numpy).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hga_jax.host.poses import at as poses_at
from hga_jax.model.path import segments_length
from . import frame as frames
from . import planners as planner_mod

MOTIONS = ("constant", "random", "chase")
CONTACT_SPACING = 2e-3
"""Metres between the car's points at which a frame's contact test looks (and at least 8
moments per frame)."""


@dataclass(frozen=True)
class EpisodeSettings:
    """An episode's rules (module doc); seconds, metres, m/s, m/s^2, degrees."""

    dt: float = 1.0 / 60.0
    time_limit: float = 20.0
    motion: str = "constant"
    noise: float = 0.0
    accel: float = 2.0
    max_speed: float = 1.5
    tolerance_m: float = 1e-3
    tolerance_deg: float = 0.5

    def __post_init__(self) -> None:
        if self.motion not in MOTIONS:
            raise ValueError(f"motion: must be one of {', '.join(MOTIONS)}, got {self.motion!r}")
        for k in ("dt", "time_limit", "accel", "max_speed", "tolerance_m", "tolerance_deg"):
            v = getattr(self, k)
            if not (math.isfinite(v) and v > 0):
                raise ValueError(f"{k}: must be a number > 0, got {v!r}")
        if not (math.isfinite(self.noise) and self.noise >= 0):
            raise ValueError(f"noise: must be a number >= 0, got {self.noise!r}")


@dataclass
class Episode:
    """What happened: one row per frame, the outcome and its time."""

    scenario: str
    planner: str
    seed: int
    settings: EpisodeSettings
    car: frames.Car
    car_name: str
    goal: tuple
    frames: list = field(default_factory=list)
    plans: list = field(default_factory=list)  # each frame's plan (kept with keep_plans)
    outcome: str = "timeout"
    time: float = 0.0
    contact: dict | None = None

    def plan_ms(self) -> np.ndarray:
        return np.array([f["plan_ms"] for f in self.frames])

    def to_dict(self) -> dict:
        """``episode.json`` (docs/model.md, "Replanning episodes")."""
        s = self.settings
        return {"scenario": self.scenario, "dt": s.dt, "speed": self.car.speed,
                "robot": {"radius": self.car.radius, "min_turn_radius": self.car.rho,
                          "car": self.car_name},
                "goal": {"x": self.goal[0], "y": self.goal[1],
                         "heading_deg": math.degrees(self.goal[2])},
                "tolerance": {"position_m": s.tolerance_m, "heading_deg": s.tolerance_deg},
                "planner": self.planner, "motion": s.motion, "noise": s.noise,
                "seed": self.seed, "time_limit": s.time_limit, "frames": self.frames,
                "outcome": self.outcome, "time": self.time, "contact": self.contact}


def _reflect(pos, vel, radii, box):
    """Positions and velocities reflected at the box's edges (discs kept inside)."""
    if box is None:
        return pos, vel
    pos, vel = pos.copy(), vel.copy()
    for axis, (lo, hi) in enumerate(((box[0], box[1]), (box[2], box[3]))):
        low, high = lo + radii, hi - radii
        under, over = pos[:, axis] < low, pos[:, axis] > high
        pos[:, axis] = np.where(under, 2 * low - pos[:, axis], pos[:, axis])
        pos[:, axis] = np.where(over, 2 * high - pos[:, axis], pos[:, axis])
        vel[:, axis] = np.where(under | over, -vel[:, axis], vel[:, axis])
    return pos, vel


def _steer(vel, pos, car_xy, s: EpisodeSettings, rng: np.random.Generator):
    """The robots' velocities for the next frame under the episode's motion."""
    if s.motion == "constant":
        return vel
    if s.motion == "random":
        a = rng.uniform(0.0, 2.0 * math.pi, len(vel))
        m = s.accel * np.sqrt(rng.uniform(0.0, 1.0, len(vel)))
        vel = vel + s.dt * m[:, None] * np.stack([np.cos(a), np.sin(a)], axis=1)
    else:  # chase
        to = np.asarray(car_xy) - pos
        d = np.maximum(np.hypot(to[:, 0], to[:, 1]), 1e-9)
        want = s.max_speed * to / d[:, None]
        change = want - vel
        c = np.hypot(change[:, 0], change[:, 1])
        limit = s.accel * s.dt
        vel = vel + change * np.minimum(1.0, limit / np.maximum(c, 1e-12))[:, None]
    speed = np.hypot(vel[:, 0], vel[:, 1])
    return vel * np.minimum(1.0, s.max_speed / np.maximum(speed, 1e-12))[:, None]


def _straight(pose, length: float) -> list:
    """A line ahead of ``pose`` (the car's way past the end of its last plan)."""
    x, y, h = pose
    return [{"type": "line", "start": [x, y],
             "end": [x + length * math.cos(h), y + length * math.sin(h)]}]


def run(scenario: Any, planner: Any, settings: EpisodeSettings = EpisodeSettings(),
        seed: int = 0, progress: Any = None, keep_plans: bool = False) -> Episode:
    """Play one episode of ``scenario`` with ``planner`` (module doc); ``keep_plans``: keep
    the plan the car drives in each frame (``Episode.plans``, for an animation)."""
    s = settings
    car = car_of(scenario)
    rng = np.random.default_rng([seed, 58])
    pos = np.asarray(scenario.centres, np.float64).reshape(-1, 2).copy()
    vel = (np.zeros_like(pos) if scenario.velocities is None else
           np.asarray(scenario.velocities, np.float64).reshape(-1, 2).copy())
    radii = np.asarray(scenario.radii, np.float64).reshape(-1)
    f = scenario.field
    box = None if f is None else (f.xmin, f.xmax, f.ymin, f.ymax)
    pose = tuple(float(v) for v in scenario.start)
    goal = tuple(float(v) for v in scenario.goal)
    ep = Episode(scenario.name, planner.name, seed, s, car, car_name(scenario), goal)
    planner.reset()
    plan: list | None = None
    step = car.speed * s.dt
    frames_total = int(math.ceil(s.time_limit / s.dt - 1e-9))
    for k in range(frames_total):
        t = k * s.dt
        seen = np.concatenate([pos, vel, radii[:, None]], axis=1)
        if s.noise > 0:
            seen[:, :4] += rng.normal(0.0, s.noise, (len(pos), 4))
        got = planner.plan(planner_mod.View(pose, goal, seen))
        if got.segments is not None:
            plan = got.segments
        if not plan:
            plan = _straight(pose, step * 2)
        if keep_plans:
            ep.plans.append(plan)
        ep.frames.append({"t": t, "ego": [pose[0], pose[1], pose[2], 1],
                          "obstacles": np.concatenate([pos, vel, radii[:, None]], axis=1).tolist(),
                          "plan_ms": got.plan_ms, "status": got.status})
        total = segments_length(plan)
        driven = min(step, total)
        cuts = max(8, int(math.ceil(driven / CONTACT_SPACING)))
        u = np.linspace(0.0, driven, cuts + 1)
        way = poses_at(plan, u)
        tau = u / car.speed
        cx = pos[:, 0][None] + vel[:, 0][None] * tau[:, None]
        cy = pos[:, 1][None] + vel[:, 1][None] * tau[:, None]
        gap = np.hypot(way[:, 0][:, None] - cx, way[:, 1][:, None] - cy) - (car.radius + radii)[None]
        if (gap < 0).any():
            i, j = np.unravel_index(int(np.argmin(gap)), gap.shape)
            ep.outcome, ep.time = "collided", t + float(tau[i])
            ep.contact = {"robot": int(j), "time": ep.time, "overlap_m": float(-gap[i, j]),
                          "at_start": bool(k == 0 and i == 0)}
            break
        if total <= step:  # the plan ends at the goal in this frame
            ep.outcome, ep.time = "reached", t + total / car.speed
            break
        end = way[-1]
        pose = (float(end[0]), float(end[1]), float(end[2]))
        plan = _rest(plan, driven)
        pos = pos + vel * s.dt
        pos, vel = _reflect(pos, vel, radii, box)
        vel = _steer(vel, pos, pose[:2], s, rng)
        if progress is not None:
            progress(k + 1, frames_total)
    else:
        ep.outcome, ep.time = "timeout", frames_total * s.dt
    return ep


def _length(seg: dict) -> float:
    return segments_length([seg])


def _rest(plan: list, driven: float) -> list:
    """The plan's pieces after ``driven`` metres (the piece under way cut at that point)."""
    out, s = [], 0.0
    for seg in plan:
        length = _length(seg)
        if s + length <= driven + 1e-12:
            s += length
            continue
        cut = max(driven - s, 0.0)
        if cut > 0.0:
            if seg["type"] == "arc":
                turn = 1.0 if float(seg["sweep"]) >= 0 else -1.0
                seg = dict(seg, start_angle=float(seg["start_angle"]) + turn * cut / float(seg["radius"]),
                           sweep=float(seg["sweep"]) - turn * cut / float(seg["radius"]))
            else:
                (x0, y0), (x1, y1) = seg["start"], seg["end"]
                u = cut / length
                seg = dict(seg, start=[x0 + u * (x1 - x0), y0 + u * (y1 - y0)])
        out.append(seg)
        s += length
    return out


def car_of(scenario: Any) -> frames.Car:
    """The episode's :class:`~hga_jax.loop.frame.Car` of a scenario."""
    return frames.Car(float(scenario.robot_radius), float(scenario.min_turn_radius),
                      float(scenario.speed), tuple(float(v) for v in scenario.bounds))


def car_name(scenario: Any) -> str:
    return str(getattr(scenario, "car", "dubins") or "dubins")


def bound_of(scenario: Any, bound: int | None = None) -> int:
    """The robot bound of an episode: ``bound`` or the scenario's robot count."""
    n = int(scenario.n)
    if bound is not None and bound < n:
        raise ValueError(f"bound: {bound} is below the scene's {n} robots")
    return n if bound is None else int(bound)


def summary(ep: Episode) -> str:
    """One line: outcome, time and per-frame plan times."""
    ms = ep.plan_ms()
    return (f"{ep.planner}: {ep.outcome} at {ep.time:.3f} s after {len(ep.frames)} frames; "
            f"plan ms median {np.median(ms):.2f}, p99 {np.percentile(ms, 99):.2f}, "
            f"max {ms.max():.2f}" if ms.size else f"{ep.planner}: {ep.outcome}")
