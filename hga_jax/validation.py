"""One validation layer for what a user hands in: run ranges, lists, plugins, layered settings.

The command line (:mod:`hga_jax.host.cli`), the scenario loader
(:mod:`hga_jax.host.config`), the study loader (:mod:`hga_jax.study.config`) and
:func:`hga_jax.running.runner.run_many` all check their input here, so each rule
is written once. A problem raises :class:`~hga_jax.errors.ConfigError` with one
line ``"<source>: <key>: <problem>"``, where ``source`` is a file, ``"command
line"`` or a function's name and ``key`` is the key as written there
(``seed``, ``--first-run``, ``families[1].scenes``).

Run ranges (integers; ``high`` bounds are exclusive in the code, inclusive in the
messages): a seed is ``0..2**32 - 1`` (run ``k`` of seed ``s`` is keyed by
``(s, k)``), ``runs`` and ``chunk`` are ``1..2**31 - 1`` and run indices are
int32, so ``first_run + runs <= 2**31``.

GA settings' own fields are checked by
:meth:`hga_jax.search.settings.GASettings.layered`; this module names the layers
(``ga.population`` in a scenario file, ``population`` in a ``--ga`` file,
``--population`` on the command line) and loads the plugins whose operators those
settings may name, before the settings are validated.
"""
from __future__ import annotations

import hashlib
import importlib
import importlib.util
import os
import sys
from typing import Any, Callable, Mapping, Sequence

import numpy as np

from hga_jax.errors import ConfigError
from hga_jax.search.settings import GASettings

SEED = (0, 2**32)
"""Seeds: ``0..2**32 - 1`` (the range of the random streams' first key word)."""
RUNS = (1, 2**31)
"""Runs of one job: ``1..2**31 - 1``."""
CHUNK = (1, 2**31)
"""Runs per compiled batch: ``1..2**31 - 1``."""
RUN_END = 2**31
"""Run indices are int32: ``first_run + runs <= RUN_END``."""

Layer = tuple[Mapping[str, Any], str, Callable[[str], str]]
"""A layer of settings: ``(mapping, source, name)``, where ``name(key)`` is how a key
is written in ``source`` (see :meth:`GASettings.layered`)."""


def error(source: str, key: str, problem: str) -> ConfigError:
    """A :class:`ConfigError` with the one-line message ``source: key: problem``."""
    return ConfigError(" ".join(f"{source}: {key}: {problem}".splitlines()))


def integer(value: Any, source: str, key: str, low: int, high: int = 2**31, *,
            grouped: bool = False) -> int:
    """``value`` if it is an integer in ``low..high - 1``, else a ConfigError.

    ``grouped``: the command line's wording for a value argparse has already made an
    integer, digits grouped (``--chunk: must be in 1..2,147,483,647, got 0``); otherwise
    the type is checked too (``seed: must be an integer in 0..4294967295, got -1``;
    numpy integers count, booleans do not).
    """
    if grouped:
        if not low <= value < high:
            raise error(source, key, f"must be in {low:,}..{high - 1:,}, got {value:,}")
        return value
    if (isinstance(value, bool) or not isinstance(value, (int, np.integer))
            or not low <= value < high):
        raise error(source, key, f"must be an integer in {low}..{high - 1}, got {value!r}")
    return int(value)


def at_least(value: int, source: str, key: str, low: int) -> int:
    """``value`` if it is ``>= low`` (an integer already), else a ConfigError."""
    if value < low:
        raise error(source, key, f"must be >= {low}, got {value}")
    return value


def run_range(seed: Any, runs: Any, first_run: Any, chunk: Any, source: str,
              name: Callable[[str], str] = lambda k: k, *, grouped: bool = False) -> None:
    """Check a job's runs ``first_run .. first_run + runs - 1`` of ``seed`` in batches of
    ``chunk`` (None: sized later) against the run ranges; ``name(key)`` is how each
    argument is written in ``source`` (``"--first-run"``)."""
    integer(seed, source, name("seed"), *SEED, grouped=grouped)
    integer(runs, source, name("runs"), *RUNS, grouped=grouped)
    integer(first_run, source, name("first_run"), 0, RUN_END - runs, grouped=grouped)
    integer(1 if chunk is None else chunk, source, name("chunk"), *CHUNK, grouped=grouped)


def turns(value: Any, collision: str, source: str, key: str = "turns") -> str:
    """``value`` if it names a car model that runs under ``collision``
    (:func:`hga_jax.model.car_model.problem`), else a ConfigError."""
    from hga_jax.model import car_model

    problem = car_model.problem(value, collision)
    if problem:
        raise error(source, key, problem)
    return value


def read_toml(path: Any) -> dict[str, Any]:
    """The table of the TOML file ``path``; a ConfigError naming the file if it cannot be
    read (``file: cannot read``), is not UTF-8 text or has a syntax error (``toml``):
    the one reader of every file a user hands in (scenarios, ``--ga`` files, studies)."""
    import tomllib

    source = str(path)
    try:
        with open(path, "rb") as fh:
            text = fh.read().decode("utf-8")
    except OSError as e:
        raise error(source, "file", f"cannot read: {e.strerror or e}") from None
    except UnicodeDecodeError as e:
        raise error(source, "file", f"not UTF-8 text: {e.reason} at byte {e.start}") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        raise error(source, "toml", f"syntax error: {e}") from None


