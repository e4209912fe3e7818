"""GA settings: a frozen, hashable dataclass. Its structure (:meth:`GASettings.structure`)
is static in the compiled step, its rates (:data:`RATES`) are the step's data.

Defaults are the paper's (section 4): population 50, 50 generations,
``pc = 0.4`` and ``pm = 0.02`` for both modules, roulette selection, cycle
crossover and inversion mutation on the permutation, two-point crossover on the
labels, per-gene redraw of the labels, no elitism. Operator names
(``selection``, ``perm_crossover``, ``perm_mutation``, ``label_crossover``,
``label_mutation``, ``path_mutation``) are those of :mod:`hga_jax.search.registry`.

Probability conventions:
- ``pc_upper`` / ``pc_lower``: per *pair* of selected parents, the chance that the
  module's crossover is applied (otherwise the children copy the parents).
- ``pm_upper``: per *individual*, the chance that the permutation is mutated once.
- ``pm_lower``: per *gene*, the chance that a label is redrawn (to another value
  of its allowed set).

``label_binding``: ``"position"`` (the paper: the label at position ``k`` turns
the obstacle at position ``k`` of the permutation) or ``"obstacle"`` (label
``1 + i`` belongs to obstacle ``i`` wherever the permutation puts it, so
crossover and mutation of the permutation keep each obstacle's turning
direction). Path moves (:mod:`hga_jax.search.path_ops`, off in the paper): ``path_mutation`` names
a move on the touched sequence (``"none"``: no move) applied to each child with
probability ``pm_path`` after the paper's operators. ``seeding``: the fraction of
generation 0 (and of every restart) built by wrapping the obstacles that block
the direct path, leg by leg (:func:`hga_jax.search.path_ops.wrap_blockers`) instead of
drawn at random; ``seeding_via``: the share of those seeded chromosomes whose wrapping
starts from a path through one obstacle (the first of their random permutation, with
its drawn label: a drawn 0 leaves the direct path) instead of the direct path, so that
fresh populations also try corridors that the direct path's blockers do not lead to;
``restart_via``: in a restart of a run whose best path so far collides, that share of
the seeded chromosomes (spread as ``seeding_via``'s, and those of both go) starts via an
obstacle too, so a run stuck on a colliding path looks elsewhere (1: every seed; 0:
restarts seed as generation 0 does).
``restart_arcs``: in a restart of a run whose best path so far collides, that share of
the seeded chromosomes (spread as ``seeding_via``'s) also sees arcs while it wraps: once
no leg of a seed is blocked, an arc with a violation of its own (read from the turn
table, as the guided move reads it) gets an untouched obstacle whose model circle
overlaps the arc's obstacle, right after it and turning the same way, so the seed
follows a chain of overlapping circles round to its end (per-arc information,
:func:`hga_jax.search.path_ops.wrap_from_words`; the tight rope only, where there is a
turn table; 0: seeds read legs only).
``wrap_clearer``: the share of wraps (seeding's, and the ``repair`` move's) that go
round the side of the wrapped obstacle whose two new legs pass through fewer obstacles
(per-leg information, :func:`hga_jax.search.path_ops._wrap`); the other wraps, and a
wrap whose two sides pass through as many, take a random side (0: every side random).
The tight rope only: under free turns and for the Reeds–Shepp car the wraps keep random
sides (their legs are not the tangents whose blockers the share counts).
``guided_arcs``: the share of the penalty that the guided move's score adds for the arc
on the moved obstacle's circle when that arc has a violation of its own (it runs into
an obstacle whose model circle overlaps, or out of a kept field), where it leaves and
where it enters (read from the turn table, as a leg's violation is read from the leg
table; the arcs of its neighbours, which change too, are not read). The tight rope,
where a turn table is built; 0: legs only.
``restart_after = R``: at generations R, 2R, 3R, ..., a run whose best-so-far
did not improve in the last R generations starts a new population, drawn like
generation 0, without elites (0: never restart). The best-so-far is kept.

``islands = K``: the population is K islands of ``population / K`` consecutive
individuals (fewer where K does not split it into equal islands of more than ``elites``:
:attr:`GASettings.island_count`) that select parents and keep ``elites`` each among
themselves; every
``migrate_every`` generations the best of each island replaces the worst of the next
(:mod:`hga_jax.search.islands`; 0: never). ``islands = 1`` (the paper): one population.

``generations_per_obstacle = k``: a run on ``n`` obstacles makes
``generations + k * max(0, n - 9)`` generations (9: the paper's scene), so the
budget grows with the scene; :meth:`GASettings.for_obstacles` resolves it (the
runner does, and records the rule in ``result.json``). 0 (the paper): a fixed count.
``reversing_budget = m``: a car that also drives backward (a car model that
``reverses``, the Reeds–Shepp car) makes ``m`` times those generations (its chromosome
is larger: leg genes with gears, end moves); 1 (the paper): as the forward car.
``pairs_from = k``: ``path_mutation = "guided_pairs"`` on fewer than ``k`` obstacles is
the plain ``"guided"`` move (resolved by :meth:`GASettings.for_obstacles`, recorded in
``result.json``); 0: on every scene.

``turns``: the car model the GA searches (:mod:`hga_jax.model.car_model`, the object
:attr:`GASettings.model`). ``"tight-rope"`` (the paper's): the chromosome is the
permutation and the labels. ``"free"`` (the car's shortest path, full collision rule
only): the model adds a module of leg genes, one per position (0 a straight tangent to
the next touched circle, 1 or 2 a free circle of radius rho joining the two, on one
side or the other: :mod:`hga_jax.model.cars.free_turns.legs`), crossed over by ``leg_crossover``
with probability ``pc_legs`` per pair and mutated by ``leg_mutation`` with probability
``pm_legs`` per gene; it rides with the labels' ``label_binding``. The Reeds–Shepp
car (``"reeds-shepp"``) has leg genes of seven values (:mod:`hga_jax.model.cars.reeds_shepp.reversing`)
and moves on the ends of its path (``end_mutation``, with probability ``pm_ends`` per
child: :mod:`hga_jax.search.end_ops`); ``ends_of_best = k`` makes the last k children
of every generation copies of the parents' best, moved at their ends (a local search
around the best, counted as every child). Under free turns and for the Reeds–Shepp car
``straight_of_best = k`` makes k children of every generation copies of the parents'
best with every leg gene 0 (each leg the tangent, driven forward): the tight-rope path
of its touched sequence, which a search with leg genes otherwise reaches only gene by
gene; ``tight_of_best = k`` makes k more such copies, each then moved
by the path move as the tight rope scores it (a blocked tangent counts as blocked where
a free leg gets round it), so a sequence that wraps a blocker, which the model's own
legs score as no shorter, is still tried. Under a model without genes of its own the leg
and end settings do nothing and the random stream is the paper's.

``penalty_weight`` scales the paper's penalty per violation
``2*pi*R`` during the search (1 = the paper); reported lengths, feasibility and
gaps do not depend on it.
"""
from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any, Callable, Mapping, NamedTuple, Sequence

