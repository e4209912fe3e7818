"""hga-jax: shortest Dubins-car paths among circular obstacles with a hierarchical GA.

Notebook use::

    import hga_jax as hg
    hg.use_cpu_cores()  # first: one JAX device per CPU core (faster; same results)
    sc = hg.load_scenario("configs/scenarios/robocup_paper.toml")
    res = hg.run_many(sc, "recommended", runs=100, seed=1)  # or "paper", or a GASettings
    print(hg.run_summary(res))
    hg.plot_path(sc, res.best.segments, touched=res.best.touched)
    hg.write_run(res, "results/notebook", plot=True, force=True)  # replaces an earlier result

The model and the result files are defined in docs/model.md.
"""
__version__ = "0.4.0"

from hga_jax.running import distributed  # distributed.initialize: one job over several processes
from hga_jax.host.config import load_scenario, scenario_from_dict
from hga_jax.running.devices import use_cpu_cores
from .errors import ConfigError, Interrupted, ModelMismatchError
from hga_jax.model.exact import solve
from hga_jax.model.path import Path, evaluate_path, from_chromosome
from hga_jax.host.plots import plot_convergence, plot_path, save_figure
from hga_jax.host.report import run_summary, write_run
from hga_jax.running.results import RunsResult
from hga_jax.running.runner import enable_compilation_cache, run_many, settings_for
from hga_jax.model.scenario import Field, Scenario
from hga_jax.search.settings import PAPER, PRESETS, RECOMMENDED, GASettings, preset

__all__ = [
    "ConfigError", "Field", "GASettings", "Interrupted", "ModelMismatchError", "PAPER", "PRESETS",
    "Path", "RECOMMENDED", "RunsResult", "Scenario", "preset",
    "enable_compilation_cache", "use_cpu_cores",
    "evaluate_path", "from_chromosome", "load_scenario", "plot_convergence", "plot_path",
    "run_many", "run_summary", "save_figure", "scenario_from_dict", "settings_for", "solve",
    "write_run",
]
