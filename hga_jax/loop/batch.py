"""Episodes as one compiled program: frames looped on the device, episodes vmapped.

:mod:`hga_jax.loop.episode` plays one episode on the host with any planner. For the
planners that are JAX programs (``hga``, ``hga-cold``, ``sampler``: :func:`planner`) a
whole batch of episodes runs here as one program: each frame of every episode is the
planner's own frame (:func:`hga_jax.loop.replanner.frame_step`, the sampler's), the car drives the
frame's plan for ``dt`` (:func:`along`, the decoded pieces in float32), the contact test
and the robots' motion follow the episode's rules (docs/model.md, "Replanning episodes":
:data:`~hga_jax.loop.episode.CONTACT_SPACING`, reflection at the field's edges, the
``constant``, ``random`` and ``chase`` motions). The frames are a ``while_loop`` that
stops when every episode has ended; an episode that has ended keeps its state.

What is the same as :func:`hga_jax.loop.episode.run` with the same planner: the rules,
and the planner's keys (episode ``e`` with seed ``s`` plans frame ``f`` with the key the
host's planner of seed ``s`` uses). What differs: the car's
pose and the robots are carried in float32 (the host's in float64), so a long episode may
take a different turn at a near tie; the noise and the ``random`` motion draw from JAX
keys (``fold_in(key(s), 58)``), not from numpy's generator; the contact test samples a
fixed number of moments per frame (:func:`moments`). Units: metres, seconds, radians.
"""
from __future__ import annotations

import functools
import math
from typing import Any, NamedTuple, Sequence

import jax
import jax.numpy as jnp
import numpy as np

from hga_jax.search import rng
from hga_jax.search.settings import GASettings
from . import episode as episodes
from . import frame as frames
from . import planners
from .replanner import LOOP, Replanner, frame_step

OUTCOMES = ("timeout", "reached", "collided")
"""The outcome codes of :class:`Outcomes` (index = code)."""
STABILITY_S = 0.5
"""Seconds of plan compared between consecutive frames (plan stability)."""
STABILITY_POINTS = 16
"""Points along those seconds."""
SHARED_SPEED = 2.0
"""m/s: a batch's contact test samples its frames as finely as a car of this speed needs at
least (every :data:`~hga_jax.loop.episode.CONTACT_SPACING` m), so that batches of cars up
to it share one compiled program."""


class Scenes(NamedTuple):
    """E episodes' starting states, padded to a robot bound N: ``first`` their first frames'
    :class:`~hga_jax.loop.frame.Observation` (a leading axis E: ``pose`` and ``goal`` (E, 3),
    ``centres`` and ``velocities`` (E, N, 2), ``radii`` and ``present`` (E, N)), ``box``
    (E, 4) the field ``xmin, xmax, ymin, ymax`` (infinite without one), ``seed`` (E,)
    int32, ``car`` each episode's :class:`~hga_jax.loop.frame.Car` as arrays (E,)
    (``bounds`` (E, 4)): scenes of several cars (radius, turning radius, speed, walls) run
    in one program."""

    first: Any
    box: Any
    seed: Any
    car: Any


class Outcomes(NamedTuple):
    """Per episode (E,): ``outcome`` (int32 code of :data:`OUTCOMES`), ``time`` (s; the
    moment of reaching the goal or of the contact, the limit on timeout), ``robot`` (the
    robot in contact, -1), ``overlap`` (m), ``frames`` (frames played), ``colliding``
    (frames whose plan collides as predicted), ``shift`` (mean distance, m, between the
    next :data:`STABILITY_S` seconds of consecutive plans, over the frames that have a
    previous plan), ``ego`` (3,) the car's last pose."""

    outcome: Any
    time: Any
    robot: Any
    overlap: Any
    frames: Any
    colliding: Any
    shift: Any
    ego: Any


