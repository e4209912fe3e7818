"""Results of many runs: statistics, the gap to the optimum, JSON/CSV files.

Lengths are metres and come from the float64 re-evaluation. ``gap = length /
optimum - 1`` for a feasible run (``inf`` for an infeasible one); when the optimum
is 0 m (start and goal poses equal), the gap is 0 for a path no longer than
``ZERO_LENGTH`` and ``inf`` otherwise; a gap within ``GAP_NOISE`` of 0 (the float64
rounding of a path as long as the optimum, e.g. -2.2e-16) is 0. A run *hits* the
optimum when its gap is below ``HIT_GAP``. Generations count from 0 (the initial
population). The file format is described in docs/model.md.
"""
from __future__ import annotations

import dataclasses
import math
import platform
from dataclasses import asdict, dataclass
from typing import Any

import numpy as np

from hga_jax.model import car_model
from hga_jax.model.path import Path, chromosome
from hga_jax.model.scenario import Scenario
from hga_jax.search.settings import GASettings

HIT_GAP = 1e-6
NEAR_GAP = 0.01
ZERO_LENGTH = 1e-9  # metres: a path this short matches an optimum of 0 m
GAP_NOISE = 1e-12  # a gap this close to 0 is rounding (the optimum's own length): 0
SEARCH_SLACK = 1e-5  # metres: absolute slack on the search's own (float32) lengths


@dataclass
class BestPath(Path):
    """:attr:`RunsResult.best`: the best run's :class:`~hga_jax.model.path.Path`, with the
    scenario's ``start`` pose (x, y, heading in rad) and the car's ``speed`` (m/s), so
    that it can be sampled as poses."""

    start: tuple[float, ...] = ()
    speed: float = 1.0

    @classmethod
    def of(cls, path: Path, scenario: Scenario) -> "BestPath":
        fields = {f.name: getattr(path, f.name) for f in dataclasses.fields(Path)}
        return cls(**fields, start=tuple(float(v) for v in scenario.start),
                   speed=float(scenario.speed))

    def poses(self, spacing: float = 0.01) -> np.ndarray:
        """The path as poses every ``spacing`` m (and at each piece's ends): a numpy
        structured array with columns ``s, x, y, heading, curvature`` (float64), ``gear``
        (int8, +1 forward, -1 backward) and ``t`` (``s / speed``, s), as
        :func:`hga_jax.host.poses.poses` gives them."""
        from hga_jax.host.poses import sample_poses

        return sample_poses(self.segments, spacing, start=self.start or None, speed=self.speed)


def best_run(length, violations) -> int:
    """The index of the best of several runs, the one rule of runs and study cells: the
    shortest feasible path if any run has one, else the fewest violations, then the
    shortest; ties go to the first run."""
    length, violations = np.asarray(length, np.float64), np.asarray(violations)
    return int(np.lexsort((np.arange(length.size), length, violations))[0])


def gap_of(length, feasible, optimum: float) -> np.ndarray:
    """``length / optimum - 1`` where feasible, inf elsewhere (see the module doc for an
    optimum of 0 m; one within ``GAP_NOISE`` of 0 is 0); elementwise over numpy arrays or
    numbers."""
    length = np.asarray(length, np.float64)
    if optimum > 0.0:
        rel = length / optimum - 1.0
        rel = np.where(np.abs(rel) <= GAP_NOISE, 0.0, rel)
    else:
        rel = np.where(length <= ZERO_LENGTH, 0.0, np.inf)
    return np.where(feasible, rel, np.inf)


def settings_dict(settings: GASettings) -> dict[str, Any]:
    """The ``settings`` of the result files: every field, and the car of its model."""
    return {**asdict(settings), "car": settings.model.car}


