"""The tidy table of a study: a pandas DataFrame, one row per run, rebuilt from the cell files.

Columns: the study, configuration label, family, scenario, obstacle count, seed
and run index; every GA setting; the run's best ``length`` (m, float64),
``feasible``, ``violations`` (the search's collision mode), ``violations_full``
(the same path under the full test), ``gap`` to the exact optimum (missing when
infeasible), ``hit`` (gap below 1e-6), ``optimum`` (m); ``generation_best`` (first
reached its best), the generation and evaluations to within 5 % and 1 % and to the
hit (missing: never), ``evaluations`` (the run's budget) and ``time_s`` (the run's
share of its batch's search time, compile excluded).

A column with missing values is float64 with NaN (floats), nullable ``Int64``
(integers) or object (anything else); :func:`numeric` reads any column as float64
with missing values as infinity. Files: CSV (missing values empty, floats in
Python's shortest round-trip form, booleans ``True``/``False``), Parquet (pyarrow,
missing values null), JSON lines (missing values ``null``), Markdown.
"""
from __future__ import annotations

import json
from typing import Any, Iterable

import numpy as np
import pandas as pd

from hga_jax.host.output import write_file
from hga_jax.running.results import json_safe

ID_COLUMNS = ("study", "config", "solver", "family", "group", "scenario", "obstacles", "seed")


def _column(values: list) -> Any:
    """A column's values: numpy's own array when none is missing (as ``np.asarray``
    types it), else the pandas dtype that keeps the others' values exactly."""
    present = [v for v in values if v is not None]
    if len(present) == len(values):
        try:
            return np.asarray(values)
        except (ValueError, TypeError):
            pass
    elif present and all(isinstance(v, int) and not isinstance(v, bool) for v in present):
        return pd.array(values, dtype="Int64")
    elif present and all(isinstance(v, float) for v in present):
        return np.array([np.nan if v is None else v for v in values], np.float64)
    arr = np.empty(len(values), object)
    arr[:] = values
    return arr


def build(study: str, docs: Iterable[dict[str, Any]]) -> pd.DataFrame:
    """One row per run of every cell document, in plan order."""
    parts: dict[str, list] = {}
    settings_keys: list[str] = []
    done = 0  # rows so far
    for doc in docs:
        n = doc["runs"]
        consts = {"study": study, "config": doc["config"], "solver": doc.get("solver", "hga"),
                  "family": doc["family"], "scenario": doc["scenario"],
                  "obstacles": doc["obstacles"], "seed": doc["seed"]}
        consts.update(doc["settings"])
        settings_keys = settings_keys or list(doc["settings"])
        cols = dict(doc["columns"])
        cols["optimum"] = [doc["optimum"]] * n
        cols["evaluations"] = (list(cols.pop("evaluations_run")) if "evaluations_run" in cols
                               else [doc["evaluations_per_run"]] * n)
        if "time_s" not in cols:  # cells written before times per run
            cols["time_s"] = [doc["search_s"] / n] * n
        cols["compile_s"] = [doc.get("compile_s", 0.0)] * n
        row = {**{k: [v] * n for k, v in consts.items()}, **cols}
        for k in row:
            if k not in parts:  # a column earlier cells lack (a peer's own)
                parts[k] = [None] * done
        for k, v in parts.items():
            v.extend(row.get(k, [None] * n))
        done += n
    if done:
        parts["group"] = group_labels(parts["family"], parts["obstacles"], parts["scenario"])
    order = list(ID_COLUMNS) + ["run"] + settings_keys + [
        k for k in parts if k not in ID_COLUMNS and k != "run" and k not in settings_keys]
    return pd.DataFrame({k: _column(parts[k]) for k in order if k in parts})


def group_labels(families: list, obstacles: list, scenarios: list) -> list[str]:
    """The group of each row: its family, and its obstacle count where the family has
    several (``"obstructed, 15 obstacles"``), so that no summary or figure pools
    scenes of different sizes; a scene file of the study (family ``"files"``) is a
    group of its own, named by its scenario (``"robocup_paper"``)."""
    counts: dict[Any, set] = {}
    for f, n in zip(families, obstacles):
        counts.setdefault(f, set()).add(n)
    return [s if f == "files" else f if len(counts[f]) == 1 else f"{f}, {n} obstacles"
            for f, n, s in zip(families, obstacles, scenarios)]


def doc_groups(docs: list[dict[str, Any]]) -> list[str]:
    """:func:`group_labels` of cell documents, one per document."""
    return group_labels([d["family"] for d in docs], [d["obstacles"] for d in docs],
                        [d["scenario"] for d in docs])


def numeric(table: pd.DataFrame, name: str) -> np.ndarray:
    """A column as float64, missing values as inf (a target never reached, a gap of an
    infeasible run)."""
    col = pd.to_numeric(table[name]).astype("Float64")
    return col.fillna(np.inf).to_numpy(np.float64)


def records(table: pd.DataFrame) -> list[dict[str, Any]]:
    """The rows as dicts of Python values, missing values as None."""
    cols = {k: [None if v is pd.NA or (isinstance(v, float) and np.isnan(v)) else v
                for v in table[k].tolist()] for k in table.columns}
    return [dict(zip(cols, row)) for row in zip(*cols.values())]


def write_csv(path: str, table: pd.DataFrame, missing: str = "") -> None:
    """CSV with a header, atomically; ``missing`` stands for a missing value (NaN)."""
    write_file(path, lambda fh: table.to_csv(fh, index=False, na_rep=missing,
                                             lineterminator="\r\n"))


def write_parquet(path: str, table: pd.DataFrame) -> None:
    """Parquet (pyarrow), atomically; an object column that mixes types (settings
    that differ in type between configurations) is stored as text."""
    out = table.copy()
    for k in out.columns:
        if out[k].dtype == object and len({type(v) for v in out[k] if v is not None}) > 1:
            out[k] = [None if v is None else str(v) for v in out[k]]
    write_file(path, lambda fh: out.to_parquet(fh, engine="pyarrow", index=False), binary=True)


def write_jsonl(path: str, table: pd.DataFrame) -> None:
    """One strict JSON object per row (missing and non-finite values as null), atomically."""
    def write(fh):
        for row in records(table):
            fh.write(json.dumps(json_safe(row), allow_nan=False) + "\n")

    write_file(path, write)


def markdown(table: pd.DataFrame) -> str:
    """A Markdown table (``DataFrame.to_markdown``), cells unpadded and as given."""
    return table.to_markdown(index=False, stralign=None, numalign=None,
                             disable_numparse=True)

