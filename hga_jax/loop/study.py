"""The replanning study: seeded episodes per family of scenes, every planner on the same ones.

A study file with ``kind = "replanning"`` (``hga-jax study configs/studies/replanning.toml``)
names families of scenes (the generators of :mod:`hga_jax.study.moving_scenes`, a robot
count each, a motion of :data:`hga_jax.loop.episode.MOTIONS`) and planners. Episode ``k``
of a family and size plays scene ``k`` with seed ``seed + k`` under every planner. The
JAX planners (``hga``, ``hga-cold``, ``sampler``) run each cell's episodes as one compiled
program (:mod:`hga_jax.loop.batch`); ``exact`` (the robots frozen at each frame) runs on the
host, on the cell's first ``host_episodes`` episodes.

Per episode the study keeps the outcome, its time, the robot in contact, whether the first
frame had a path known to keep clear of every robot in time (the exact module's answer for
the scene as it stands at time 0: a contact after such a first frame was avoidable as
predicted; without one it is reported apart), the time to the goal against that path's
(its length over the car's speed: a clairvoyant planner's time where the robots keep their
velocities), the plan's mean shift between frames and the frames whose plan collides as
predicted. Per cell (family, size, planner): reached, collided and timeout with 95% Wilson
intervals, contacts after a first frame with a clear path, the median time ratio and the
median shift, and the milliseconds per episode-frame (compile excluded).

Cells are kept in ``cells/`` of the output folder and never run again (a study resumes);
``replanning.md`` and ``replanning.csv`` hold the table, ``episodes.csv`` one row per
episode.
"""
from __future__ import annotations

import json
import math
import os
import time
import tomllib
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hga_jax.errors import ConfigError

BATCHED = ("hga", "hga-cold", "sampler")
HOST = ("exact",)
KINDS = ("crossing", "leaving", "random_moving", "standing")


@dataclass(frozen=True)
class Family:
    name: str
    kind: str
    robots: tuple[int, ...]
    motion: str
    seed: int


@dataclass(frozen=True)
class PlannerSpec:
    name: str
    label: str
    generations: int = 5


@dataclass
class ReplanningStudy:
    name: str
    description: str
    seed: int
    episodes: int
    host_episodes: int
    time_limit: float
    noise: float
    families: list[Family] = field(default_factory=list)
    planners: list[PlannerSpec] = field(default_factory=list)


def is_replanning(path: str) -> bool:
    """Whether the study file ``path`` is a replanning study (``kind = "replanning"``)."""
    try:
        with open(path, "rb") as fh:
            return tomllib.load(fh).get("kind") == "replanning"
    except (OSError, tomllib.TOMLDecodeError):
        return False


def _err(path: str, key: str, why: str) -> ConfigError:
    return ConfigError(f"{os.path.basename(path)}: {key}: {why}")


def load(path: str, quick: bool = False) -> ReplanningStudy:
    """The study of ``path`` (its ``[quick]`` table over the top with ``quick``); a bad key
    is one :class:`~hga_jax.errors.ConfigError` naming the file and the key."""
    from hga_jax.loop.episode import MOTIONS

    with open(path, "rb") as fh:
        d = tomllib.load(fh)
    if quick:
        d = {**d, **d.get("quick", {})}
    known = {"kind", "name", "description", "seed", "episodes", "host_episodes", "time_limit",
             "noise", "families", "planners", "quick"}
    for k in d:
        if k not in known:
            raise _err(path, k, "unknown key")

    def number(key, default, kind=int, low=0):
        v = d.get(key, default)
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) \
                or v < low or (kind is int and v != int(v)):
            raise _err(path, key, f"must be a{'n integer' if kind is int else ' number'} >= {low}")
        return kind(v)

    st = ReplanningStudy(str(d.get("name", "replanning")), str(d.get("description", "")),
                         number("seed", 0), number("episodes", 100, low=1),
                         number("host_episodes", 20), number("time_limit", 10.0, float, 0.1),
                         number("noise", 0.0, float))
    for i, f in enumerate(d.get("families", [])):
        where = f"families[{i}]"
        kind = f.get("kind")
        if kind not in KINDS:
            raise _err(path, f"{where}.kind", f"must be one of {', '.join(KINDS)}")
        motion = f.get("motion", "constant")
        if motion not in MOTIONS:
            raise _err(path, f"{where}.motion", f"must be one of {', '.join(MOTIONS)}")
        robots = f.get("robots", [9])
        if not robots or any(not isinstance(n, int) or n < 2 for n in robots):
            raise _err(path, f"{where}.robots", "must be a list of integers >= 2")
        st.families.append(Family(str(f.get("name", f"{kind}_{motion}")), kind, tuple(robots),
                                  motion, int(f.get("seed", st.seed + 100 + i))))
    for i, p in enumerate(d.get("planners", [{"name": n} for n in BATCHED + HOST])):
        name = p.get("name")
        if name not in BATCHED + HOST:
            raise _err(path, f"planners[{i}].name", f"must be one of {', '.join(BATCHED + HOST)}")
        gens = p.get("generations", 5)
        if not isinstance(gens, int) or gens < 1:
            raise _err(path, f"planners[{i}].generations", "must be an integer >= 1")
        st.planners.append(PlannerSpec(name, str(p.get("label", name)), gens))
    if not st.families:
        raise _err(path, "families", "at least one family")
    return st