def scenes(scenarios: Sequence[Any], seeds: Sequence[int], bound: int | None = None) -> Scenes:
    """The :class:`Scenes` of host scenarios (one per episode) and their seeds, padded to
    ``bound`` (default the largest robot count)."""
    n = max(int(sc.n) for sc in scenarios)
    bound = n if bound is None else int(bound)
    if bound < n:
        raise ValueError(f"bound: {bound} is below a scene's {n} robots")
    rows = []
    for sc in scenarios:
        vel = (np.zeros((sc.n, 2)) if sc.velocities is None
               else np.asarray(sc.velocities, np.float64).reshape(-1, 2))
        robots = np.concatenate([np.asarray(sc.centres, np.float64).reshape(-1, 2), vel,
                                 np.asarray(sc.radii, np.float64).reshape(-1, 1)], axis=1)
        obs = frames.observation(sc.start, sc.goal, robots, bound)
        f = sc.field
        box = (np.array([-np.inf, np.inf, -np.inf, np.inf]) if f is None
               else np.array([f.xmin, f.xmax, f.ymin, f.ymax]))
        rows.append((obs, box.astype(np.float32), episodes.car_of(sc)))
    stack = lambda xs: np.stack(xs)  # noqa: E731
    obs = jax.tree.map(lambda *xs: stack(xs), *[r[0] for r in rows])
    cars = [r[2] for r in rows]
    f32 = np.float32
    car = frames.Car(*(np.asarray([getattr(c, k) for c in cars], f32)
                       for k in ("radius", "rho", "speed", "bounds", "margin")))
    return Scenes(obs,
                  stack([r[1] for r in rows]), np.asarray(seeds, np.int32), car)


def along(circles, arcs, lines, count, u):
    """The car's poses ``(x, y, heading)`` (K, 3) at distances ``u`` (K,) along one decoded
    tight-rope path (one row of :class:`~hga_jax.model.decode.Decoded`: ``circles`` (S, 4),
    ``arcs`` (S, 5), ``lines`` (S - 1, 5), ``count``), and its length. Piece ``2s`` is the
    arc on slot ``s`` (from its arrival point, ``r * sweep`` long), piece ``2s + 1`` the leg
    to slot ``s + 1``; a distance beyond the end gives the end pose."""
    S = circles.shape[0]
    dt = circles.dtype
    slot = jnp.arange(S)
    cx, cy, r, sign = (circles[:, i] for i in range(4))
    ax, ay, swp = arcs[:, 0], arcs[:, 1], arcs[:, 4]
    arc_len = jnp.where(slot < count, r * swp, 0.0)
    p1x, p1y, p2x, p2y = (lines[:, i] for i in range(4))
    dx, dy = p2x - p1x, p2y - p1y
    line_len = jnp.where(jnp.arange(S - 1) < count - 1, jnp.hypot(dx, dy), 0.0)
    lengths = jnp.stack([arc_len, jnp.concatenate([line_len, jnp.zeros((1,), dt)])],
                        axis=1).reshape(-1)  # (2S,) arc 0, line 0, arc 1, ...
    ends = jnp.cumsum(lengths)
    total = ends[-1]
    u = jnp.clip(u, 0.0, total)
    k = jnp.clip(jnp.searchsorted(ends, u, side="right"), 0, 2 * S - 1)
    # a distance at the very end lies on the last piece with a length
    last = jnp.max(jnp.where(lengths > 0, jnp.arange(2 * S), 0))
    k = jnp.where(u >= total, last, k)
    local = u - (ends[k] - lengths[k])
    s = k // 2
    on_arc = k % 2 == 0
    # an arc: counter-clockwise where its circle's sign is -1 (the pieces' sweep = -sign swp)
    turn = -sign[s]
    a0 = jnp.arctan2(ay[s] - cy[s], ax[s] - cx[s])
    ang = a0 + turn * local / jnp.maximum(r[s], 1e-12)
    arc_pose = (cx[s] + r[s] * jnp.cos(ang), cy[s] + r[s] * jnp.sin(ang),
                ang + turn * (jnp.pi / 2))
    li = jnp.minimum(s, S - 2)
    ll = jnp.maximum(line_len[li], 1e-12)
    w = local / ll
    line_pose = (p1x[li] + w * dx[li], p1y[li] + w * dy[li], jnp.arctan2(dy[li], dx[li]))
    pose = [jnp.where(on_arc, a, b) for a, b in zip(arc_pose, line_pose)]
    heading = jnp.arctan2(jnp.sin(pose[2]), jnp.cos(pose[2]))
    return jnp.stack([pose[0], pose[1], heading], axis=-1), total


