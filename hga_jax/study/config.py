"""Study configuration files (TOML): scenes, a grid of GA settings, seeds, budget.

A study file holds (paths are relative to the file)::

    name = "operator_study"       # outputs under results/<name>/
    seed = 0                      # run k of every cell is run k of this seed
    runs = 1000                   # runs per cell (one configuration on one scene)
    scenarios = ["../scenarios/robocup_paper.toml"]   # optional scene files
    plugins = ["my_operators.py"] # optional: Python files imported first
    analyses = ["paper"]          # optional extra reports: paper, penalty, scaling, reversing,
                                  # per_scene, moving
    yardstick = "tight-rope"      # the optimum the gaps are taken to: a car model's name
    [ga]                          # settings shared by every configuration
    [[families]]                  # optional generated scenes (see scenes.py)
    name = "clutter"; kind = "clutter"; obstacles = [5, 9, 15]; scenes = 10; seed = 1
    car = "reeds-shepp"           # optional: the scenes' car (default: the generator's)
    cpu_devices = 1               # optional: JAX CPU devices (1: every solver on one core)
    [[configs]]                   # each table is a grid: the product of its lists
    perm_crossover = ["cx", "pmx", "ox1"]
    [[configs]]                   # a peer (see below)
    solver = "ompl"; planner = "BITstar"; time_limit = 1.0; runs = 20
    [quick]                       # --quick: runs, scenes, obstacles, ga, configs, scenarios

A configuration's ``solver`` (default ``"hga"``) names what searches (:data:`SOLVERS`):

- ``"hga"``: hga-jax's GA with the table's settings over ``preset`` (``"paper"``, the
  default, or ``"recommended"``); ``batch = false`` runs each run alone (one compiled
  run at a time, as a user asking for one path would), instead of all runs at once;
- ``"random"``: random search, ``evaluations`` random chromosomes per run, the best
  kept (the GA with that population and 0 generations);
- ``"exact"``: the exact solver (one run per scene: it is deterministic);
- ``"frozen"``: among robots that move, the frozen-snapshot planner: the exact optimum of
  the scene with every robot standing where it is at time 0, judged in time (one run per
  scene; on a scene where nothing moves, the exact solver);
- ``"deap"``: the paper's GA written with DEAP (:mod:`hga_jax.peers.deap_ga`); of the
  GA settings it takes population, generations, the four rates and collision;
- ``"ompl"``: one of OMPL's planners (``planner``, :data:`~hga_jax.peers.ompl_planner.PLANNERS`)
  for ``time_limit`` seconds per run (:mod:`hga_jax.peers.ompl_planner`).

``runs`` (any solver) sets the runs per scene of that configuration (default: the
study's). A peer whose package is missing is skipped with one line, not an error.

Configurations are labelled by the keys their table varies (``perm_crossover=pmx``)
or by the table's ``label`` when it names one point; the first is the reference
that the statistical tests compare every other configuration with. Every problem
raises :class:`~hga_jax.errors.ConfigError` naming the file and key.
"""
from __future__ import annotations

import dataclasses
import itertools
import os
from dataclasses import dataclass, field
from typing import Any, Mapping

from hga_jax import validation
from hga_jax.model import car_model
from hga_jax.peers.ompl_planner import PLANNERS
from hga_jax.search.settings import PAPER, PRESETS, GASettings

TOP = {"name", "description", "seed", "runs", "scenarios", "plugins", "analyses", "ga",
       "families", "configs", "quick", "yardstick", "cpu_devices"}
FAMILY = {"name", "kind", "obstacles", "scenes", "seed", "density", "car"}
QUICK = {"runs", "scenes", "obstacles", "ga", "configs", "scenarios"}
KINDS = ("clutter", "obstructed", "clusters", "scattered", "corridors", "loops", "cluster_loops",
         "behind", "slot", "wall", "leaving", "crossing", "random_moving", "standing")
"""Scene generators: :mod:`hga_jax.study.scenes`, :mod:`~hga_jax.study.clusters`,
:mod:`~hga_jax.study.scattered`, :mod:`~hga_jax.study.corridors`, for free
turns :mod:`~hga_jax.study.loops`, for the Reeds–Shepp car, the parking-like
:mod:`~hga_jax.study.parking` and, with robots that move, :mod:`~hga_jax.study.moving_scenes`
(``obstacles``: the robots in all, standing and moving)."""
ANALYSES = ("paper", "penalty", "scaling", "reversing", "per_scene", "moving")


@dataclass(frozen=True)
class Family:
    """Generated scenes: ``scenes`` per obstacle count, from ``seed``."""

    name: str
    kind: str
    obstacles: tuple[int, ...]
    scenes: int
    seed: int
    density: float | None = None  # obstacles per m^2 (field grows with n); None: RoboCup field
    car: str | None = None  # the scenes' [robot] car; None: the generator's (dubins but parking)


