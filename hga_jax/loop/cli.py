"""The ``hga-jax episode`` subcommand: one replanning episode, written as ``episode.json``."""
from __future__ import annotations

import argparse
import math
import os

from . import episode as episodes
from .planners import PLANNERS


def add_parser(sub, formatter=argparse.HelpFormatter) -> None:
    p = sub.add_parser(
        "episode", help="a replanning episode among robots that move (episode.json)",
        formatter_class=formatter, description=(
            "Play one episode of a scenario: a frame every DT seconds, the planner replans "
            "from the car's pose, the car drives its plan for DT, the robots move by the "
            "chosen motion; it ends reached, collided or at the time limit. Writes "
            "DIR/episode.json (every frame: time, the car's pose, the robots, the plan's "
            "milliseconds; the outcome)."))
    p.add_argument("scenario", help="scenario TOML file (robots may have vx, vy)")
    p.add_argument("--planner", default="hga", choices=PLANNERS,
                   help="hga: the warm-started HGA in time; hga-cold: a fresh population each "
                   "frame; exact: the exact optimum among the robots frozen at each frame; "
                   "sampler: the direct paths, last frame's winner and 100 random "
                   "chromosomes judged in time each frame")
    p.add_argument("--motion", default="constant", choices=episodes.MOTIONS,
                   help="how the robots move: straight on, reflected at the field's edges; "
                   "random accelerations; steering toward the car")
    p.add_argument("--seed", type=int, default=0, help="the episode's seed (planner and motion)")
    p.add_argument("--out", metavar="DIR", help="output folder (default: results/<scenario "
                   "file name>-episode)")
    p.add_argument("--dt", type=float, default=1.0 / 60.0, help="seconds between frames")
    p.add_argument("--time-limit", type=float, default=20.0, help="seconds before a timeout")
    p.add_argument("--noise", type=float, default=0.0, help="standard deviation of the "
                   "observed positions (m) and velocities (m/s)")
    p.add_argument("--generations", type=int, default=5,
                   help="generations per frame (hga, hga-cold)")
    p.add_argument("--bound", type=int, help="robots the planner is compiled for (default: "
                   "the scene's count)")
    p.add_argument("--animate", action="store_true", help="also write DIR/episode.gif: the "
                   "robots and their predicted tracks, the car's trail and its plan, every "
                   "sixth frame")
    p.add_argument("--force", action="store_true", help="replace an existing episode.json")
    p.add_argument("--no-cache", action="store_true", help="do not keep compiled programs "
                   "on disk")


def run(args: argparse.Namespace) -> int:
    from hga_jax import validation
    from hga_jax.errors import ConfigError
    from hga_jax.host.config import load_scenario
    from hga_jax.host.output import write_json, writable_folder

    from . import planners

    scenario = load_scenario(args.scenario)
    for flag, value in (("--dt", args.dt), ("--time-limit", args.time_limit)):
        if not (math.isfinite(value) and value > 0):
            raise validation.error("command line", flag, f"must be a number > 0, got {value!r}")
    if not (math.isfinite(args.noise) and args.noise >= 0):
        raise validation.error("command line", "--noise", f"must be a number >= 0, got "
                               f"{args.noise!r}")
    validation.at_least(args.generations, "command line", "--generations", 1)
    if args.bound is not None and args.bound < scenario.n:
        raise validation.error("command line", "--bound", f"must be at least the scene's "
                               f"{scenario.n} robots, got {args.bound}")
    if scenario.car != "dubins":
        raise ConfigError(f"{args.scenario}: robot.car: episodes take the forward car "
                          f"(dubins) so far, got {scenario.car!r}")
    out = args.out or os.path.join("results", os.path.splitext(
        os.path.basename(args.scenario))[0] + "-episode")
    writable_folder(out)
    target = os.path.join(out, "episode.json")
    for name in ("episode.json", "episode.gif"):
        if os.path.exists(os.path.join(out, name)) and not args.force:
            raise ConfigError(f"{out}: output folder: already holds an {name}; use --force "
                              "to replace it, or another folder")
    if not args.no_cache:
        from hga_jax.compiled import enable_compilation_cache

        enable_compilation_cache()
    settings = episodes.EpisodeSettings(dt=args.dt, time_limit=args.time_limit,
                                        motion=args.motion, noise=args.noise)
    car = episodes.car_of(scenario)
    planner = planners.make(args.planner, car, episodes.bound_of(scenario, args.bound),
                            seed=args.seed, generations=args.generations)
    ep = episodes.run(scenario, planner, settings, seed=args.seed, keep_plans=args.animate)
    write_json(target, ep.to_dict())
    written = [target]
    if args.animate:
        from hga_jax.host.output import write_file
        from hga_jax.host.plots.episode_animation import animate

        gif = os.path.join(out, "episode.gif")
        box = None if scenario.field is None else (scenario.field.xmin, scenario.field.xmax,
                                                   scenario.field.ymin, scenario.field.ymax)
        tmp = gif + ".part.gif"
        animate(ep, ep.plans, tmp, box)
        os.replace(tmp, gif)
        written.append(gif)
    print(episodes.summary(ep))
    print("wrote " + ", ".join(written))
    return 0
