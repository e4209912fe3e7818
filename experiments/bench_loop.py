"""Per-frame plan time of the replanner (hga_jax/loop): one car, and several cars in one call.

Frames of a moving scene: 11 robots (the bound), 5 of them driving straight across the
way, the car starting at (0.3, 1.5) for the goal (4.2, 1.5) at 1 m/s; the robots move
between frames as they are predicted (60 frames per second) and the car's pose follows
its plan. After ``warm_up`` (compile, timed apart), ``--frames`` frames are timed one by
one (``Plan.plan_ms``: the whole ``step``, host conversion included): median, p99 and max,
and how many programs the replanner compiled (1: no recompilation). Then the same for
``--cars`` cars batched in one call (each its own copy of the scene, the robot count
changing from frame to frame between 6 and 11: the bound's padding). A fixed pure-Python
loop is timed before and after (calibration: the machine is shared).

Usage (from the repository root)::

    python3 experiments/bench_loop.py [--frames 300] [--generations 5] [--cars 6]
"""
from __future__ import annotations

import argparse

import numpy as np
from calibration import calibration

BOUND = 11


def robots(k: int, t: float) -> np.ndarray:
    """The scene's robots at time ``t``: 6 standing, 5 crossing the way (slot order kept)."""
    rng = np.random.default_rng(7)
    out = []
    for i in range(BOUND):
        x, y = rng.uniform(0.8, 3.8), rng.uniform(0.3, 2.7)
        vx, vy = (0.0, 0.0) if i < 6 else (rng.uniform(-0.3, 0.3), rng.choice([-1, 1]) * rng.uniform(0.4, 1.0))
        out.append((x + vx * t, y + vy * t, vx, vy, 0.09))
    return np.array(out[:k])


def main(argv=None) -> int:
    from hga_jax.host.poses import at
    from hga_jax.model.path import segments_length
    from hga_jax.loop import Car, Replanner, observation

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frames", type=int, default=300)
    ap.add_argument("--generations", type=int, default=5)
    ap.add_argument("--cars", type=int, default=6)
    ap.add_argument("--deadline-ms", type=float, default=None,
                    help="a frame's budget in wall time (up to --generations generations)")
    args = ap.parse_args(argv)
    print(f"calibration: pure-Python loop of 10^6 multiply-adds: {calibration() * 1e3:.1f} ms")
    car = Car(0.09, 0.2, 1.0, (0.09, 4.41, 0.09, 2.91))
    goal = (4.2, 1.5, 0.0)

    def frames(cars: int):
        rp = Replanner(car, BOUND, generations=args.generations, cars=cars, seed=1,
                       deadline_ms=args.deadline_ms)
        compile_s = rp.warm_up()
        poses = [(0.3, 1.5, 0.0)] * cars
        times, ran = [], []
        for f in range(args.frames):
            t = f / 60.0
            k = [BOUND if cars == 1 else 6 + (f + c) % (BOUND - 5) for c in range(cars)]
            obs = [observation(poses[c], goal, robots(k[c], t), BOUND) for c in range(cars)]
            batch = type(obs[0])(*(np.stack(x) for x in zip(*obs)))
            plans = rp.step(batch)
            times.append(plans[0].plan_ms)
            ran.append(plans[0].generations)
            for c, p in enumerate(plans):
                if p.segments and segments_length(p.segments) > 1.0 / 60.0:
                    x, y, h = at(p.segments, [1.0 / 60.0])[0][:3]
                    poses[c] = (x, y, h)
                else:  # arrived: start over
                    poses[c] = (0.3, 1.5, 0.0)
        ms = np.array(times)
        print(f"{cars} car(s), {BOUND} robots bound, {args.generations} generations of "
              f"{rp.settings.population} per frame, {args.frames} frames: plan ms median "
              f"{np.median(ms):.2f}, p99 {np.percentile(ms, 99):.2f}, max {ms.max():.2f}; "
              f"frames over 16.7 ms: {int((ms > 16.7).sum())}; compile {compile_s:.1f} s; "
              f"programs compiled: {rp.compiles()}"
              + ("" if args.deadline_ms is None else
                 f"; deadline {args.deadline_ms:g} ms: generations run median "
                 f"{np.median(ran):g} (min {min(ran)}, max {max(ran)}), frames over it "
                 f"{int((ms > args.deadline_ms).sum())}"), flush=True)

    frames(1)
    if args.cars > 1:
        frames(args.cars)
    print(f"calibration again: {calibration() * 1e3:.1f} ms")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