import numpy as np

from hga_jax.errors import ConfigError
from hga_jax.model import car_model
from hga_jax.model.collision import COLLISIONS

LABEL_BINDINGS = ("position", "obstacle")
SHARES = ("pc_upper", "pm_upper", "pc_lower", "pm_lower", "pm_path", "pc_legs", "pm_legs",
          "pm_ends", "seeding_via", "restart_via", "wrap_clearer", "guided_arcs", "restart_arcs")
"""The :data:`RATES` that are probabilities or shares (float32 in the program)."""
RATES = SHARES + ("penalty_weight", "seeding", "restart_after", "migrate_every")
"""Settings that are data of a compiled program, not its structure (:meth:`GASettings.rates`):
configurations that differ only in these run the same program. Of ``seeding``,
``restart_after`` and ``migrate_every`` only whether they are on (> 0) is structure."""


class Rates(NamedTuple):
    """The :data:`RATES` of a configuration as arrays (scalars): probabilities float32
    (compared with the float32 uniforms of :func:`hga_jax.search.rng.unit`), the penalty
    weight in the search's float type, ``seeded`` the number of seeded individuals of a
    fresh population (``round(seeding * population)``), ``restart_after`` and
    ``migrate_every`` int32."""

    pc_upper: Any
    pm_upper: Any
    pc_lower: Any
    pm_lower: Any
    pm_path: Any
    pc_legs: Any
    pm_legs: Any
    pm_ends: Any
    seeding_via: Any
    restart_via: Any
    wrap_clearer: Any
    guided_arcs: Any
    restart_arcs: Any
    penalty_weight: Any
    seeded: Any
    restart_after: Any
    migrate_every: Any


