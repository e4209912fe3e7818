"""Planners on the same replanning episodes: outcomes, time to the goal, per-frame plan time.

Scenes from the study's generators of robots that move (:mod:`hga_jax.study.moving_scenes`,
``--families``, ``--robots`` robots, seed 2026, scenes 0..``--scenes``-1), each played as an
episode (:mod:`hga_jax.loop.episode`, 60 frames per second, 20 s limit) by every planner
of ``--planners`` under every motion of ``--motions``, with the same episode seed. Prints
one line per (family, motion, planner): reached / collided / timeout counts, the median
time to the goal of the reached episodes, and the plan's milliseconds per frame over all
frames (median, p99, max; the first frame of an episode included, the compile not: each
planner is built and compiled once, before its episodes).

Usage (from the repository root)::

    python3 experiments/episodes_compare.py [--scenes 10] [--robots 9]
        [--families crossing random_moving] [--motions constant random]
        [--planners hga hga-cold exact sampler]
"""
from __future__ import annotations

import argparse
import time

import numpy as np
from calibration import calibration


def main(argv=None) -> int:
    from hga_jax import scenario_from_dict
    from hga_jax.loop import episode, planners
    from hga_jax.study import moving_scenes

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scenes", type=int, default=10)
    ap.add_argument("--robots", type=int, default=9)
    ap.add_argument("--families", nargs="+", default=["crossing", "random_moving"])
    ap.add_argument("--motions", nargs="+", default=["constant", "random"])
    ap.add_argument("--planners", nargs="+", default=["hga", "hga-cold", "exact", "sampler"])
    ap.add_argument("--generations", type=int, default=5)
    args = ap.parse_args(argv)
    print(f"calibration: {calibration() * 1e3:.1f} ms")
    t_all = time.perf_counter()
    for family in args.families:
        scenes = [scenario_from_dict(moving_scenes.generate(family, args.robots, 2026, i,
                                                            f"{family}_{i}"), f"{family}_{i}")
                  for i in range(args.scenes)]
        for motion in args.motions:
            for name in args.planners:
                made: dict = {}
                outcomes, times, ms = [], [], []
                for k, sc in enumerate(scenes):
                    car = episode.car_of(sc)
                    key = (car, name)
                    if key not in made:
                        made[key] = planners.make(name, car, args.robots, seed=k,
                                                  generations=args.generations)
                    ep = episode.run(sc, made[key], episode.EpisodeSettings(motion=motion),
                                     seed=k)
                    outcomes.append(ep.outcome)
                    if ep.outcome == "reached":
                        times.append(ep.time)
                    ms.extend(ep.plan_ms().tolist())
                ms = np.array(ms)
                count = {o: outcomes.count(o) for o in ("reached", "collided", "timeout")}
                print(f"{family:<14} {motion:<9} {name:<9} reached {count['reached']:>3} "
                      f"collided {count['collided']:>3} timeout {count['timeout']:>3}  "
                      f"time to goal median {np.median(times) if times else float('nan'):.2f} s"
                      f"  plan ms median {np.median(ms):.2f} p99 {np.percentile(ms, 99):.2f} "
                      f"max {ms.max():.2f}", flush=True)
    print(f"total {time.perf_counter() - t_all:.0f} s; calibration again: "
          f"{calibration() * 1e3:.1f} ms")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