def moments(speed: float, dt: float) -> int:
    """How many pieces a frame's way is cut into for the contact test: every
    :data:`~hga_jax.loop.episode.CONTACT_SPACING` metres of a full frame's drive at
    ``speed`` (the batch's fastest car), at least 8 (the host's rule for a full frame)."""
    return max(8, int(math.ceil(speed * dt / episodes.CONTACT_SPACING)))


def _reflect(pos, vel, radii, box):
    """:func:`hga_jax.loop.episode._reflect` on the device (an infinite box reflects
    nothing)."""
    out_p, out_v = [], []
    for axis in range(2):
        low, high = box[2 * axis] + radii, box[2 * axis + 1] - radii
        p, v = pos[:, axis], vel[:, axis]
        under, over = p < low, p > high
        p = jnp.where(under, 2 * low - p, jnp.where(over, 2 * high - p, p))
        out_p.append(p)
        out_v.append(jnp.where(under | over, -v, v))
    return jnp.stack(out_p, axis=1), jnp.stack(out_v, axis=1)


def _steer(vel, pos, car_xy, motion: str, s: episodes.EpisodeSettings, key):
    """:func:`hga_jax.loop.episode._steer` on the device (its random draws from ``key``)."""
    if motion == "constant":
        return vel
    if motion == "random":
        ka, km = jax.random.split(key)
        a = jax.random.uniform(ka, vel.shape[:1], vel.dtype, 0.0, 2.0 * math.pi)
        m = s.accel * jnp.sqrt(jax.random.uniform(km, vel.shape[:1], vel.dtype))
        vel = vel + s.dt * m[:, None] * jnp.stack([jnp.cos(a), jnp.sin(a)], axis=1)
    else:  # chase
        to = car_xy[None, :] - pos
        d = jnp.maximum(jnp.hypot(to[:, 0], to[:, 1]), 1e-9)
        change = s.max_speed * to / d[:, None] - vel
        c = jnp.hypot(change[:, 0], change[:, 1])
        vel = vel + change * jnp.minimum(1.0, s.accel * s.dt / jnp.maximum(c, 1e-12))[:, None]
    speed = jnp.hypot(vel[:, 0], vel[:, 1])
    return vel * jnp.minimum(1.0, s.max_speed / jnp.maximum(speed, 1e-12))[:, None]


class HGA(NamedTuple):
    """The ``hga`` planner in a batch (``warm=False``: ``hga-cold``): the replanner's frame
    (:func:`~hga_jax.loop.replanner.frame_step`) with its settings, ``generations`` per frame
    and ``immigrants`` (a count); its state the GA's, from a blank one."""

    settings: GASettings
    generations: int
    immigrants: int
    warm: bool = True

    @property
    def name(self) -> str:
        return "hga" if self.warm else "hga-cold"

    def key(self, seed, f):  # car 0 of a Replanner of this seed
        return jax.random.fold_in(jax.random.fold_in(rng.key(seed), 0), f)

    def plan(self, key, state, init, obs, car):
        state = state if self.warm else init
        state, (circles, arcs, lines, count, _, violations, _) = frame_step(
            key, state, obs, car, self.settings, self.generations, self.immigrants)
        return state, (circles, arcs, lines, count), violations


class Sampler(NamedTuple):
    """The ``sampler`` planner in a batch (:class:`~hga_jax.loop.planners.SamplerPlanner`'s
    frame, its keys and its memory of last frame's winner)."""

    samples: int = planners.SAMPLES
    name: str = "sampler"

    def key(self, seed, f):
        return jax.random.fold_in(rng.key(seed), f)

    def plan(self, key, state, init, obs, car):
        perm, labels, out = planners._sample_step(key, obs, state, car, self.samples)
        circles, arcs, lines, count, _, violations = out
        return (perm, labels), (circles, arcs, lines, count), violations


class _Carry(NamedTuple):
    pose: Any
    pos: Any
    vel: Any
    state: Any  # the planner's
    prev: Any  # last frame's decoded plan (circles, arcs, lines, count), for stability
    has_prev: Any
    done: Any
    out: Outcomes
    shift_sum: Any
    shift_n: Any


