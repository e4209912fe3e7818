"""Car models: what a path may be, one object per model behind one seam.

A *car model* says which paths a car may drive among the obstacles: the paper's tight
rope (turns on the model circles only, :mod:`hga_jax.model.cars.tight_rope.model`) and free turns
(turns on circles of radius rho in free space too, :mod:`hga_jax.model.cars.free_turns.model`).
Everything that differs between models is a method or an attribute of its
:class:`CarModel`; the GA loop, the runner, the command line, studies, peers, plots and
reports ask the model of the settings (``GASettings.model``) or of a result, and never
test a model's name. A model:

- names itself (``name``, the value of ``turns`` in settings, files and flags) and
  says how messages name it (``words``, ``optimum_name``);
- checks the settings it runs under (:meth:`CarModel.problem`);
- builds the scenario's device arrays and tables for the search
  (:meth:`CarModel.search_arrays`);
- adds genes to a chromosome (``genes``: :class:`GeneModule`, each with the
  :mod:`hga_jax.search.registry` kinds of its operators and the settings of their rates);
- builds its tangent graph and solves its exact optimum (:meth:`CarModel.graph`,
  :meth:`CarModel.solve`), and says what its optimum adds to a result
  (:meth:`CarModel.extras`, :meth:`CarModel.notes`);
- marks its own kinds of segment (``segment_flags``: keys such as ``"free"`` set on the
  segments of the result files, :func:`segment_kind`).

A new model is one module with a subclass and one :func:`register` call
(docs/model.md, "Adding a car model"). Host code; nothing here imports JAX.
"""
from __future__ import annotations

import contextlib
import math
from dataclasses import dataclass
from typing import Any, Iterator

import numpy as np

DEFAULT = "tight-rope"
"""The paper's model: the default of ``turns`` everywhere."""
DUBINS = "dubins"
"""The car that drives forward only (the paper's robot): the default ``car``."""

_MODELS: dict[str, "CarModel"] = {}


@dataclass(frozen=True)
class GeneModule:
    """Genes a model adds to a chromosome: one per position (``n + 2``, as the labels,
    and bound to positions or obstacles as the labels are), values ``0 .. len(weights) - 1``.

    name: the field of the population and of results that holds them (``"legs"``).
    weights: how often fresh chromosomes (generation 0, restarts) take each value, in
    proportion (``(2, 1, 1)``: 0 half the time).
    crossover, mutation: the :class:`~hga_jax.search.settings.GASettings` fields (and
    :mod:`hga_jax.search.registry` kinds) naming their operators; pc, pm: the fields of
    their rates (per pair, per gene). words: how summaries name the genes.
    ends, pe: the fields of the move on the path's ends and of its rate per child (a
    reversing car's, :mod:`hga_jax.search.end_ops`; empty: none).
    straight: the field of how many children per generation are the parents' best with
    every gene 0 (free turns: every leg a tangent; empty: none).
    tight: the field of how many children per generation are such copies moved by the
    path move on the tangents' legs (``ScenarioArrays.tight_legs``; empty: none).
    """

    name: str
    weights: tuple[int, ...]
    crossover: str
    mutation: str
    pc: str
    pm: str
    words: str
    ends: str = ""
    pe: str = ""
    straight: str = ""
    tight: str = ""


