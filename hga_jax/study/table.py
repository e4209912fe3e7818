"""The tidy table of a study: one row per run, rebuilt from the cell files.

Columns: the study, configuration label, family, scenario, obstacle count, seed
and run index; every GA setting; the run's best ``length`` (m, float64),
``feasible``, ``violations`` (the search's collision mode), ``violations_full``
(the same path under the full test), ``gap`` to the exact optimum (empty when
infeasible), ``hit`` (gap below 1e-6), ``optimum`` (m); ``generation_best`` (first
reached its best), the generation and evaluations to within 5 % and 1 % and to the
hit (empty: never), ``evaluations`` (the run's budget) and ``time_s`` (the run's
share of its batch's search time, compile excluded).
"""
from __future__ import annotations

import csv
import json
from typing import Any, Iterable

import numpy as np

from hga_jax.host.output import write_file
from hga_jax.host.results import json_safe

ID_COLUMNS = ("study", "config", "family", "scenario", "obstacles", "seed")


class Table(dict):
    """Columns as numpy arrays (object arrays where values may be missing)."""

    @property
    def rows(self) -> int:
        return len(next(iter(self.values()))) if self else 0

    def where(self, mask: np.ndarray) -> "Table":
        return Table({k: v[mask] for k, v in self.items()})

    def numeric(self, name: str) -> np.ndarray:
        """A column as float64, missing values as inf (a target never reached, a gap
        of an infeasible run)."""
        return np.array([np.inf if v is None else float(v) for v in self[name]], np.float64)


def build(study: str, docs: Iterable[dict[str, Any]]) -> Table:
    """One row per run of every cell document, in plan order."""
    parts: dict[str, list] = {}
    settings_keys: list[str] = []
    for doc in docs:
        n = doc["runs"]
        consts = {"study": study, "config": doc["config"], "family": doc["family"],
                  "scenario": doc["scenario"], "obstacles": doc["obstacles"],
                  "seed": doc["seed"]}
        consts.update(doc["settings"])
        settings_keys = settings_keys or list(doc["settings"])
        cols = dict(doc["columns"])
        cols["optimum"] = [doc["optimum"]] * n
        cols["evaluations"] = [doc["evaluations_per_run"]] * n
        cols["time_s"] = [doc["search_s"] / n] * n
        for k, v in consts.items():
            parts.setdefault(k, []).extend([v] * n)
        for k, v in cols.items():
            parts.setdefault(k, []).extend(v)
    order = list(ID_COLUMNS) + ["run"] + settings_keys + [
        k for k in parts if k not in ID_COLUMNS and k != "run" and k not in settings_keys]
    out = Table()
    for k in order:
        if k in parts:
            values = parts[k]
            arr = np.empty(len(values), object)
            arr[:] = values
            if all(v is not None for v in values):
                try:
                    arr = np.asarray(values)
                except (ValueError, TypeError):
                    pass
            out[k] = arr
    return out


def _py(v: Any) -> Any:
    return v.item() if isinstance(v, np.generic) else v


def write_csv(path: str, table: Table) -> None:
    names = list(table)

    def write(fh):
        w = csv.writer(fh)
        w.writerow(names)
        cols = [table[k].tolist() for k in names]
        for row in zip(*cols):
            w.writerow(["" if v is None else v for v in row])

    write_file(path, write)


def write_jsonl(path: str, table: Table) -> None:
    names = list(table)

    def write(fh):
        cols = [table[k].tolist() for k in names]
        for row in zip(*cols):
            fh.write(json.dumps(json_safe(dict(zip(names, map(_py, row)))),
                                allow_nan=False) + "\n")

    write_file(path, write)


def read_csv(path: str) -> list[dict[str, str]]:
    with open(path, newline="") as fh:
        return list(csv.DictReader(fh))