MODEL_FIELDS = ("leg_crossover", "leg_mutation", "end_mutation", "ends_of_best",
                "straight_of_best", "tight_of_best")
"""Settings that only a car model with genes of its own reads (:attr:`GASettings.model`):
under another model they do not change the program (:meth:`GASettings.structure`)."""
BUDGET_BASE = 9
"""Obstacles (the paper's scene) up to which ``generations_per_obstacle`` adds nothing."""
PRECISIONS = ("float32", "float64")


@dataclass(frozen=True)
class GASettings:
    """Settings of one GA configuration (all runs of a batch share them)."""

    population: int = 50
    generations: int = 50
    pc_upper: float = 0.4
    pm_upper: float = 0.02
    pc_lower: float = 0.4
    pm_lower: float = 0.02
    selection: str = "roulette"
    tournament_size: int = 2
    perm_crossover: str = "cx"
    perm_mutation: str = "inversion"
    label_crossover: str = "two_point"
    label_mutation: str = "redraw"
    elites: int = 0
    collision: str = "full"
    precision: str = "float32"
    label_binding: str = "position"
    penalty_weight: float = 1.0
    path_mutation: str = "none"
    pm_path: float = 0.0
    seeding: float = 0.0
    seeding_via: float = 0.0
    restart_via: float = 0.0
    restart_arcs: float = 0.0
    wrap_clearer: float = 0.0
    guided_arcs: float = 0.0
    restart_after: int = 0
    islands: int = 1
    migrate_every: int = 0
    generations_per_obstacle: int = 0
    reversing_budget: int = 1
    pairs_from: int = 0
    turns: str = car_model.DEFAULT
    leg_crossover: str = "two_point"
    leg_mutation: str = "redraw"
    pc_legs: float = 0.4
    pm_legs: float = 0.02
    end_mutation: str = "redraw"
    pm_ends: float = 0.5
    ends_of_best: int = 0
    straight_of_best: int = 0
    tight_of_best: int = 0

    @property
    def model(self) -> car_model.CarModel:
        """The car model the GA searches (``turns``): what it adds to a chromosome, its
        device arrays, its exact optimum (:mod:`hga_jax.model.car_model`)."""
        return car_model.get(self.turns)

    def for_car(self, car: str) -> "GASettings":
        """These settings searching the model of ``car`` (``turns`` as it is for the
        forward car; the Reeds–Shepp car's own model otherwise:
        :func:`hga_jax.model.car_model.resolve`)."""
        turns = car_model.resolve(self.turns, car)
        return self if turns == self.turns else dataclasses.replace(self, turns=turns)

    def _times(self) -> int:
        """The ``reversing_budget`` factor where the car model reverses, else 1."""
        return self.reversing_budget if self.model.reverses else 1

    def for_obstacles(self, n: int) -> GASettings:
        """The settings of a run on ``n`` obstacles: ``generations`` raised by
        ``generations_per_obstacle`` per obstacle beyond :data:`BUDGET_BASE` (and times
        ``reversing_budget`` for a car that reverses), then ``generations_per_obstacle``
        0 and, where it was applied, ``reversing_budget`` 1 (resolved; resolving again
        changes nothing). Resolve the car first (:meth:`for_car`): for the forward car the
        factor is kept, unapplied, so that settings resolved for the car later still
        apply it. ``path_mutation = "guided_pairs"`` on fewer than ``pairs_from``
        obstacles becomes ``"guided"`` (``pairs_from`` then 0)."""
        if self.path_mutation == "guided_pairs" and int(n) < self.pairs_from:
            return dataclasses.replace(self, path_mutation="guided", pairs_from=0).for_obstacles(n)
        m = self._times()
        if not self.generations_per_obstacle and m == 1:
            return self
        extra = self.generations_per_obstacle * max(0, int(n) - BUDGET_BASE)
        return dataclasses.replace(self, generations=m * (self.generations + extra),
                                   generations_per_obstacle=0,
                                   reversing_budget=1 if m != 1 else self.reversing_budget)

    def budget(self, n: int) -> dict[str, Any] | None:
        """How the generation count of a run on ``n`` obstacles was set (None: fixed)."""
        k, m = self.generations_per_obstacle, self._times()
        if not k and m == 1:
            return None
        rule = f"{self.generations} + {k} * max(0, n - {BUDGET_BASE})" if k else f"{self.generations}"
        if m != 1:
            rule = (f"{m} * ({rule})" if k else f"{m} * {rule}") + " (a car that reverses)"
        g = self.for_obstacles(n).generations
        return {"rule": f"generations = {rule}", "obstacles": int(n), "generations": g,
                "evaluations_per_run": self.population * (g + 1)}

    def rates(self, dtype: Any = np.float32) -> Rates:
        """The :data:`RATES` as arrays (``dtype``: the search's float type, of the penalty
        weight)."""
        f4 = np.float32
        return Rates(*(np.asarray(getattr(self, k), f4) for k in SHARES),
                     np.asarray(self.penalty_weight, dtype),
                     np.asarray(int(round(self.seeding * self.population)), np.int32),
                     np.asarray(self.restart_after, np.int32),
                     np.asarray(self.migrate_every, np.int32))

    def structure(self) -> "GASettings":
        """These settings without their :data:`RATES` (probabilities 0, weight 1;
        ``seeding`` and ``restart_after`` 1 where on, else 0), without their generation
        count and its rule (0, ``generations_per_obstacle`` 0, ``reversing_budget`` 1: a
        block of generations takes its last generation as data) and with the
        defaults of the :data:`MODEL_FIELDS` that their car model does not read: what a
        compiled program depends on, and its identity."""
        genes = self.model.genes
        used = {name for g in genes for name in (g.crossover, g.mutation, g.ends) if name}
        if any(g.ends for g in genes):
            used.add("ends_of_best")
        used.update(g.straight for g in genes if g.straight)
        used.update(g.tight for g in genes if g.tight)
        idle = {f.name: f.default for f in dataclasses.fields(self)
                if f.name in MODEL_FIELDS and f.name not in used}
        return dataclasses.replace(
            self, **{k: 0.0 for k in SHARES}, penalty_weight=1.0, generations=0,
            generations_per_obstacle=0, reversing_budget=1, pairs_from=0,
            seeding=float(self.seeding > 0),
            restart_after=int(self.restart_after > 0), migrate_every=int(self.migrate_every > 0),
            **idle)

    def with_rates(self, rates: Rates) -> "GASettings":
        """These settings (a structure) with the :data:`RATES` of ``rates`` (traced
        arrays inside a program: unchecked, unhashable, for reading only);
        :meth:`static` gives the structure back."""
        obj = object.__new__(GASettings)
        obj.__dict__.update(self.__dict__)
        obj.__dict__.update(rates._asdict())
        obj.__dict__["_static"] = self
        return obj

    def static(self) -> "GASettings":
        """The settings whose values are Python values: these, or the structure that
        :meth:`with_rates` was given."""
        return self.__dict__.get("_static", self)

    def seeded_count(self) -> Any:
        """How many individuals of a fresh population are seeded: ``round(seeding *
        population)``, a Python int, or inside the step the count of its rates (data)."""
        return self.__dict__.get("seeded", round(self.seeding * self.population))

    @property
    def seeds(self) -> bool:
        """Whether fresh populations are seeded (``seeding > 0``; structure)."""
        return self.static().seeding > 0

    @property
    def restarts(self) -> bool:
        """Whether stalled runs restart (``restart_after > 0``; structure)."""
        return self.static().restart_after > 0

    @property
    def island_count(self) -> int:
        """The islands the population is split into (structure): the largest count up to
        ``islands`` that splits it into equal islands of two or more individuals, more
        than ``elites`` each (``islands = 5``: population 50 five islands of ten, 12 four
        of three, 8 with 2 elites two of four, 7 one population)."""
        p = self.population
        for k in range(min(self.islands, p // 2), 1, -1):
            if p % k == 0 and p // k > max(self.elites, 1):
                return k
        return 1

    @property
    def migrates(self) -> bool:
        """Whether islands send migrants (more than one island and ``migrate_every >
        0``; structure)."""
        return self.island_count > 1 and self.static().migrate_every > 0

    @property
    def counts_wrap_sides(self) -> bool:
        """Whether ``wrap_clearer`` applies: the tight rope, whose legs are the tangents
        whose blockers it counts (a car model with genes of its own keeps random sides)."""
        return not self.model.genes

    @property
    def uses_legs(self) -> bool:
        """Whether the search reads the per-leg blockers (:mod:`hga_jax.model.legs`)."""
        return self.path_mutation != "none" or self.seeds

    def __post_init__(self) -> None:
        self.validate("<settings>")

    def validate(self, source: str, prefix: str = "ga",
                 origins: Mapping[str, str] | None = None) -> None:
        """Raise :class:`ConfigError` naming ``source`` and the key if a value is bad.

        ``origins`` (key -> ``"<source>: <key as written there>"``) names where each
        layered value came from; a conflict between two keys names both sources.
        """
        origins = origins or {}

        def where(key: str) -> str:
            return origins.get(key) or f"{source}: {_dotted(prefix, key)}"

        def bad(key: str, why: str) -> ConfigError:
            return ConfigError(f"{where(key)}: {why}")

        def pop() -> str:
            return f"population ({self.population}, from {origins.get('population', 'the default')})"

        for key in ("population", "generations", "tournament_size", "elites", "restart_after",
                    "islands", "migrate_every", "generations_per_obstacle", "reversing_budget",
                    "pairs_from", "ends_of_best", "straight_of_best", "tight_of_best"):
            v = getattr(self, key)
            if isinstance(v, bool) or not isinstance(v, int):
                raise bad(key, f"must be an integer, got {v!r}")
        if self.population < 2:
            raise bad("population", f"must be >= 2, got {self.population}")
        if self.generations < 0:
            raise bad("generations", f"must be >= 0, got {self.generations}")
        if not 1 <= self.tournament_size <= self.population:
            raise bad("tournament_size", f"must be in 1..{pop()}, got {self.tournament_size}")
        if self.islands < 1:
            raise bad("islands", f"must be >= 1 (1: one population), got {self.islands}")
        if not 0 <= self.elites < self.population:
            raise bad("elites", f"must be in 0..{pop()} - 1, got {self.elites}")
        if not 0 <= self.ends_of_best < self.population:
            raise bad("ends_of_best", f"must be in 0..{pop()} - 1, got {self.ends_of_best}")
        if not 0 <= self.straight_of_best < self.population - self.ends_of_best:
            raise bad("straight_of_best", f"must be in 0..{pop()} - ends_of_best "
                      f"({self.ends_of_best}) - 1, got {self.straight_of_best}")
        left = self.population - self.ends_of_best - self.straight_of_best
        if not 0 <= self.tight_of_best < left:
            raise bad("tight_of_best", f"must be in 0..{pop()} - ends_of_best "
                      f"({self.ends_of_best}) - straight_of_best ({self.straight_of_best}) - 1, "
                      f"got {self.tight_of_best}")
        if self.generations_per_obstacle < 0:
            raise bad("generations_per_obstacle", f"must be >= 0 (0: a fixed count), "
                      f"got {self.generations_per_obstacle}")
        if self.reversing_budget < 1:
            raise bad("reversing_budget", f"must be >= 1 (1: as the forward car), "
                      f"got {self.reversing_budget}")
        if self.pairs_from < 0:
            raise bad("pairs_from", f"must be >= 0 (0: on every scene), got {self.pairs_from}")
        if self.restart_after < 0:
            raise bad("restart_after", f"must be >= 0 (0: never), got {self.restart_after}")
        if self.migrate_every < 0:
            raise bad("migrate_every", f"must be >= 0 (0: never), got {self.migrate_every}")
        for key in (*SHARES, "seeding"):
            v = getattr(self, key)
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise bad(key, f"must be a number, got {v!r}")
            if not (math.isfinite(v) and 0.0 <= v <= 1.0):
                raise bad(key, f"must be a probability in [0, 1], got {v!r}")
        w = self.penalty_weight
        if isinstance(w, bool) or not isinstance(w, (int, float)) or not (
                math.isfinite(w) and w > 0):
            raise bad("penalty_weight", f"must be a finite number > 0, got {w!r}")
        from hga_jax.search import registry

        choices = [(kind, registry.names(kind)) for kind in registry.KINDS]
        for key, allowed in choices + [
            ("label_binding", LABEL_BINDINGS),
            ("collision", COLLISIONS),
            ("precision", PRECISIONS),
        ]:
            v = getattr(self, key)
            if v not in allowed:
                raise bad(key, f"must be one of {', '.join(allowed)}, got {v!r}")
        problem = car_model.problem(self.turns, self.collision)
        if problem:
            known = self.turns in car_model.names()  # then the collision test is the problem
            raise bad("turns", problem + (f" (from {origins.get('collision', 'the default')})"
                                          if known else ""))
        if not self.model.searched:
            raise bad("turns", f"the GA does not search the paths of {self.turns!r} yet; "
                      "its optimum is a yardstick (hga-jax exact, a study's yardstick)")

    @classmethod
    def from_mapping(
        cls, mapping: Mapping[str, Any], source: str, prefix: str = "ga",
        base: "GASettings | None" = None,
    ) -> "GASettings":
        """Settings from a TOML table (``[ga]``), on top of ``base`` (default: paper).

        Unknown keys and wrong types raise :class:`ConfigError` naming the key.
        """
        return cls.layered([(mapping, source, lambda k: _dotted(prefix, k))], base)

    @classmethod
    def layered(cls, layers: Sequence[tuple[Mapping[str, Any], str, Callable[[str], str]]],
                base: "GASettings | None" = None) -> "GASettings":
        """Settings from ``layers`` applied in order on top of ``base`` (default: paper).

        A layer is ``(mapping, source, name)``: its keys, the file (or "command line")
        they came from, and how a key is written there (``ga.population``,
        ``--population``). Each value is checked for its key and type in its layer;
        the result is validated once, so an error names the source of every value
        it involves.
        """
        values, origins = cls._merged(layers, base)
        obj = cls.__new__(cls)
        for k, v in values.items():
            object.__setattr__(obj, k, v)
        obj.validate(layers[-1][1] if layers else "<settings>", "ga", origins)
        return obj

    @classmethod
    def check_layer(cls, layer: tuple[Mapping[str, Any], str, Callable[[str], str]]) -> None:
        """Check one layer's keys and value types alone (a scenario's ``[ga]`` when the
        file is read); its values are checked against each other, and against the other
        layers, once all layers are merged (:meth:`layered`)."""
        cls._merged([layer], None)

    @classmethod
    def _merged(cls, layers, base) -> tuple[dict[str, Any], dict[str, str]]:
        """The values of ``layers`` over ``base``, each key and type checked, and where
        each value came from."""
        names = {f.name: f for f in dataclasses.fields(cls)}
        values = dataclasses.asdict(base or cls())
        origins: dict[str, str] = {}
        for mapping, source, name in layers:
            for key, v in mapping.items():
                if key not in names:
                    raise ConfigError(
                        f"{source}: {name(key)}: unknown key (known: {', '.join(names)})")
                default = values[key]
                if isinstance(default, float) and isinstance(v, int) and not isinstance(v, bool):
                    v = float(v)
                if type(v) is not type(default):
                    raise ConfigError(
                        f"{source}: {name(key)}: must be {type(default).__name__}, got {v!r}")
                values[key] = v
                origins[key] = f"{source}: {name(key)}"
        return values, origins

    def replace(self, source: str = "<settings>", **changes: Any) -> "GASettings":
        """A copy with ``changes`` applied (None values ignored), validated."""
        changes = {k: v for k, v in changes.items() if v is not None}
        return GASettings.from_mapping(changes, source, prefix="ga", base=self)


PAPER = GASettings()
"""The paper's HGA (section 4): the defaults of :class:`GASettings`."""

RECOMMENDED = GASettings(selection="tournament", tournament_size=2, elites=2,
                         path_mutation="guided_pairs", pm_path=1.0, seeding=1.0, seeding_via=0.75,
                         restart_via=1.0, restart_arcs=1.0, wrap_clearer=0.75, guided_arcs=1.0, restart_after=12,
                         islands=5, migrate_every=4, penalty_weight=10.0, generations_per_obstacle=24,
                         reversing_budget=3, pairs_from=10, ends_of_best=2,
                         straight_of_best=1, tight_of_best=1)
"""hga-jax's recommended HGA: the paper's operators and rates, plus generation 0 and
restarts seeded by wrapping blocking obstacles (three wraps in four round the side whose
new legs pass through fewer obstacles), one guided path move per child (the
best of ten candidate moves by their legs and arcs, beyond 9 obstacles each also with
one of the moved obstacle's neighbours turned the other way), tournament
selection within five islands of ten, 2 elites each, the best of each island to the
next every 4 generations, restarts of runs stalled for 12 generations (every seed of
a restart via a random obstacle where the run's best path collides, wrapping the
overlapping neighbours of its colliding arcs too), ten times the
paper's penalty per violation during the search, three times the generations for a car
that reverses, two children per generation that
move the best path's ends (the Reeds–Shepp car only), one that is the best path with straight legs (free turns and
the Reeds–Shepp car) and one more moved as the tight rope would move it, and a
budget that grows with the scene: the paper's 50 x 51 chromosomes up to 9 obstacles,
24 more generations per obstacle beyond (15 obstacles: 50 x 195 = 9,750; 25: 50 x 435
= 21,750; 40: 50 x 795 = 39,750)
(``configs/ga/recommended.toml``; measured in docs/results.md)."""

PRESETS: dict[str, GASettings] = {"recommended": RECOMMENDED, "paper": PAPER}
"""Named settings: ``hga-jax run --preset NAME`` (default ``recommended``)."""


def preset(name: str, source: str = "<preset>") -> GASettings:
    """The settings of preset ``name`` (:data:`PRESETS`); ConfigError if unknown."""
    if name not in PRESETS:
        raise ConfigError(f"{source}: preset: must be one of {', '.join(PRESETS)}, got {name!r}")
    return PRESETS[name]


def _dotted(prefix: str, key: str) -> str:
    return f"{prefix}.{key}" if prefix else key