class CarModel:
    """A car model (module doc). Subclasses set the attributes and implement the
    methods that raise :class:`NotImplementedError`."""

    name: str = ""
    car: str = DUBINS
    """The car the model is of: ``"dubins"`` (forward only) or ``"reeds-shepp"`` (also
    backward); a car's first registered model is the one ``car`` alone selects."""
    reverses: bool = False
    """Whether the car also drives backward (a Reeds–Shepp car)."""
    searched: bool = True
    """Whether the GA searches this model's paths (else it is a yardstick only)."""
    describe: str = ""
    """One phrase for help texts: what paths the model holds."""
    words: str = ""
    """How a verdict names the model after its collision test (``"collision full,
    free turns"``); empty for the paper's."""
    optimum_name: str = "optimum"
    """How summaries name the model's optimum."""
    adjective: str = ""
    """The model as an adjective: \"the tight-rope optimum\"."""
    genes: tuple[GeneModule, ...] = ()
    segment_flags: dict[str, str] = {}
    """Keys this model sets on its own kinds of segment in the result files, each with
    the words a legend gives them, ``{type}`` standing for the segment's type
    (``{"free": "free turn (radius rho)"}``)."""
    includes: tuple[str, ...] = ()
    """Models every one of whose paths this model holds too (a cheaper graph to try first)."""
    yardstick_note: str = ""
    """What a study's summary says when gaps are taken to this model's optimum."""

    def problem(self, collision: str) -> str | None:
        """What is wrong with this model under the collision test ``collision``
        (None: nothing)."""
        return None

    def connect(self, p: Any, q: Any, rho: float) -> list[dict[str, Any]]:
        """The car's shortest path from pose ``p`` to pose ``q`` with no obstacles, as
        result-file segments (the forward car's: Dubins, :mod:`hga_jax.model.dubins`)."""
        from .dubins import shortest

        return shortest(tuple(p), tuple(q), rho)

    def search_arrays(self, scenario: Any, dtype: Any, collision: str,
                      with_legs: bool = False) -> Any:
        """The scenario's :class:`~hga_jax.model.scenario.ScenarioArrays` for the search
        in ``dtype``: with the tables of this model's fitness and, with ``with_legs``,
        the legs the path operators read."""
        raise NotImplementedError

    def decode_arrays(self, scenario: Any) -> Any:
        """The scenario's float64 arrays that decode this model's chromosomes (the
        tables its genes read; no turn table)."""
        return scenario.arrays(np.float64)

    def graph(self, scenario: Any, collision: str) -> Any:
        """The model's tangent graph of every feasible piece
        (:class:`~hga_jax.model.graph_search.Graph`)."""
        raise NotImplementedError

    def solve(self, scenario: Any, collision: str) -> Any:
        """The model's exact optimum (:class:`~hga_jax.model.exact.ExactResult`)."""
        raise NotImplementedError

    def extras(self, optimum: Any) -> dict[str, Any]:
        """Keys this model adds to an optimum's dict in the result files."""
        return {}

    def summary(self, optimum: Any) -> dict[str, Any]:
        """Keys this model adds to a result's summary beside its optimum."""
        return {}

    def head(self, optimum: Any) -> str:
        """What follows the optimum's length and touches in ``exact``'s first line."""
        return ""

    def notes(self, optimum: Any, searched: "CarModel | None" = None) -> list[str]:
        """Lines a summary adds about a feasible optimum of this model: what no
        chromosome expresses, how it compares with another model's; ``searched``: the
        model the GA searched (None: ``exact``, which also prints the chromosome)."""
        return []


def segment_flags() -> tuple[str, ...]:
    """Every segment flag of the registered models, in the order they registered (a
    plot gives each its own style by its place here)."""
    _builtins()
    return tuple(dict.fromkeys(f for m in _MODELS.values() for f in m.segment_flags))


def segment_kind(segment: dict[str, Any]) -> tuple[str, str | None]:
    """``(kind, legend words)`` of a result file's segment: ``("line", None)``, ``("arc",
    None)``, or a kind marked by the ``segment_flags`` of the models, with their words
    (``{type}`` stands for the segment's type): ``("free arc", "free turn (radius
    rho)")``, ``("reverse line", "path line, driven backward")``."""
    _builtins()
    flags = dict.fromkeys((flag, words) for model in _MODELS.values()
                          for flag, words in model.segment_flags.items() if segment.get(flag))
    if not flags:
        return segment["type"], None
    words = "; ".join(w.format(type=segment["type"]) for _, w in flags)
    return " ".join(f for f, _ in flags) + " " + segment["type"], words


