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

How often an operator applies is the GA's business (``pc_*``, ``pm_upper``,
``pm_path``: one do-word per pair or individual), not the operator's.

The random stream: generation ``g`` of a run draws one block of uint32 words
(``hga_jax.search.ga.draw_rows``); each operator reads its own rows of it. The
built-in selections and label mutation read words directly (``from_words``, their
rows given by ``rows(n, settings)``), so the stream of every built-in setting is
the one it always was. Every other operator gets its keys from two rows of words
(one key per pair or individual; selection one key per run, from the rows' first
column). Crossovers, permutation mutations and path moves, built in or registered,
all read one do-word row and two key rows, so a registered one in their place reads
the very words the built-in would (with ``pc_upper = 0`` it is the built-in's run).
A registered selection or label mutation reads two key rows in place of the
built-in's own (1 or ``tournament_size``; ``n + 2``): the block's size, and with it
every word of the block (threefry's original layout), may change. Settings that name
no registered operator draw exactly the words they always did.

Registered names are identifiers, fixed while in use: compiled programs are cached
by settings, so a name must keep meaning the same function (:func:`unregister`
exists for tests; :func:`isolated` undoes registrations on leaving).
"""
from __future__ import annotations

import contextlib
from dataclasses import dataclass, field
from typing import Any, Callable, Iterator

KINDS = ("selection", "perm_crossover", "perm_mutation", "label_crossover", "label_mutation",
         "path_mutation", "leg_crossover", "leg_mutation")
OPTIONS = ("settings",)  # what register() accepts as keyword options


@dataclass(frozen=True)
class Operator:
    """One registry entry.

    ``fn``: the operator, with its kind's signature (module doc). ``settings``:
    GASettings fields passed to ``fn`` (and ``from_words``) as keywords.
    ``from_words``: a built-in's word-reading form, for a whole population:
    selection ``from_words(words, fitness)``, label mutation
    ``from_words(words, labels, rate)``, ``words`` the ``rows(n, settings)`` rows of
    the generation's draw, transposed to (P, rows).
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
    order of registration (``path_mutation`` starts with ``"none"``)."""
    return tuple(_kind(kind))


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


def _load_builtins() -> None:
    from hga_jax.search import guided, label_ops, leg_ops, path_ops, perm_crossover
    from hga_jax.search import perm_mutation
    from hga_jax.search import selection

    def add(kind, name, fn, **kw):
        _TABLE[kind][name] = Operator(kind, name, fn, builtin=True, doc=fn.__doc__ or "", **kw)

    for kind in KINDS:
        _TABLE[kind] = {}
    add("selection", "roulette", selection.roulette_pick,
        from_words=selection.roulette_from_words, rows=lambda n, s: 1)
    add("selection", "tournament", selection.tournament_pick, settings=("tournament_size",),
        from_words=selection.tournament_from_words, rows=lambda n, s: s.tournament_size)
    for name in ("cx", "pmx", "ox1"):
        add("perm_crossover", name, getattr(perm_crossover, name))
    for name in ("inversion", "exchange"):
        add("perm_mutation", name, getattr(perm_mutation, name))
    add("label_crossover", "two_point", label_ops.two_point)
    add("label_mutation", "redraw", label_ops.redraw,
        from_words=label_ops.redraw_from_words, rows=lambda n, s: n + 2)
    add("path_mutation", "none", path_ops.keep)
    for name in ("flip", "drop", "insert", "shift", "repair", "mixed"):
        add("path_mutation", name, getattr(path_ops, name))
    add("path_mutation", "guided", guided.guided)
    add("leg_crossover", "two_point", leg_ops.two_point)
    add("leg_mutation", "redraw", leg_ops.redraw,
        from_words=leg_ops.redraw_from_words, rows=lambda n, s: n + 2)
