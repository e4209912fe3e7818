"""Studies: seeded GA runs over scenes and a grid of settings, with statistics and figures.

``run_study("configs/studies/operator_study.toml")`` (or ``hga-jax study FILE``)
generates the scenes, runs every cell (one configuration on one scene) that is not
already in the study folder, and writes the tidy table of runs, summary tables,
statistics and figures. Modules: ``config`` (study files), ``scenes`` (seeded scene
families), ``store`` (resumable cell files), ``table`` (one row per run), ``stats``
(scipy-based intervals and tests), ``summary``, ``figures``, ``analyses``, ``run``.
"""
from .config import Study, load_study

__all__ = ["Outcome", "Study", "load_study", "run_study"]


def __getattr__(name: str):
    """``run_study`` and ``Outcome`` load scipy and matplotlib only when first used."""
    if name in ("Outcome", "run_study"):
        from . import run

        return getattr(run, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