def scene(fam: Family, n: int, k: int):
    """Scene ``k`` of a family with ``n`` robots (a Scenario)."""
    from hga_jax.host.config import scenario_from_dict
    from hga_jax.study.moving_scenes import generate

    name = f"{fam.name}_n{n:03d}_{k:03d}"
    return scenario_from_dict(generate(fam.kind, n, fam.seed, k, name), name)


def reference(sc) -> tuple[bool, float]:
    """Whether a path clear in time is known at the first frame, and its length (m)."""
    from hga_jax.model.exact import solve

    r = solve(sc)
    return bool(r.feasible), float(r.length) if r.feasible else math.nan


def _cell_rows(study: ReplanningStudy, fam: Family, n: int, spec: PlannerSpec, scenes,
               refs) -> tuple[list[dict], float, int]:
    from . import batch, episode, planners as host_planners

    settings = episode.EpisodeSettings(time_limit=study.time_limit, motion=fam.motion,
                                       noise=study.noise)
    seeds = [study.seed + k for k in range(len(scenes))]
    rows = []
    t0 = time.perf_counter()
    if spec.name in BATCHED:
        timing: dict = {}
        got = batch.run_batch(batch.scenes(scenes, seeds), settings, name=spec.name,
                              generations=spec.generations, timing=timing)
        compile_s = timing["compile_s"]
        for k, sc in enumerate(scenes):
            rows.append(dict(outcome=batch.OUTCOMES[int(got.outcome[k])],
                             time=float(got.time[k]), robot=int(got.robot[k]),
                             frames=int(got.frames[k]), colliding=int(got.colliding[k]),
                             shift=float(got.shift[k])))
        frames = int(got.frames.sum())
    else:
        frames, compile_s = 0, 0.0
        for k, sc in enumerate(scenes[:study.host_episodes]):
            car = episode.car_of(sc)
            tc = time.perf_counter()
            pl = host_planners.make(spec.name, car, sc.n, seed=seeds[k], field=_field(sc))
            compile_s += time.perf_counter() - tc
            ep = episode.run(sc, pl, settings, seed=seeds[k])
            frames += len(ep.frames)
            rows.append(dict(outcome=ep.outcome, time=ep.time,
                             robot=-1 if ep.contact is None else int(ep.contact["robot"]),
                             frames=len(ep.frames),
                             colliding=sum(f["status"] != "clear" for f in ep.frames),
                             shift=math.nan))
    seconds = time.perf_counter() - t0 - compile_s  # the episodes' time, compile apart
    for k, r in enumerate(rows):
        clear, length = refs[k]
        sc = scenes[k]
        r.update(family=fam.name, kind=fam.kind, motion=fam.motion, robots=n,
                 planner=spec.label, scene=sc.name, seed=seeds[k], clear_first=clear,
                 reference_time=length / float(sc.speed) if clear else math.nan)
    return rows, seconds, frames


def _field(sc) -> dict | None:
    f = sc.field
    if f is None:
        return None
    return {"xmin": f.xmin, "xmax": f.xmax, "ymin": f.ymin, "ymax": f.ymax,
            "keep_inside": f.keep_inside}


def run(path: str, out: str | None = None, quick: bool = False, force: bool = False,
        progress: bool = True, episodes: int | None = None) -> dict[str, Any]:
    """Run (or resume) the study of ``path`` into ``out`` (``episodes``: only the first of
    each cell's); its folder, table and episodes."""
    import pandas as pd

    study = load(path, quick)
    if episodes is not None:
        study.episodes = min(study.episodes, int(episodes))
        study.host_episodes = min(study.host_episodes, study.episodes)
    out = out or os.path.join("results", study.name + ("_quick" if quick else ""))
    cells_dir = os.path.join(out, "cells")
    stamp = os.path.join(out, "study.json")
    os.makedirs(cells_dir, exist_ok=True)
    me = {"name": study.name, "file": os.path.basename(path), "quick": quick,
          "episodes": study.episodes, "host_episodes": study.host_episodes}
    if os.path.exists(stamp):
        with open(stamp) as fh:
            other = json.load(fh)
        if other != me and not force:
            raise ConfigError(f"{out}: holds the study {other.get('name')!r} "
                              f"({other.get('file')}); --force replaces it")
        if other != me:
            for f in os.listdir(cells_dir):
                os.remove(os.path.join(cells_dir, f))
    with open(stamp, "w") as fh:
        json.dump(me, fh)
    rows, cells = [], []
    for fam in study.families:
        for n in fam.robots:
            scenes = refs = None
            for spec in study.planners:
                cell = os.path.join(cells_dir, f"{fam.name}_n{n:03d}_{spec.label}.json")
                if os.path.exists(cell):
                    with open(cell) as fh:
                        got = json.load(fh)
                else:
                    if scenes is None:
                        scenes = [scene(fam, n, k) for k in range(study.episodes)]
                        refs = [reference(sc) for sc in scenes]
                    if progress:
                        print(f"{fam.name}, {n} robots, {spec.label}: "
                              f"{study.episodes if spec.name in BATCHED else min(study.episodes, study.host_episodes)} episodes",
                              flush=True)
                    ep_rows, seconds, frames = _cell_rows(study, fam, n, spec, scenes, refs)
                    got = {"rows": ep_rows, "seconds": seconds, "frames": frames}
                    tmp = cell + ".tmp"
                    with open(tmp, "w") as fh:
                        json.dump(got, fh)
                    os.replace(tmp, cell)
                rows += got["rows"]
                cells.append(dict(family=fam.name, motion=fam.motion, robots=n,
                                  planner=spec.label, seconds=got["seconds"],
                                  frames=got["frames"]))
    episodes = pd.DataFrame(rows)
    table = summary(episodes, pd.DataFrame(cells))
    episodes.to_csv(os.path.join(out, "episodes.csv"), index=False)
    table.to_csv(os.path.join(out, "replanning.csv"), index=False)
    with open(os.path.join(out, "replanning.md"), "w") as fh:
        fh.write(markdown_page(study, table))
    return {"folder": out, "table": table, "episodes": episodes}


