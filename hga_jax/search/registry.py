"""The operator registry: one table per kind of operator, the only source of names.

Kinds (:data:`KINDS`); each is also the :class:`~hga_jax.search.settings.GASettings`
field that picks it. Every operator works on ONE individual or ONE pair (the GA
vmaps it over the population and the runs), takes a typed key of
:mod:`hga_jax.search.rng` (usable with ``jax.random.*``), is pure, and has shapes
that depend on ``n`` (obstacles) and ``P`` (population) only:

- ``selection``: ``fn(key, fitness) -> indices``; ``fitness`` (P,) float, higher is
  better (always positive); ``indices`` (P,) int32 in ``0..P-1``, the parents in
  mating order. Settings fields the entry declares (``settings=("tournament_size",)``)
  are passed as keywords.
- ``perm_crossover``: ``fn(key, a, b) -> (child_a, child_b)``; int32 permutations
  (n,) of ``0..n-1`` in and out.
- ``perm_mutation``: ``fn(key, perm) -> perm``.
- ``label_crossover``: ``fn(key, a, b) -> (a, b)``; labels (n + 2,) int32 in
  ``{-1, 0, +1}``, the start and goal genes (first, last) never 0.
- ``label_mutation``: ``fn(key, labels, rate) -> labels``; ``rate`` is
  ``settings.pm_lower`` (the built-in ``"redraw"`` redraws each gene with that
  probability).
- ``path_mutation``: ``fn(key, perm, labels, legs) -> (perm, labels)``, positional
  labels, ``legs`` the scenario's :class:`~hga_jax.model.legs.Legs`
  (:mod:`hga_jax.search.path_ops`); the name ``"none"`` (no move) comes first.
- ``leg_crossover``: ``fn(key, a, b) -> (a, b)``; leg genes (n + 2,) int32 in
  ``{0, 1, 2}`` (free turns only: :mod:`hga_jax.search.leg_ops`).
- ``leg_mutation``: ``fn(key, legs, rate) -> legs``; ``rate`` is ``settings.pm_legs``.
- ``end_mutation``: ``fn(key, labels, legs, values) -> (labels, legs)``, positional;
  a reversing car's move on the ends of its path (:mod:`hga_jax.search.end_ops`),
  applied with probability ``settings.pm_ends`` per child; ``values``: how many
  values a leg gene takes. The name ``"none"`` (no move) comes first.

How often an operator applies is the GA's business (``pc_*``, ``pm_upper``,
``pm_path``: one do-word per pair or individual), not the operator's.

The random stream: generation ``g`` of a run draws one block of uint32 words
(``hga_jax.search.ga.draw_rows``); each operator reads its own rows of it. The
built-in selections, label mutation and guided path move read words directly
(``from_words``, their rows given by ``rows(n, settings)``), so the stream of every
built-in setting is the one it always was (the guided move's since hga-jax 0.5: its
26 words, the ten candidates' own). Every other operator gets its keys from two rows of words
(one key per pair or individual; selection one key per run, from the rows' first
column). Crossovers, permutation mutations and the other path moves, built in or
registered, all read one do-word row and two key rows, so a registered one in their
place reads the very words the built-in would (with ``pc_upper = 0`` it is the
built-in's run). A registered selection, label mutation or path move reads two key
rows in place of the built-in's own (1 or ``tournament_size``; ``n + 2``; 26): the
block's size, and with it every word of the block (threefry's original layout), may
change. Settings that name no registered operator draw exactly the words they always did.

Registered names are identifiers, fixed while in use: compiled programs are cached
by settings, so a name must keep meaning the same function (:func:`unregister`
exists for tests; :func:`isolated` undoes registrations on leaving).
"""
from __future__ import annotations

import contextlib
from dataclasses import dataclass, field
from typing import Any, Callable, Iterator

KINDS = ("selection", "perm_crossover", "perm_mutation", "label_crossover", "label_mutation",
         "path_mutation", "leg_crossover", "leg_mutation", "end_mutation")
