"""Seeded families of RoboCup-like scenes, each saved as a scenario TOML file.

Robots as on the bundled RoboCup scene: radius 0.09 m, minimum turning radius
0.15 m, so every obstacle is a model circle of radius 0.18 m; no two obstacle
centres closer than 0.30 m; the field (2.8 m x 2.3 m, or larger at a given
density) is kept. The start pose is near the left edge, the goal pose near the
right edge, headings within 60 degrees of +x.

- ``clutter``: obstacles uniform over the field.
- ``obstructed``: about half of the obstacles scattered along the straight line
  from start to goal, the rest uniform; a scene is kept only when that straight
  line and all four direct Dubins paths (no obstacle touched) collide and the
  exact optimum wraps at least three obstacles.
- ``clusters`` (:mod:`hga_jax.study.clusters`): held-out scenes by another rule
  (clumps, per-scene robot and field, any headings), blocked as ``obstructed``.
- ``scattered`` (:mod:`hga_jax.study.scattered`) and ``corridors``
  (:mod:`hga_jax.study.corridors`): two more held-out rules (obstacles strewn with
  mixed radii; barriers across the field with gaps to thread).
- ``loops`` and ``cluster_loops`` (:mod:`hga_jax.study.loops`): poses a few turning
  radii apart, kept where free turns beat the tight rope (for ``turns = "free"``).
- ``behind``, ``slot`` and ``wall`` (:mod:`hga_jax.study.parking`): parking-like poses
  of a Reeds–Shepp car, kept where reversing shortens the path (with ``car =
  "dubins"``: where the forward car has a feasible, expressible optimum).
- ``leaving``, ``crossing``, ``random_moving`` and ``standing``
  (:mod:`hga_jax.study.moving_scenes`): robots that move (the last the control, the same
  draws standing); kept where the standing robots' optimum exists and a path feasible
  in time is known (their optimum may be a path no chromosome expresses).

Every kept scene has a feasible optimum that a chromosome expresses (touching
each obstacle at most once; with leg genes for the free-turn families), so a GA run
can hit it. Scene ``i`` with ``n``
obstacles of a family with seed ``s`` depends on ``(s, n, i)`` alone.
"""
from __future__ import annotations

import math
import os
from dataclasses import dataclass

import numpy as np

from hga_jax.host.config import scenario_from_dict
from hga_jax.model.exact import solve
from hga_jax.host.output import write_file
from hga_jax.model.scenario import Scenario
from .config import Family
from .scene_files import FIELD_H, FIELD_W, blocked, scene_dict, to_toml
from .scene_files import MODEL_RADIUS, SPACING  # noqa: F401  (the families' RoboCup sizes)
from .scene_files import place_uniform as _place

MAX_TRIES = 5000


@dataclass
class Scene:
    name: str
    family: str  # family name, or "files" for a scene file of the study
    path: str  # its TOML file
    scenario: Scenario
    text: str  # the file's content (part of a cell's identity)


def field_size(n: int, density: float | None) -> tuple[float, float]:
    """The RoboCup field, or a field of its shape holding ``n / density`` square metres."""
    if density is None:
        return FIELD_W, FIELD_H
    area = max(n / density, FIELD_W * FIELD_H)
    w = math.sqrt(area * FIELD_W / FIELD_H)
    return w, area / w


def _poses(rng: np.random.Generator, w: float, h: float) -> tuple[list[float], list[float]]:
    start = [rng.uniform(0.25, 0.5), rng.uniform(0.35, h - 0.35), rng.uniform(-60, 60)]
    goal = [rng.uniform(w - 0.5, w - 0.25), rng.uniform(0.35, h - 0.35), rng.uniform(-60, 60)]
    return start, goal


def generate(kind: str, n: int, seed: int, index: int, name: str,
             density: float | None = None, car: str | None = None) -> dict:
    """Scene ``index`` with ``n`` obstacles of a ``kind`` family with ``seed``: a mapping.
    ``car``: the family's car, which the parking-like kinds keep their scenes for (the
    other kinds draw and keep alike for any car; the caller sets it)."""
    if kind == "clusters":
        from . import clusters

        return clusters.generate(n, seed, index, name, density)
    if kind == "corridors":
        from . import corridors

        return corridors.generate(n, seed, index, name, density)
    if kind == "scattered":
        from . import scattered

        return scattered.generate(n, seed, index, name, density)
    if kind in ("loops", "cluster_loops"):
        from . import loops

        return loops.generate(kind, n, seed, index, name, density)
    if kind in ("behind", "slot", "wall"):
        from . import parking

        return parking.generate(kind, n, seed, index, name, density, car)
    if kind in ("leaving", "crossing", "random_moving", "standing"):
        from . import moving_scenes

        return moving_scenes.generate(kind, n, seed, index, name, density, car)
    rng = np.random.default_rng([seed, n, index])
    w, h = field_size(n, density)
    for _ in range(MAX_TRIES):
        start, goal = _poses(rng, w, h)
        try:
            centres = _place(rng, n, w, h, start, goal, kind == "obstructed")
        except RuntimeError:
            continue
        d = scene_dict(name, w, h, start, goal, centres)
        try:
            sc = scenario_from_dict(d, name)
        except ValueError:
            continue
        if kind == "obstructed" and not blocked(sc):
            continue
        opt = solve(sc)
        if not (opt.feasible and opt.expressible):
            continue
        if kind == "obstructed" and len(opt.touched) < 3:
            continue
        return d
    raise RuntimeError(f"no {kind} scene with {n} obstacles found in {MAX_TRIES} tries")


def family_scenes(fam: Family, folder: str) -> list[Scene]:
    """The family's scenes, written to ``folder`` (atomically, only when changed)."""
    out = []
    for n in fam.obstacles:
        for i in range(fam.scenes):
            name = f"{fam.name}_n{n:03d}_{i:03d}"
            d = generate(fam.kind, n, fam.seed, i, name, fam.density, fam.car)
            if fam.car is not None:
                d["robot"]["car"] = fam.car
            text = to_toml(d, f"{fam.kind} scene {i} with {n} obstacles of family {fam.name!r} "
                              f"(seed {fam.seed}), generated by hga-jax study.\n"
                              f"Rerun it alone: hga-jax run <this file> --runs 1000")
            path = os.path.join(folder, name + ".toml")
            if not (os.path.exists(path) and open(path).read() == text):
                write_file(path, lambda fh: fh.write(text))
            out.append(Scene(name, fam.name, path, scenario_from_dict(d, path), text))
    return out