def car(scenario: Any, settings: GASettings, car_from: str | None = None,
        collision_from: str | None = None) -> None:
    """A ConfigError naming where the car came from when the GA of ``settings`` cannot
    search that car's paths: its model is not one the GA searches, or not under the
    settings' collision test. ``car_from``: ``"<source>: <key>"`` of the car (default: the
    scenario's ``robot.car``; ``"command line: --car"`` where ``--car`` set it);
    ``collision_from``: that of the collision test (default: "the settings")."""
    from hga_jax.model import car_model

    where = car_from or f"{scenario.source}: robot.car"
    name = car_model.resolve(settings.turns, scenario.car)
    if not car_model.get(name).searched:
        raise ConfigError(f"{where}: {scenario.car}: the GA does not search its paths yet; "
                          "its optimum is a yardstick (hga-jax exact, a study's yardstick)")
    problem = car_model.problem(name, settings.collision)
    if problem:
        said = f"collision from {collision_from}" if collision_from else "the settings' collision"
        raise ConfigError(f"{where}: {scenario.car}: {problem} ({said})")


def strings(value: Any, source: str, key: str) -> list[str]:
    """``value`` if it is a list of non-empty strings (a TOML array), else a ConfigError."""
    if not isinstance(value, list) or not all(isinstance(s, str) and s for s in value):
        raise error(source, key, f"must be a list of non-empty strings, got {value!r}")
    return value


def flag(key: str) -> str:
    """How setting ``key`` is written on the command line: ``--tournament-size``."""
    return "--" + key.replace("_", "-")


def file_layer(mapping: Mapping[str, Any], source: str, prefix: str = "") -> Layer:
    """The settings of a TOML table: keys written ``prefix.key`` (``ga.population``),
    or bare at the top of a ``--ga`` file (``prefix=""``)."""
    return (mapping, source, (lambda k: f"{prefix}.{k}") if prefix else (lambda k: k))


def flag_layer(flags: Mapping[str, Any]) -> Layer:
    """The settings given as command-line flags (None: the flag was not given)."""
    return ({k: v for k, v in flags.items() if v is not None}, "command line", flag)


def settings(layers: Sequence[Layer], base: GASettings | None = None) -> GASettings:
    """The settings of ``layers`` applied in order over ``base`` (default: the paper's),
    validated once by :meth:`GASettings.layered` (an error names each value's source).
    Operators named there must be registered first: see :func:`load_plugins`."""
    return GASettings.layered(list(layers), base)


def _module_name(path: str) -> str:
    """The ``sys.modules`` name of a plugin file: one per absolute path."""
    return "hga_jax_plugin_" + hashlib.sha1(os.path.abspath(path).encode()).hexdigest()[:12]


def is_file(plugin: str) -> bool:
    """Whether a plugin is named by a file path (``my_ops.py``, ``lib/ops``) rather than
    an importable module name (``my_package.ops``)."""
    return plugin.endswith(".py") or os.sep in plugin or "/" in plugin


def load_plugin(plugin: str, source: str = "load_plugin", key: str = "plugin") -> None:
    """Import one plugin: a ``.py`` file (by path) or a module name (on ``sys.path``).

    A plugin registers operators at import with :func:`hga_jax.search.registry.register`.
    It is imported once per process, like any module (a second load does nothing). A
    plugin that cannot be imported raises one line ``"<source>: <key>: cannot import
    <plugin>: <error type>: <error>"``.
    """
    def fail(why: str) -> ConfigError:
        return error(source, key, f"cannot import {plugin}: {why}")

    if not is_file(plugin):
        try:
            importlib.import_module(plugin)
        except Exception as e:  # the user's code: report it on one line
            raise fail(f"{type(e).__name__}: {e}") from None
        return
    name = _module_name(plugin)
    if name in sys.modules:
        return
    if not os.path.isfile(plugin):
        raise fail("no such file")
    try:
        spec = importlib.util.spec_from_file_location(name, plugin)
        if spec is None or spec.loader is None:
            raise ImportError("not a Python file")
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    except Exception as e:  # the user's code: report it on one line
        sys.modules.pop(name, None)
        raise fail(f"{type(e).__name__}: {e}") from None


def load_plugins(plugins: Sequence[str], source: str, key: str | Callable[[int], str]
                 ) -> list[str]:
    """Import every plugin in order (:func:`load_plugin`); ``key`` names the option
    (``"--plugin"``) or, given a function of the position, the list's items
    (``plugins[1]``: counted from 1). Returns the plugins, as given."""
    for i, plugin in enumerate(plugins):
        load_plugin(plugin, source, key(i) if callable(key) else key)
    return list(plugins)