def _one_frame(f, c: _Carry, sc: Scenes, init, planner, s: episodes.EpisodeSettings,
               cuts: int):
    """Frame ``f`` of one episode (its carry ``c``), as :func:`hga_jax.loop.episode.run`."""
    dt = jnp.float32
    car = sc.car
    world = jax.random.fold_in(jax.random.fold_in(rng.key(sc.seed), 58), f)
    k_noise, k_motion = jax.random.split(world)
    t = f.astype(dt) * s.dt
    seen_p, seen_v = c.pos, c.vel
    if s.noise > 0:
        e = jax.random.normal(k_noise, c.pos.shape[:1] + (4,), dt) * s.noise
        seen_p, seen_v = c.pos + e[:, :2], c.vel + e[:, 2:]
    o = sc.first
    obs = o._replace(pose=c.pose, centres=seen_p, velocities=seen_v)
    state, plan, violations = planner.plan(planner.key(sc.seed, f), c.state, init, obs, car)
    step = car.speed * s.dt
    u = jnp.linspace(0.0, 1.0, cuts + 1, dtype=dt)
    way, total = along(*plan, u * step)
    driven = jnp.minimum(step, total)
    tau = u * driven / car.speed
    at = c.pos[None] + c.vel[None] * tau[:, None, None]  # (K, N, 2)
    gap = (jnp.hypot(way[:, None, 0] - at[..., 0], way[:, None, 1] - at[..., 1])
           - (car.radius + o.radii)[None])
    gap = jnp.where(o.present[None], gap, jnp.inf)
    hit = jnp.any(gap < 0)
    flat = jnp.argmin(gap)
    i, j = flat // gap.shape[1], flat % gap.shape[1]
    reached = ~hit & (total <= step)
    # plan stability: this plan's next seconds against the last plan's at the same moments
    v = jnp.linspace(0.0, STABILITY_S, STABILITY_POINTS, dtype=dt) * car.speed
    now, _ = along(*plan, v)
    before, _ = along(*c.prev, v + step)
    shift = jnp.mean(jnp.hypot(now[:, 0] - before[:, 0], now[:, 1] - before[:, 1]))
    live = ~c.done
    ended = hit | reached
    code = jnp.where(hit, 2, jnp.where(reached, 1, 0)).astype(jnp.int32)
    when = jnp.where(hit, t + tau[i], t + total / car.speed)
    out = c.out
    out = Outcomes(
        outcome=jnp.where(live & ended, code, out.outcome),
        time=jnp.where(live & ended, when, jnp.where(live, t + s.dt, out.time)),
        robot=jnp.where(live & hit, j.astype(jnp.int32), out.robot),
        overlap=jnp.where(live & hit, -gap[i, j], out.overlap),
        frames=out.frames + live.astype(jnp.int32),
        colliding=out.colliding + (live & (violations > 0)).astype(jnp.int32),
        shift=out.shift, ego=jnp.where(live, way[-1], out.ego))
    pos = c.pos + c.vel * s.dt
    pos, vel = _reflect(pos, c.vel, o.radii, sc.box)
    vel = _steer(vel, pos, way[-1, :2], s.motion, s, k_motion)
    keep = lambda old, new: jax.tree.map(lambda a, b: jnp.where(live, b, a), old, new)  # noqa: E731
    counted = live & c.has_prev
    return _Carry(pose=keep(c.pose, way[-1]), pos=keep(c.pos, pos), vel=keep(c.vel, vel),
                  state=keep(c.state, state), prev=keep(c.prev, plan),
                  has_prev=c.has_prev | live, done=c.done | ended, out=out,
                  shift_sum=c.shift_sum + jnp.where(counted, shift, 0.0),
                  shift_n=c.shift_n + counted.astype(jnp.int32))