OPTIONS = ("settings",)  # what register() accepts as keyword options


@dataclass(frozen=True)
class Operator:
    """One registry entry.

    ``fn``: the operator, with its kind's signature (module doc). ``settings``:
    GASettings fields passed to ``fn`` (and ``from_words``) as keywords.
    ``from_words``: a built-in's word-reading form, for a whole population:
    selection ``from_words(words, fitness)``, label mutation
    ``from_words(words, labels, rate)``, path move ``from_words(words, perm, labels,
    legs)``, ``words`` the ``rows(n, settings)`` rows of the generation's draw,
    transposed to (P, rows).
    """

    kind: str
    name: str
    fn: Callable
    builtin: bool = False
    settings: tuple[str, ...] = ()
    from_words: Callable | None = None
    rows: Callable[[int, Any], int] | None = None
    doc: str = field(default="", compare=False)

    def options(self, settings) -> dict[str, Any]:
        """The keyword options this entry takes, read from ``settings``."""
        return {k: getattr(settings, k) for k in self.settings}


_TABLE: dict[str, dict[str, Operator]] = {}


def _kind(kind: str) -> dict[str, Operator]:
    if kind not in KINDS:
        raise ValueError(f"operator kind must be one of {', '.join(KINDS)}, got {kind!r}")
    if not _TABLE:
        _load_builtins()
    return _TABLE[kind]


def names(kind: str) -> tuple[str, ...]:
    """The names settings accept for ``kind``: built-ins first, then registered ones in
    order of registration (``path_mutation`` starts with ``"none"``). Reading names
    imports no operator (so no JAX) until an operator is asked for or registered."""
    if not _TABLE:
        if kind not in KINDS:
            raise ValueError(f"operator kind must be one of {', '.join(KINDS)}, got {kind!r}")
        return tuple(name for k, name, *_ in BUILTINS if k == kind)
    return tuple(_kind(kind))


def builtin_only(settings: Any) -> bool:
    """Whether every operator ``settings`` (a GASettings) names is built in: its
    programs then depend on hga_jax's code alone (:mod:`hga_jax.compiled` stores
    those on disk), when its car model is built in too."""
    from hga_jax.model import car_model

    builtin = {(k, name) for k, name, *_ in BUILTINS}
    return (car_model.built_in(settings.model)
            and all((kind, getattr(settings, kind)) in builtin for kind in KINDS))


def entry(kind: str, name: str) -> Operator:
    """The :class:`Operator` of ``name``; ValueError listing the known names if unknown."""
    table = _kind(kind)
    if name not in table:
        raise ValueError(f"unknown {kind} {name!r} (known: {', '.join(table)})")
    return table[name]


def get(kind: str, name: str) -> Callable:
    """The operator ``name`` of ``kind`` (signature in the module doc)."""
    return entry(kind, name).fn


def register(kind: str, name: str, fn: Callable | None = None, **options):
    """Make ``fn`` usable as ``GASettings(<kind>=name)``; returns ``fn``.

    A direct call ``register(kind, name, fn)`` or a decorator
    ``@register(kind, name)``. ``name`` must be an identifier not yet taken (by a
    built-in or another registration). Options: ``settings=("field", ...)``,
    GASettings fields passed to ``fn`` as keywords (selection only, where the
    signature allows extra settings).
    """
    table = _kind(kind)
    unknown = set(options) - set(OPTIONS)
    if unknown:
        raise TypeError(f"register: unknown options {sorted(unknown)} (known: {', '.join(OPTIONS)})")
    if fn is None:
        return lambda f: register(kind, name, f, **options)
    if not (isinstance(name, str) and name.isidentifier()):
        raise ValueError(f"operator name must be an identifier, got {name!r}")
    if not callable(fn):
        raise TypeError(f"operator {name!r} must be callable, got {fn!r}")
    old = table.get(name)
    if old is not None:
        if old.builtin:
            raise ValueError(f"{kind} {name!r} is built in (already registered)")
        if old.fn is not fn:
            raise ValueError(f"{kind} {name!r} is already registered")
        return fn
    extra = tuple(options.get("settings", ()))
    if extra and kind != "selection":
        raise TypeError(f"register: settings options are for selections, not {kind}")
    table[name] = Operator(kind, name, fn, settings=extra, doc=fn.__doc__ or "")
    return fn