@dataclass
class RunsResult:
    """Everything a batch of runs produced (arrays have one row per run)."""

    scenario: Scenario
    settings: GASettings
    seed: int
    run_ids: np.ndarray  # (R,)
    perm: np.ndarray  # (R, n) best chromosome of each run
    labels: np.ndarray  # (R, n + 2)
    length: np.ndarray  # (R,) float64 metres
    violations: np.ndarray  # (R,)
    generation: np.ndarray  # (R,) generation its best was first reached
    history: dict[str, np.ndarray]  # name -> (G + 1, R)
    best: Path  # overall best path (float64): a BestPath, whose poses(spacing) samples it
    best_run: int
    optimum: Any = None  # exact.ExactResult or None
    compile_s: float = 0.0
    search_s: float = 0.0
    finish_s: float = 0.0
    evaluations: int = 0
    preset: str | None = None  # the preset the settings were built on (None: not said)
    devices: int = 1  # devices the search was spread over (all processes')
    plugins: tuple[str, ...] = ()  # plugins imported for the settings (hga-jax run --plugin)
    budget: dict[str, Any] | None = None  # how the generations grew with n (GASettings.budget)
    legs: np.ndarray | None = None  # (R, n + 2) positional leg genes (free turns), else None
    # A resumed job: what its interrupted start had done, included in the totals above
    # ({"runs": count, "compile_s": s, "search_s": s}); None for a job run at once.
    earlier: dict[str, Any] | None = None

    @property
    def feasible(self) -> np.ndarray:
        return self.violations == 0

    @property
    def optimum_length(self) -> float | None:
        """The yardstick of the gaps (m): the optimum, or among robots that move where no
        optimum is certified the lower bound (:attr:`yardstick` says which); None without."""
        opt = self.optimum
        if opt is not None and not opt.optimal:
            return opt.lower_bound
        return float(opt.length) if opt is not None and opt.feasible else None

    @property
    def yardstick(self) -> str:
        """What the gaps are measured against: ``"optimum"`` or ``"lower bound"`` (robots
        that move, no optimum certified: :mod:`hga_jax.model.in_time.optimum`)."""
        opt = self.optimum
        return "lower bound" if opt is not None and not opt.optimal else "optimum"

    @property
    def gap(self) -> np.ndarray:
        """Per run ``length / optimum - 1`` (inf when infeasible, nan without optimum)."""
        opt = self.optimum_length
        if opt is None:
            return np.full(len(self.length), np.nan)
        return gap_of(self.length, self.feasible, opt)

    @property
    def hit(self) -> np.ndarray:
        return self.gap < HIT_GAP

    def first_generation_within(self, gap: float) -> np.ndarray:
        """Per run the first generation whose best-so-far is feasible and within ``gap``
        of the optimum (-1: never). Judged on the search's own lengths with a relative
        slack of 1e-6 and an absolute one of ``SEARCH_SLACK``."""
        opt = self.optimum_length
        if opt is None:
            return np.full(len(self.length), -1)
        h = self.history
        ok = (h["best_so_far_violations"] == 0) & (
            h["best_so_far_length"] <= opt * (1.0 + gap) * (1.0 + 1e-6) + SEARCH_SLACK)
        return np.where(ok.any(axis=0), ok.argmax(axis=0), -1)

    @property
    def generation_hit(self) -> np.ndarray:
        return np.where(self.hit, self.generation, -1)

    def summary(self) -> dict[str, Any]:
        """The figures the command line prints and result.json carries."""
        best_len = self.best.length
        found = (self.feasible == self.best.feasible) & np.isclose(
            self.length, best_len, rtol=1e-9, atol=0.0)
        out: dict[str, Any] = {
            "best_length": best_len,
            "best_feasible": self.best.feasible,
            "runs": int(len(self.length)),
            "feasible_runs": int(self.feasible.sum()),
            "runs_found_best": int(found.sum()),
            "median_generation_found_best": _median(self.generation[found]),
            "compile_s": self.compile_s,
            "search_s": self.search_s,
            "devices": self.devices,
            "evaluations": self.evaluations,
            "evaluations_per_s": self.evaluations / self.search_s if self.search_s else None,
            **({"resumed": dict(self.earlier)} if self.earlier else {}),
        }
        if self.optimum_length is not None:
            gap = self.gap[self.feasible]  # infeasible runs are counted, not averaged
            near = self.first_generation_within(NEAR_GAP)
            out.update(car_model.get(self.optimum.turns).summary(self.optimum))
            if self.scenario.has_motion:  # gaps to the optimum or to the bound, said
                out["yardstick"] = self.yardstick
                if self.optimum.feasible and not self.optimum.optimal:
                    out["best_known_length"] = float(self.optimum.length)
            out.update({
                "optimum_length": self.optimum_length,
                "hit_rate": float(self.hit.mean()),
                "infeasible_runs": int((~self.feasible).sum()),
                "gap_median": _stat(np.median, gap),
                "gap_mean": _stat(np.mean, gap),
                "gap_max": _stat(np.max, gap),
                "shorter_than_optimum": int(np.sum(gap < -HIT_GAP)),
                "runs_hit": int(self.hit.sum()),
                "runs_within_1pct": int((near >= 0).sum()),
                "median_generation_within_1pct": _median(near[near >= 0]),
                "median_generation_hit": _median(self.generation_hit[self.hit]),
            })
        return out

    def to_dict(self) -> dict[str, Any]:
        """result.json (the format of docs/model.md plus run statistics)."""

        near = self.first_generation_within(NEAR_GAP)
        per_run = []
        for i, k in enumerate(self.run_ids):
            upper, lower = chromosome(self.perm[i], self.labels[i])
            per_run.append({
                "run": int(k), "length": float(self.length[i]),
                "feasible": bool(self.feasible[i]), "violations": int(self.violations[i]),
                "generation": int(self.generation[i]),
                "gap": float(self.gap[i]), "hit": bool(self.hit[i]),
                "generation_within_1pct": int(near[i]),
                "generation_hit": int(self.generation_hit[i]),
                "upper": upper, "lower": lower,
                **({} if self.legs is None else {"legs": [int(v) for v in self.legs[i]]}),
            })
        return result_document(self.scenario, {
            "seed": self.seed,
            "runs": [int(self.run_ids[0]), int(self.run_ids[-1])],
            "preset": self.preset,
            **({"plugins": list(self.plugins)} if self.plugins else {}),
            "settings": settings_dict(self.settings),
            **({"budget": self.budget} if self.budget else {}),
            "best": {"run": self.best_run, **self.best.to_dict()},
            "optimum": optimum_dict(self.optimum),
            "summary": self.summary(),
            "per_run": per_run,
        })

    def history_rows(self) -> list[dict[str, Any]]:
        """history.csv rows: per generation, median and quartiles over runs."""
        h = self.history
        near = self.first_generation_within(NEAR_GAP)
        rows = []
        for g in range(h["best_fitness"].shape[0]):
            row: dict[str, Any] = {"generation": g}
            for name in ("best_fitness", "mean_fitness", "best_so_far_fitness",
                         "best_so_far_length"):
                q25, q50, q75 = np.percentile(h[name][g], [25, 50, 75])
                row.update({f"{name}_median": q50, f"{name}_q25": q25, f"{name}_q75": q75})
            row["feasible_fraction"] = float(np.mean(h["best_so_far_violations"][g] == 0))
            if self.optimum_length is not None:
                row["within_1pct_fraction"] = float(np.mean((near >= 0) & (near <= g)))
                row["hit_fraction"] = float(np.mean(self.hit & (self.generation <= g)))
            rows.append(row)
        return rows