def finite(value: float | None) -> float | None:
    """``value`` where it is a finite length (m), else None (what the result files write
    for an optimum that does not exist)."""
    return value if value is not None and math.isfinite(value) else None


def register(model: CarModel) -> CarModel:
    """Make ``model`` known by its name (one name, one model); returns it. A model of a
    class of the same name as the registered one replaces it (a notebook cell or a
    plugin run again), unless that one is built in."""
    if not model.name:
        raise ValueError("a car model needs a name")
    _builtins()  # the paper's model first, whoever registers first
    old = _MODELS.get(model.name, model)
    if old is not model and (built_in(old) or type(old).__qualname__ != type(model).__qualname__):
        raise ValueError(f"a car model named {model.name!r} is already registered")
    _MODELS[model.name] = model
    return model


def built_in(model: CarModel) -> bool:
    """Whether ``model`` is one of hga-jax's own (its programs may be kept on disk)."""
    return type(model).__module__.startswith(__package__ + ".")


@contextlib.contextmanager
def isolated() -> Iterator[None]:
    """Registrations made inside the block are removed on leaving it (tests)."""
    _builtins()
    saved = dict(_MODELS)
    try:
        yield
    finally:
        _MODELS.clear()
        _MODELS.update(saved)


def _builtins() -> None:
    """Register the built-in models (the paper's first), once."""
    if _loaded:
        return
    _loaded.append(True)
    import importlib

    for car in ("tight_rope", "free_turns", "reeds_shepp"):  # each model module registers
        importlib.import_module(f"{__package__}.cars.{car}.model")


_loaded: list[bool] = []


def names() -> tuple[str, ...]:
    """The registered models' names, the paper's first: the allowed values of ``turns``."""
    _builtins()
    return tuple(_MODELS)


def cars() -> tuple[str, ...]:
    """The cars of the registered models, the forward car first."""
    _builtins()
    return tuple(dict.fromkeys(m.car for m in _MODELS.values()))


def with_genes(car: str) -> CarModel:
    """The first model of ``car`` that adds genes to a chromosome: the one whose tables
    decode a chromosome of that car carrying leg genes (``ValueError`` if none does)."""
    _builtins()
    found = [m for m in _MODELS.values() if m.car == car and m.genes]
    if not found:
        raise ValueError(f"no car model of {car!r} adds genes to a chromosome")
    return found[0]


def of_car(car: str) -> CarModel:
    """The first model of ``car`` (the car's own, without free turns for the forward
    car); ``ValueError`` for an unknown car."""
    return get(resolve(DEFAULT, car))


def resolve(turns: str, car: str = DUBINS) -> str:
    """The name of the model of ``car`` with ``turns``: ``turns`` itself for the forward
    car (the default, which any model's name overrides) or when it is a model of that
    car, else the car's first model (a Reeds–Shepp car's model includes free turns,
    whatever ``turns`` says). ``ValueError`` for an unknown car."""
    _builtins()
    if car not in cars():
        raise ValueError(f"must be one of {', '.join(cars())}, got {car!r}")
    if car == DUBINS or (turns in _MODELS and _MODELS[turns].car == car):
        return turns
    return next(m.name for m in _MODELS.values() if m.car == car)


def help_text() -> str:
    """The registered models, each with its phrase: for ``--turns``' help."""
    _builtins()
    return "; ".join(f"{m.name} ({m.describe})" for m in _MODELS.values())


def get(name: str) -> CarModel:
    """The model named ``name``; ``ValueError`` naming the allowed values if none is."""
    _builtins()
    if name not in _MODELS:
        raise ValueError(f"must be one of {', '.join(_MODELS)}, got {name!r}")
    return _MODELS[name]


def problem(name: Any, collision: str) -> str | None:
    """What is wrong with the model ``name`` under ``collision`` (None: nothing): the
    one rule for settings, the exact solver, runs and studies."""
    _builtins()
    if not isinstance(name, str) or name not in _MODELS:
        return f"must be one of {', '.join(_MODELS)}, got {name!r}"
    return _MODELS[name].problem(collision)