def unregister(kind: str, name: str) -> None:
    """Remove a registered (not built-in) operator."""
    table = _kind(kind)
    if name in table and table[name].builtin:
        raise ValueError(f"{kind} {name!r} is built in and cannot be removed")
    table.pop(name, None)


@contextlib.contextmanager
def isolated() -> Iterator[None]:
    """Registrations made inside the block are removed on leaving it (tests)."""
    saved = {kind: dict(_kind(kind)) for kind in KINDS}
    try:
        yield
    finally:
        for kind, table in saved.items():
            _TABLE[kind].clear()
            _TABLE[kind].update(table)


BUILTINS = (
    # (kind, name, module of hga_jax.search, function, from_words function, rows(n, s))
    ("selection", "roulette", "selection", "roulette_pick", "roulette_from_words",
     lambda n, s: 1),
    ("selection", "tournament", "selection", "tournament_pick", "tournament_from_words",
     lambda n, s: s.tournament_size),
    ("perm_crossover", "cx", "perm_crossover", "cx", None, None),
    ("perm_crossover", "pmx", "perm_crossover", "pmx", None, None),
    ("perm_crossover", "ox1", "perm_crossover", "ox1", None, None),
    ("perm_mutation", "inversion", "perm_mutation", "inversion", None, None),
    ("perm_mutation", "exchange", "perm_mutation", "exchange", None, None),
    ("label_crossover", "two_point", "label_ops", "two_point", None, None),
    ("label_mutation", "redraw", "label_ops", "redraw", "redraw_from_words",
     lambda n, s: n + 2),
    ("path_mutation", "none", "path_ops", "keep", None, None),
    *(("path_mutation", name, "path_ops", name, None, None)
      for name in ("flip", "drop", "insert", "shift", "repair", "mixed")),
    ("path_mutation", "guided", "guided", "guided", "guided_from_words",
     lambda n, s: _module("guided").WORDS),
    ("path_mutation", "guided_pairs", "guided_pairs", "guided_pairs", "guided_pairs_from_words",
     lambda n, s: _module("guided_pairs").WORDS),
    ("leg_crossover", "two_point", "leg_ops", "two_point", None, None),
    ("leg_mutation", "redraw", "leg_ops", "redraw", "redraw_from_words", lambda n, s: n + 2),
    ("end_mutation", "none", "end_ops", "keep", None, None),
    ("end_mutation", "redraw", "end_ops", "redraw", "redraw_from_words", lambda n, s: 2),
)
"""The built-in operators, in the order :func:`names` lists them; their modules (and
JAX) are imported on first use of an operator, not to read their names."""
_SETTINGS = {("selection", "tournament"): ("tournament_size",)}


def _module(name: str):
    """The built-in operators' module ``hga_jax.search.<name>``."""
    import importlib

    return importlib.import_module(f"hga_jax.search.{name}")


def _load_builtins() -> None:
    table: dict[str, dict[str, Operator]] = {kind: {} for kind in KINDS}
    for kind, name, module, attr, words, rows in BUILTINS:
        mod = _module(module)
        fn = getattr(mod, attr)
        extra = {} if words is None else {"from_words": getattr(mod, words), "rows": rows}
        table[kind][name] = Operator(kind, name, fn, builtin=True, doc=fn.__doc__ or "",
                                     settings=_SETTINGS.get((kind, name), ()), **extra)
    _TABLE.update(table)
