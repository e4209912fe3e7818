"""hga-jax: shortest paths of a car-like robot (forward only, or also backward) among
circular obstacles, standing or moving, with a hierarchical GA.

Notebook use::

    import hga_jax as hg
    hg.use_cpu_cores()  # first: one JAX device per CPU core, for many runs per call
    sc = hg.load_scenario("configs/scenarios/robocup_paper.toml")
    res = hg.run_many(sc, "recommended", runs=100, seed=1)  # or "paper", or a GASettings
    print(hg.run_summary(res))
    hg.plot_path(sc, res.best.segments, touched=res.best.touched)
    poses = res.best.poses(0.05)  # s, x, y, heading, curvature, gear, t every 5 cm
    hg.write_run(res, "results/notebook", plot=True, force=True)  # replaces an earlier result

``use_cpu_cores()`` spreads each batch of runs over the cores (the same results): worth
it with many runs per call (hundreds), a cost with one plan per call (``runs=1``, a
robot's loop), which it slows down; leave it out there (measured: docs/python.md).
``run_many`` without settings runs the recommended preset, as ``hga-jax run`` does.
Compiled programs are kept on disk (``~/.cache/hga-jax/programs``) unless
``hg.enable_compilation_cache(False)`` or ``HGA_JAX_CACHE_DIR=off``. All of it:
docs/python.md. The model and the result files are defined in docs/model.md.
"""
__version__ = "0.11.0"

import importlib
from typing import Any

_EXPORTS = {  # name -> module it lives in; imported on first use, so that importing
    # hga_jax (and the command line's help and checks) does not import JAX
    "distributed": "hga_jax.running.distributed",  # one job over several processes
    "load_scenario": "hga_jax.host.config", "scenario_from_dict": "hga_jax.host.config",
    "use_cpu_cores": "hga_jax.running.devices",
    "ConfigError": "hga_jax.errors", "Interrupted": "hga_jax.errors",
    "ModelMismatchError": "hga_jax.errors",
    "solve": "hga_jax.model.exact",
    "Path": "hga_jax.model.path", "evaluate_path": "hga_jax.model.path",
    "from_chromosome": "hga_jax.model.path", "Touch": "hga_jax.model.touch",
    "plot_convergence": "hga_jax.host.plots", "plot_path": "hga_jax.host.plots",
    "save_figure": "hga_jax.host.plots",
    "run_summary": "hga_jax.host.report", "write_run": "hga_jax.host.report",
    "poses": "hga_jax.host.poses",
    "RunsResult": "hga_jax.running.results", "BestPath": "hga_jax.running.results",
    "enable_compilation_cache": "hga_jax.compiled", "run_many": "hga_jax.running.runner",
    "settings_for": "hga_jax.running.runner",
    "Field": "hga_jax.model.scenario", "Scenario": "hga_jax.model.scenario",
    "PAPER": "hga_jax.search.settings", "PRESETS": "hga_jax.search.settings",
    "RECOMMENDED": "hga_jax.search.settings", "GASettings": "hga_jax.search.settings",
    "preset": "hga_jax.search.settings",
}

__all__ = sorted(k for k in _EXPORTS if k != "distributed")


def __getattr__(name: str) -> Any:
    if name not in _EXPORTS:
        raise AttributeError(f"module 'hga_jax' has no attribute {name!r}")
    module = importlib.import_module(_EXPORTS[name])
    value = module if name == "distributed" else getattr(module, name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_EXPORTS))