@functools.lru_cache(maxsize=None)
def _program(planner, s: episodes.EpisodeSettings, cuts: int):
    limit = int(math.ceil(s.time_limit / s.dt - 1e-9))

    def run(sc: Scenes, init, prev):
        E = sc.first.pose.shape[0]
        one = functools.partial(_one_frame, planner=planner, s=s, cuts=cuts)
        frame = jax.vmap(one, in_axes=(None, 0, 0, None))
        zero = jnp.zeros((E,), jnp.float32)
        out = Outcomes(jnp.zeros((E,), jnp.int32), zero, jnp.full((E,), -1, jnp.int32), zero,
                       jnp.zeros((E,), jnp.int32), jnp.zeros((E,), jnp.int32), zero, sc.first.pose)
        many = lambda a: jnp.broadcast_to(a, (E,) + jnp.shape(a))  # noqa: E731
        c0 = _Carry(sc.first.pose, sc.first.centres, sc.first.velocities, jax.tree.map(many, init),
                    jax.tree.map(many, prev), jnp.zeros((E,), bool), jnp.zeros((E,), bool),
                    out, zero, jnp.zeros((E,), jnp.int32))

        def body(state):
            f, c = state
            return f + 1, frame(f, c, sc, init)

        _, c = jax.lax.while_loop(lambda st: (st[0] < limit) & ~jnp.all(st[1].done), body,
                                  (jnp.int32(0), c0))
        o = c.out
        return o._replace(time=jnp.where(c.done, o.time, limit * s.dt),
                          shift=c.shift_sum / jnp.maximum(c.shift_n, 1))

    return jax.jit(run)


def planner(name: str, bound: int, generations: int = 5, immigrants: float = 0.15,
            ga: GASettings | None = None):
    """The batch planner called ``name`` (``hga``, ``hga-cold``, ``sampler``) for ``bound``
    robots, and its initial state (numpy)."""
    n = int(bound)
    if name == "sampler":
        labels = np.zeros(n + 2, np.int32)
        labels[[0, -1]] = -1  # the direct path, turning left at both ends (as the host's)
        return Sampler(), (np.arange(n, dtype=np.int32), labels)
    if name not in ("hga", "hga-cold"):
        raise ValueError(f"planner: the batch runs hga, hga-cold and sampler, got {name!r}")
    rp = Replanner(frames.Car(0.09, 0.2, 1.0), n, settings=ga or LOOP,
                   generations=generations, immigrants=immigrants)  # its state's shapes
    init = jax.device_get(jax.tree.map(lambda a: a[0], rp._blank))
    return HGA(rp.settings.structure(), rp.generations, rp.immigrants, name == "hga"), init


_COMPILED: dict = {}


def run_batch(scenes_: Scenes, settings: episodes.EpisodeSettings = episodes.EpisodeSettings(),
              name: str = "hga", generations: int = 5, immigrants: float = 0.15,
              ga: GASettings | None = None, timing: dict | None = None) -> Outcomes:
    """Every episode of ``scenes_`` (:func:`scenes`) with the planner ``name`` (``hga``,
    ``hga-cold`` or ``sampler``), as one compiled program (module doc); numpy arrays out.
    ``timing``: a dict that gets ``compile_s`` (0 where this process compiled the same
    program before) and ``run_s``, apart."""
    import time

    n = scenes_.first.centres.shape[1]
    plan, init = planner(name, n, generations, immigrants, ga)
    S = n + 2
    f32 = np.float32
    prev = (np.zeros((S, 4), f32), np.zeros((S, 5), f32), np.zeros((S - 1, 5), f32),
            np.int32(0))
    # cut for 2 m/s at least, so that batches of slower cars share one program
    cuts = moments(max(float(np.max(scenes_.car.speed)), SHARED_SPEED), settings.dt)
    args = (scenes_, init, prev)
    shapes = jax.tree.map(lambda a: (np.shape(a), np.asarray(a).dtype.str), args)
    key = (plan, settings, cuts, str(shapes))
    t0 = time.perf_counter()
    if key not in _COMPILED:
        _COMPILED[key] = _program(plan, settings, cuts).lower(*args).compile()
    t1 = time.perf_counter()
    out = jax.block_until_ready(_COMPILED[key](*args))
    t2 = time.perf_counter()
    if timing is not None:
        timing.update(compile_s=t1 - t0, run_s=t2 - t1)
    return Outcomes(*(np.asarray(x) for x in jax.device_get(out)))