SOLVERS = ("hga", "random", "exact", "deap", "ompl", "frozen")
"""What a configuration's ``solver`` may name (see the module doc)."""
PEER_KEYS = {"solver", "preset", "planner", "time_limit", "runs", "batch", "evaluations"}
"""Configuration keys beside the GA settings and ``label``."""
_NEEDS = {"planner": ("ompl",), "time_limit": ("ompl",), "batch": ("hga",),
          "evaluations": ("random",), "preset": ("hga",)}
DEAP_SETTINGS = ("population", "generations", "pc_upper", "pc_lower", "pm_upper",
                 "pm_lower", "collision")
"""The GA settings the DEAP peer implements (the others must be the paper's)."""


@dataclass(frozen=True)
class Config:
    """One configuration of the grid: what searches and with which settings.

    settings: the GA settings (for ``hga``, ``random`` and ``deap``; the paper's
    otherwise). runs: runs per scene (None: the study's). planner, time_limit: an
    OMPL configuration's planner and seconds per run. batch: ``hga`` runs searched
    all at once (True) or one at a time (False)."""

    label: str
    settings: GASettings
    solver: str = "hga"
    planner: str | None = None
    time_limit: float | None = None
    runs: int | None = None
    batch: bool = True

    def identity(self) -> tuple:
        return (self.settings, self.solver, self.planner, self.time_limit, self.runs,
                self.batch)


@dataclass
class Study:
    name: str
    source: str
    seed: int
    runs: int
    scenarios: list[str]
    families: list[Family]
    configs: list[Config]
    plugins: list[str] = field(default_factory=list)
    analyses: list[str] = field(default_factory=list)
    description: str = ""
    quick: bool = False
    yardstick: str = car_model.DEFAULT
    cpu_devices: int | None = None

    def runs_of(self, config: Config) -> int:
        """Runs per scene of ``config``: its own ``runs``, else the study's (1: exact, frozen)."""
        if config.solver in ("exact", "frozen"):
            return 1
        return config.runs if config.runs is not None else self.runs


_err = validation.error


def _keys(table: Any, allowed: set[str], source: str, where: str) -> Mapping[str, Any]:
    if not isinstance(table, Mapping):
        raise _err(source, where or "file", f"must be a table, got {table!r}")
    for k in table:
        if k not in allowed:
            raise _err(source, f"{where}.{k}" if where else k,
                       f"unknown key (known: {', '.join(sorted(allowed))})")
    return table


def _int(v: Any, source: str, key: str, low: int, high: int = 2**31) -> int:
    return validation.integer(v, source, key, low, high)


_strings = validation.strings


def _family(t: Any, i: int, source: str, quick: Mapping[str, Any]) -> Family:
    where = f"families[{i + 1}]"  # counted from 1, as obstacles are
    t = _keys(t, FAMILY, source, where)
    for k in ("name", "kind", "obstacles"):
        if k not in t:
            raise _err(source, f"{where}.{k}", "missing key")
    if not (isinstance(t["name"], str) and t["name"].isidentifier()):
        raise _err(source, f"{where}.name", f"must be an identifier, got {t['name']!r}")
    if t["kind"] not in KINDS:
        raise _err(source, f"{where}.kind", f"must be one of {', '.join(KINDS)}, got {t['kind']!r}")
    obs = quick.get("obstacles", t["obstacles"])
    key = "quick.obstacles" if "obstacles" in quick else f"{where}.obstacles"
    if not isinstance(obs, list) or not obs:
        raise _err(source, key, f"must be a non-empty list of integers, got {obs!r}")
    least = {"obstructed": 3, "clusters": 3, "scattered": 2, "corridors": 2, "leaving": 2,
             "crossing": 2, "random_moving": 2, "standing": 2}.get(t["kind"], 1)
    obs = tuple(_int(n, source, key, least, 1001) for n in obs)
    scenes = _int(quick.get("scenes", t.get("scenes", 1)), source, f"{where}.scenes", 1, 10_001)
    density = t.get("density")
    if density is not None and (isinstance(density, bool) or not isinstance(density, (int, float))
                                or not 0 < density < 20):
        raise _err(source, f"{where}.density", f"must be a number in (0, 20) obstacles per "
                   f"square metre, got {density!r}")
    if density is not None and t["kind"] in ("clusters", "scattered"):
        low, high = {"clusters": (0.8, 2.0), "scattered": (0.6, 2.5)}[t["kind"]]
        raise _err(source, f"{where}.density", f"not used by kind {t['kind']} (each scene draws "
                   f"its own, {low} to {high} obstacles per square metre); remove it")
    if density is not None and t["kind"] in ("corridors", "loops", "cluster_loops", "behind",
                                             "slot", "wall", "leaving", "crossing",
                                             "random_moving", "standing"):
        raise _err(source, f"{where}.density", f"not used by kind {t['kind']} (its fields "
                   "are fixed or drawn per scene); remove it")
    car = t.get("car")
    if car is not None and car not in car_model.cars():
        raise _err(source, f"{where}.car", f"must be one of {', '.join(car_model.cars())}, "
                   f"got {car!r}")
    return Family(t["name"], t["kind"], obs, scenes,
                  _int(t.get("seed", 0), source, f"{where}.seed", *validation.SEED),
                  None if density is None else float(density), car)


