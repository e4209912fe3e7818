"""The study analysis ``reversing``: what backing up saves, and whether the GA finds it.

Per scene family and obstacle count, from the cells' optima (a Reeds–Shepp optimum
records the free-turn and tight-rope optima of the same scene beside its own,
:meth:`~hga_jax.model.car_model.CarModel.extras`): how many scenes reversing shortens
by 1 % or more (and how many the forward car cannot drive at all: ratio 0), the median
and smallest ratio of the Reeds–Shepp optimum to the free-turn (forward-only) one and to
the tight rope's, the median cusps; and for the
study's first configuration its hit rate over all runs and on its worst scene
(``reversing.csv``, ``reversing.md``). Host code.
"""
from __future__ import annotations

import math
import os
from typing import Any

import numpy as np
import pandas as pd

from hga_jax.host.output import write_file
from .table import markdown, write_csv

SAVES = 0.01
"""A scene where reversing saves at least this share of the forward car's optimum."""


def reversing(study: Any, tab: pd.DataFrame, docs: list[dict], rows: Any,
              folder: str, draw: bool = True) -> list[str]:
    """The table of the module doc; its files (it draws no figure)."""
    scenes: dict[tuple[str, int], dict[str, dict]] = {}
    for d in docs:
        details = d.get("optimum_details") or {}
        if d.get("optimum") is None or "free_turn_length" not in details:
            continue  # no Reeds-Shepp optimum here
        scenes.setdefault((d["family"], d["obstacles"]), {})[d["scenario"]] = {
            "both": d["optimum"], "forward": details["free_turn_length"],
            "rope": details.get("tight_rope_length"), "cusps": details.get("cusps", 0)}
    first = study.configs[0].label
    out = []
    for (family, n), by_scene in scenes.items():
        # A scene the forward car cannot drive at all: ratio 0 (reversing is all of it).
        free = np.array([s["both"] / s["forward"] if s["forward"] else 0.0
                         for s in by_scene.values()])
        tight = np.array([s["both"] / s["rope"] if s["rope"] else 0.0
                          for s in by_scene.values()])
        m = (tab["config"] == first) & (tab["family"] == family) & (tab["obstacles"] == n)
        per_scene = tab[m].groupby("scenario")["hit"].mean() if m.any() else pd.Series([], float)
        out.append({
            "family": family, "obstacles": n, "scenes": len(by_scene),
            "scenes_reversing_saves": int(np.sum(free <= 1 - SAVES)),
            "scenes_forward_no_path": int(np.sum(free == 0.0)),
            "rs_to_free_median": float(np.median(free)), "rs_to_free_min": float(np.min(free)),
            "rs_to_tight_median": float(np.median(tight)) if tight.size else math.nan,
            "cusps_median": float(np.median([s["cusps"] for s in by_scene.values()])),
            "config": first,
            "hit_rate": float(tab[m]["hit"].mean()) if m.any() else math.nan,
            "worst_scene_hit_rate": float(per_scene.min()) if len(per_scene) else math.nan})
    write_csv(os.path.join(folder, "reversing.csv"), pd.DataFrame(out), missing="nan")
    text = _markdown(out)
    write_file(os.path.join(folder, "reversing.md"), lambda fh: fh.write(text))
    return [os.path.join(folder, "reversing.csv"), os.path.join(folder, "reversing.md")]


def _markdown(out: list[dict]) -> str:
    def pct(v):
        return "-" if math.isnan(v) else f"{100 * v:.1f} %"

    def ratio(v):
        return "-" if math.isnan(v) else f"{v:.3f}"

    rows = [{
        "family": r["family"], "n": r["obstacles"],
        "scenes (reversing saves >= 1 %; forward: no path)":
            f"{r['scenes']} ({r['scenes_reversing_saves']}; {r['scenes_forward_no_path']})",
        "RS / free turns: median (min)": f"{ratio(r['rs_to_free_median'])} "
                                         f"({ratio(r['rs_to_free_min'])})",
        "RS / tight rope: median": ratio(r["rs_to_tight_median"]),
        "median cusps": f"{r['cusps_median']:g}",
        f"hit rate ({r['config']})": pct(r["hit_rate"]),
        "worst scene": pct(r["worst_scene_hit_rate"]),
    } for r in out]
    return markdown(pd.DataFrame(rows)) + "\n"