def summary(episodes, cells):
    """One row per (family, size, planner): the module doc's measures."""
    import pandas as pd

    from hga_jax.study import stats

    out = []
    for (fam, n, planner), g in episodes.groupby(["family", "robots", "planner"], sort=False):
        e = len(g)
        row = {"family": fam, "motion": g["motion"].iloc[0], "robots": n, "planner": planner,
               "episodes": e}
        for what in ("reached", "collided", "timeout"):
            k = int((g["outcome"] == what).sum())
            lo, hi = stats.wilson(k, e)
            row[what] = k / e
            row[f"{what}_low"], row[f"{what}_high"] = lo, hi
        clear = g[g["clear_first"]]
        row["clear_first"] = len(clear)
        row["contacts_after_clear_first"] = int((clear["outcome"] == "collided").sum())
        reached = g[(g["outcome"] == "reached") & g["clear_first"]]
        ratio = reached["time"] / reached["reference_time"]
        row["time_ratio_median"] = float(ratio.median()) if len(ratio) else math.nan
        row["shift_median_m"] = float(g["shift"].median())
        c = cells[(cells["family"] == fam) & (cells["robots"] == n) & (cells["planner"] == planner)]
        frames = int(c["frames"].sum())
        row["ms_per_episode_frame"] = 1e3 * float(c["seconds"].sum()) / max(frames, 1)
        out.append(row)
    return pd.DataFrame(out)


def _pct(v: float, lo: float, hi: float) -> str:
    return f"{100 * v:.1f}% [{100 * lo:.1f}, {100 * hi:.1f}]"


def markdown_page(study: ReplanningStudy, table) -> str:
    import pandas as pd

    from hga_jax.study.table import markdown

    view = pd.DataFrame({
        "family": table["family"], "motion": table["motion"], "robots": table["robots"],
        "planner": table["planner"], "episodes": table["episodes"],
        "reached [95% Wilson]": [_pct(r.reached, r.reached_low, r.reached_high)
                                 for r in table.itertuples()],
        "collided [95% Wilson]": [_pct(r.collided, r.collided_low, r.collided_high)
                                  for r in table.itertuples()],
        "timeout": [f"{100 * v:.1f}%" for v in table["timeout"]],
        "contacts after a clear first frame": [
            f"{r.contacts_after_clear_first} of {r.clear_first}" for r in table.itertuples()],
        "time to goal / clear path's (median)": [
            "-" if not math.isfinite(v) else f"{v:.3f}" for v in table["time_ratio_median"]],
        "plan shift, m (median)": ["-" if not math.isfinite(v) else f"{v:.4f}"
                                   for v in table["shift_median_m"]],
        "ms per episode-frame": [f"{v:.2f}" for v in table["ms_per_episode_frame"]],
    })
    return (f"# {study.name}: replanning episodes\n\n{study.description}\n\n"
            f"{study.episodes} episodes per family and size ({study.host_episodes} for the "
            f"planners that run on the host), time limit {study.time_limit:g} s, frames every "
            f"1/60 s, observation noise {study.noise:g}. A contact after a clear first frame: "
            f"the exact module knew a path clear in time of every robot as the scene stood "
            f"at time 0. Time to goal over the time of that path (reached episodes with one). "
            f"Plan shift: the mean distance between the next 0.5 s of consecutive plans. "
            f"ms per episode-frame: the cell's wall time, compile excluded, over the frames "
            f"its episodes played (a batch computes every episode's frame until its last "
            f"episode ends).\n\n"
            + markdown(view) + "\n")