def _grid(t: Any, i: int, source: str, base, key: str) -> list[Config]:
    """The configurations of one ``[[configs]]`` table; ``base(preset)`` gives the
    settings its points are layered on."""
    where = f"{key}[{i + 1}]"  # counted from 1
    ga_keys = {f.name for f in dataclasses.fields(GASettings)}
    t = dict(_keys(t, ga_keys | PEER_KEYS | {"label"}, source, where))
    label = t.pop("label", None)
    if label is not None and not (isinstance(label, str) and label.strip()):
        raise _err(source, f"{where}.label", f"must be a non-empty string, got {label!r}")
    names = list(t)
    values = [v if isinstance(v, list) else [v] for v in t.values()]
    for k, v in zip(names, values):
        if not v:
            raise _err(source, f"{where}.{k}", "must not be an empty list")
    points = list(itertools.product(*values))
    if label is not None and len(points) > 1:
        raise _err(source, f"{where}.label", f"names one configuration, but the table has "
                   f"{len(points)}")
    out = []
    for point in points:
        config = _point(dict(zip(names, point)), source, where, base)
        varied = [f"{k}={v}" for k, v, vs in zip(names, point, values)
                  if len(vs) > 1 or len(points) == 1]
        out.append(dataclasses.replace(config, label=label or ", ".join(varied) or "base"))
    return out


def _point(values: dict[str, Any], source: str, where: str, base) -> Config:
    """One point of a grid: its solver's keys checked, its settings built."""
    peer = {k: values.pop(k) for k in list(values) if k in PEER_KEYS}
    solver = peer.get("solver", "hga")
    if solver not in SOLVERS:
        raise _err(source, f"{where}.solver", f"must be one of {', '.join(SOLVERS)}, "
                   f"got {solver!r}")
    for k in peer:
        if k in _NEEDS and solver not in _NEEDS[k]:
            raise _err(source, f"{where}.{k}", f"only for solver {' or '.join(_NEEDS[k])} "
                       f"(this configuration's is {solver!r})")
    if solver in ("exact", "ompl", "frozen") and values:
        raise _err(source, f"{where}.{next(iter(values))}", f"solver {solver!r} takes no GA "
                   "settings")
    if solver == "random":
        for k in ("population", "generations"):
            if k in values:
                raise _err(source, f"{where}.{k}", "solver 'random' takes evaluations instead")
        if "evaluations" not in peer:
            raise _err(source, f"{where}.evaluations", "missing key (random chromosomes per run)")
        values.update(population=_int(peer["evaluations"], source, f"{where}.evaluations", 1,
                                      10**7), generations=0)
    preset = peer.get("preset", "paper")
    if preset not in PRESETS:
        raise _err(source, f"{where}.preset", f"must be one of {', '.join(PRESETS)}, "
                   f"got {preset!r}")
    settings = validation.settings([validation.file_layer(values, source, where)], base(preset))
    if solver == "deap":
        for f in dataclasses.fields(GASettings):
            if f.name not in DEAP_SETTINGS and getattr(settings, f.name) != getattr(PAPER, f.name):
                raise _err(source, f"{where}.{f.name}", "solver 'deap' writes the paper's "
                           f"operators only: {f.name} must be {getattr(PAPER, f.name)!r}, got "
                           f"{getattr(settings, f.name)!r}")
    planner = time_limit = None
    if solver == "ompl":
        for k in ("planner", "time_limit"):
            if k not in peer:
                raise _err(source, f"{where}.{k}", "missing key")
        planner = peer["planner"]
        if planner not in PLANNERS:
            raise _err(source, f"{where}.planner", f"must be one of {', '.join(PLANNERS)}, "
                       f"got {planner!r}")
        time_limit = peer["time_limit"]
        if isinstance(time_limit, bool) or not isinstance(time_limit, (int, float)) or not (
                0 < time_limit <= 3600):
            raise _err(source, f"{where}.time_limit", f"must be seconds in (0, 3600], got "
                       f"{time_limit!r}")
        time_limit = float(time_limit)
    batch = peer.get("batch", True)
    if not isinstance(batch, bool):
        raise _err(source, f"{where}.batch", f"must be true or false, got {batch!r}")
    runs = peer.get("runs")
    if runs is not None:
        runs = _int(runs, source, f"{where}.runs", 1, 1_000_001)
    return Config("", settings, solver, planner, time_limit, runs, batch)