def _stat(fn, values: np.ndarray) -> float | None:
    return float(fn(values)) if len(values) else None


def _median(values: np.ndarray) -> float | None:
    return float(np.median(values)) if len(values) else None


RANDOM_STREAM = "generation-draw"  # hga-jax 0.2: one draw per generation (0.1: "operator-draws")


def result_document(scenario: Scenario, body: dict[str, Any]) -> dict[str, Any]:
    """A JSON-safe result.json: the scenario and version header, then ``body``."""
    import jax

    from hga_jax import __version__

    from hga_jax.model.scenario import scenario_to_dict

    return json_safe({
        "scenario_name": scenario.name,
        "scenario": {"name": scenario.name, "source": scenario.source, "obstacles": scenario.n,
                     "definition": scenario_to_dict(scenario)},
        "versions": {"hga_jax": __version__, "jax": jax.__version__, "numpy": np.__version__,
                     "python": platform.python_version()},
        "random_stream": RANDOM_STREAM,
        **body,
    })


def optimum_dict(opt: Any) -> dict[str, Any] | None:
    """result.json's ``optimum`` from an :class:`~hga_jax.model.exact.ExactResult` (or None)."""
    return None if opt is None else opt.to_dict()


def json_safe(obj: Any) -> Any:
    """JSON-safe copy: numpy scalars to Python, non-finite floats to None."""
    if isinstance(obj, dict):
        return {k: json_safe(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [json_safe(v) for v in obj]
    if isinstance(obj, (np.integer,)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        return float(obj) if math.isfinite(obj) else None
    return obj