def load_study(path: str, quick: bool = False, scenes: int | None = None) -> Study:
    """Read and check a study file (see the module doc); ``quick`` applies ``[quick]``;
    ``scenes`` keeps at most that many scenes per family and obstacle count (the first
    ones: a part of the full study, whose finished cells the full study reuses)."""
    source = str(path)
    data = validation.read_toml(path)
    if not data:
        raise _err(source, "file", "is empty (a study needs name, runs, and scenarios or "
                   "families)")
    data = _keys(data, TOP, source, "")
    if quick:  # the whole study is checked first: a typo only the full grid uses stops here
        load_study(path, False, scenes)
    for k in ("name", "runs"):
        if k not in data:
            raise _err(source, k, "missing key")
    name = data["name"]
    if not (isinstance(name, str) and name.replace("-", "_").isidentifier()):
        raise _err(source, "name", f"must be a name of letters, digits, _ and -, got {name!r}")
    q = _keys(data.get("quick", {}), QUICK, source, "quick") if quick else {}
    runs = _int(q.get("runs", data["runs"]), source, "quick.runs" if "runs" in q else "runs",
                1, 1_000_001)
    seed = _int(data.get("seed", 0), source, "seed", *validation.SEED)
    here = os.path.dirname(os.path.abspath(source))
    skey = "quick.scenarios" if "scenarios" in q else "scenarios"
    scen = [os.path.normpath(os.path.join(here, p))
            for p in _strings(q.get("scenarios", data.get("scenarios", [])), source, skey)]
    plugins = [os.path.normpath(os.path.join(here, p))
               for p in _strings(data.get("plugins", []), source, "plugins")]
    analyses = _strings(data.get("analyses", []), source, "analyses")
    for a in analyses:
        if a not in ANALYSES:
            raise _err(source, "analyses", f"must name some of {', '.join(ANALYSES)}, got {a!r}")
    fams = data.get("families", [])
    if not isinstance(fams, list):
        raise _err(source, "families", f"must be an array of tables, got {fams!r}")
    families = [_family(t, i, source, q) for i, t in enumerate(fams)]
    if scenes is not None:
        families = [dataclasses.replace(f, scenes=min(f.scenes, scenes)) for f in families]
    if len({f.name for f in families}) < len(families):
        raise _err(source, "families", "two families share a name")
    if not scen and not families:
        raise _err(source, "scenarios", "a study needs scenarios or families")
    validation.load_plugins(plugins, source, lambda i: f"plugins[{i + 1}]")
    ga = _keys(data.get("ga", {}), {f.name for f in dataclasses.fields(GASettings)}, source, "ga")
    layers = [validation.file_layer(ga, source, "ga")]
    if "ga" in q:
        quick_ga = _keys(q["ga"], set(ga) | {f.name for f in dataclasses.fields(GASettings)},
                         source, "quick.ga")
        layers.append(validation.file_layer(quick_ga, source, "quick.ga"))

    def base(name: str) -> GASettings:  # the shared [ga] (and quick.ga) over a preset
        return validation.settings(layers, PRESETS[name])

    base("paper")
    key = "quick.configs" if "configs" in q else "configs"
    tables = q.get("configs", data.get("configs", [{}]))
    if not isinstance(tables, list) or not tables:
        raise _err(source, key, f"must be a non-empty array of tables, got {tables!r}")
    configs: list[Config] = []
    for i, t in enumerate(tables):
        for c in _grid(t, i, source, base, key):
            if all(c.identity() != o.identity() for o in configs):
                if any(c.label == o.label for o in configs):
                    raise _err(source, f"{key}[{i + 1}]", f"two configurations named {c.label!r}")
                configs.append(c)
    yardstick = data.get("yardstick", car_model.DEFAULT)
    for c in configs:  # free turns need the full collision test in every configuration
        validation.turns(yardstick, c.settings.collision, source, "yardstick")
    cpu = data.get("cpu_devices")
    cpu = None if cpu is None else _int(cpu, source, "cpu_devices", 1, 4097)
    return Study(name, source, seed, runs, scen, families, configs, plugins, analyses,
                 str(data.get("description", "")), quick, yardstick, cpu)
