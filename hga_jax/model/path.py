"""A single path, re-evaluated exactly: float64 length, violations and segments.

Host-side: runs the same decoder as the search (:func:`hga_jax.model.decode.decode_batch`)
in float64 and turns its slots into the segment list of the result files
(docs/model.md). Every length that hga-jax reports comes from here, whatever
precision the search used.

Obstacles are *numbered* from 1 (the order of the scenario's ``[[obstacles]]``
tables) in what users read: ``upper``, ``violations_at`` and the result files'
``touched``, in files and in Python results alike (:class:`Touch`). Python-side
indices into arrays (``perm``, ``scenario.centres``) count from 0.
"""
from __future__ import annotations

import functools
from dataclasses import dataclass, field
from typing import Any, Sequence

import numpy as np

from hga_jax.model import collision as col
from hga_jax.model import geometry as g
from hga_jax.model.cars.free_turns import legs as free_legs
from hga_jax.model.cars.reeds_shepp import reversing
from hga_jax.model.in_time import clearance
from hga_jax.errors import ConfigError
from .scenario import Scenario
from .touch import Touch, touch_list


@functools.cache
def _decoder():
    """The jitted decoder (JAX is imported on the first decoding, not with this module)."""
    import jax

    from .decode import decode_batch

    return jax.jit(decode_batch, static_argnames="collision")
TINY = 1e-12  # m: a line this short is rounding (e.g. between coincident circles)
BLOCK = 64  # float64 decoding always runs on blocks of this many rows


def decode64(scenario: Scenario, perm, labels, collision: str = "full", legs=None):
    """Float64 decoding of a batch, as numpy arrays (a :class:`Decoded` of them);
    ``legs``: positional leg genes of free-turn chromosomes (or None).

    Rows go through one compiled shape of ``BLOCK`` rows (the last block padded), so
    a chromosome gets bit-identical values alone or in a batch of any size.
    """
    labels = np.asarray(labels, np.int32).reshape(-1, scenario.n + 2)
    rows = labels.shape[0]
    perm = np.asarray(perm, np.int32).reshape(rows, scenario.n)
    pad = -rows % BLOCK

    def padded(a):
        return np.concatenate([a, np.repeat(a[:1], pad, axis=0)])

    perm, labels = padded(perm), padded(labels)
    if legs is not None:
        legs = padded(np.asarray(legs, np.int32).reshape(rows, scenario.n + 2))
    import jax

    from hga_jax import compiled

    parts = []
    with jax.enable_x64(True):
        sa = _arrays64(scenario, legs is not None)
        block = (lambda a: None if a is None else a[:BLOCK])
        key = ("decode64", collision, legs is None, tuple(
            (np.shape(a), np.result_type(a).name) for a in jax.tree.leaves(sa)))
        decode = compiled.program(key, lambda: _decoder().lower(
            sa, perm[:BLOCK], labels[:BLOCK], collision=collision, legs=block(legs)))
        for i in range(0, rows + pad, BLOCK):
            d = decode(sa, perm[i:i + BLOCK], labels[i:i + BLOCK],
                       legs=None if legs is None else legs[i:i + BLOCK])
            parts.append(jax.tree.map(np.asarray, d))
    return jax.tree.map(lambda *xs: np.concatenate(xs)[:rows], *parts)


def _arrays64(scenario: Scenario, genes: bool):
    """The float64 arrays that decode the scenario's chromosomes (with leg genes: the
    tables of its car's model with genes, :func:`hga_jax.model.car_model.with_genes`)."""
    if not genes:
        return scenario.arrays(np.float64)
    from . import car_model

    return car_model.with_genes(scenario.car).decode_arrays(scenario)


@dataclass
class Path:
    """An evaluated path.

    length: metres (arcs + lines, no penalty). violations: count (docs/model.md).
    upper, lower: the chromosome (upper ``[0, ..., n+1]``, lower labels).
    segments: segment dicts of the result files in travel order (zero-length pieces
      left out, and lines shorter than ``TINY``: rounding, with no direction).
    touched: :class:`Touch` ``(obstacle number from 1, label +1 CW / -1 CCW)`` pairs in
      travel order, as in :class:`~hga_jax.model.exact.ExactResult`; ``to_dict`` writes
      them in the result files' format, ``{"obstacle": number from 1, "label": ...}``.
    violations_at: one dict per violation: ``{"kind": "obstacle" | "missing tangent" |
      "field" | "missing cusp" | "moving obstacle" | "moving obstacle wrapped", "segment":
      index into segments (None for a zero-length piece), "obstacle": number from 1 (None
      unless kind names an obstacle)}``. Among robots that move, ``violations`` is the
      float64 decoder's count (:data:`hga_jax.model.in_time.clearance.SUBARCS_64` sub-arcs) and the
      entries in time are the float64 path check's (:func:`hga_jax.model.in_time.clearance.segment_hits`).
    legs: the leg genes of a free-turn chromosome (positional, as ``lower``), or None;
      arcs on free circles carry ``"free": true`` in ``segments``, and pieces driven
      backward (a car that reverses) ``"reverse": true``.
    """

    length: float
    violations: int
    upper: list[int]
    lower: list[int]
    segments: list[dict[str, Any]] = field(default_factory=list)
    touched: list[Touch] = field(default_factory=list)
    violations_at: list[dict[str, Any]] = field(default_factory=list)
    legs: list[int] | None = None

    @property
    def feasible(self) -> bool:
        return self.violations == 0

    @property
    def cusps(self) -> int:
        """Where the gear changes between two pieces (a car that reverses)."""
        return sum(a.get("reverse", False) != b.get("reverse", False)
                   for a, b in zip(self.segments, self.segments[1:]))

    def to_dict(self) -> dict[str, Any]:
        return {
            "length": self.length,
            "feasible": self.feasible,
            "violations": self.violations,
            "upper": self.upper,
            "lower": self.lower,
            "touched": touch_list(self.touched),
            "segments": self.segments,
            "violations_at": self.violations_at,
            **({} if self.legs is None else {"legs": self.legs}),
        }


def chromosome(perm: Sequence[int], labels: Sequence[int]) -> tuple[list[int], list[int]]:
    """(upper, lower) of docs/model.md from the internal ``perm`` (0-based) and ``labels``."""
    n = len(perm)
    return [0] + [int(p) + 1 for p in perm] + [n + 1], [int(v) for v in labels]


def from_chromosome(upper: Sequence[int], lower: Sequence[int], n: int,
                    source: str = "<chromosome>") -> tuple[np.ndarray, np.ndarray]:
    """Internal ``(perm, labels)`` from an (upper, lower) chromosome, checked."""
    upper, lower = [int(u) for u in upper], [int(v) for v in lower]
    if len(upper) != n + 2 or upper[0] != 0 or upper[-1] != n + 1 or sorted(upper[1:-1]) != list(
            range(1, n + 1)):
        raise ConfigError(f"{source}: upper: must be 0, a permutation of 1..{n}, {n + 1}")
    if len(lower) != n + 2 or any(v not in (-1, 1) for v in (lower[0], lower[-1])) or any(
            v not in (-1, 0, 1) for v in lower):
        raise ConfigError(f"{source}: lower: must be {n + 2} labels, ends in {{-1, 1}}, "
                          "others in {-1, 0, 1}")
    return np.asarray(upper[1:-1], np.int32) - 1, np.asarray(lower, np.int32)


def legs_from_list(legs: Sequence[int] | None, n: int, source: str = "<chromosome>",
                   values: int = free_legs.VARIANTS) -> np.ndarray | None:
    """Internal leg genes from a chromosome's ``legs`` list, checked (``values``: how
    many a gene takes, :func:`gene_values`); None stays None."""
    if legs is None:
        return None
    out = [int(v) for v in legs]
    if len(out) != n + 2 or any(not 0 <= v < values for v in out):
        raise ConfigError(f"{source}: legs: must be {n + 2} leg genes in "
                          f"{{{', '.join(map(str, range(values)))}}}")
    return np.asarray(out, np.int32)


def gene_values(scenario: Scenario) -> int:
    """How many values a leg gene of the scenario's car takes (3 for the forward car's
    free turns, 7 for the Reeds–Shepp car's)."""
    from . import car_model

    return len(car_model.with_genes(scenario.car).genes[0].weights)


def evaluate_path(scenario: Scenario, perm: Sequence[int], labels: Sequence[int],
                  collision: str = "full", legs: Sequence[int] | None = None) -> Path:
    """Decode one chromosome in float64 and describe its path, violations located;
    ``legs``: its positional leg genes under free turns (the full rule only)."""
    perm = np.asarray(perm, np.int32).reshape(scenario.n)
    labels = np.asarray(labels, np.int32).reshape(scenario.n + 2)
    if legs is not None:
        legs = np.asarray(legs, np.int32).reshape(scenario.n + 2)
    import jax

    d = jax.tree.map(lambda a: a[0], decode64(scenario, perm, labels, collision, legs))
    upper, lower = chromosome(perm, labels)
    locate = _Locator(scenario, collision)
    segments: list[dict[str, Any]] = []
    where: list[dict[str, Any]] = []
    count = int(d.count)
    backward = [d.gears is not None and bool(d.gears[0])]  # the gear now
    slots = np.flatnonzero(labels != 0)  # the position of each of the path's circles

    def straight(ends) -> list[dict[str, Any]]:
        """A quarter turn's tangent (none where its ends meet), located."""
        if np.hypot(ends[2] - ends[0], ends[3] - ends[1]) <= TINY:
            return []
        add({"type": "line", "start": [ends[0], ends[1]], "end": [ends[2], ends[3]]})
        return locate.line(ends, True, len(segments) - 1)

    def add(segment: dict[str, Any]) -> None:
        if backward[0]:
            segment["reverse"] = True
        segments.append(segment)

    for s in range(count):
        cx, cy, r, sign = (float(v) for v in d.circles[s])
        ax, ay, bx, by, swp = (float(v) for v in d.arcs[s])
        drawn = swp > 0.0
        if drawn:
            add({"type": "arc", "center": [cx, cy], "radius": r,
                 "start_angle": float(np.arctan2(ay - cy, ax - cx)), "sweep": -sign * swp})
        where += locate.arc((cx, cy, r, sign), int(d.obstacle[s]), (ax, ay, bx, by, swp),
                            len(segments) - 1 if drawn else None)
        if s < count - 1 and d.free is not None and abs(float(d.free[s][3])) > 0.5:
            fx, fy, fswp, fs = (float(v) for v in d.free[s][:4])
            p1x, p1y, p2x, p2y, _ = (float(v) for v in d.lines[s])
            rho = float(scenario.min_turn_radius)
            if d.gears is None:  # the forward car: over the free circle from P1 to P2
                (q1x, q1y, q2x, q2y), cusps = (p1x, p1y, p2x, p2y), 0
            else:  # P1 to Q1 straight, the free circle to Q2, straight to P2; cusps at Q1, Q2
                q1x, q1y, q2x, q2y = (float(v) for v in d.free[s][4:8])
                cusps = int(round(float(d.free[s][8])))
            where += straight((p1x, p1y, q1x, q1y))
            backward[0] ^= bool(cusps & 1)
            if fswp > 0.0:
                add({"type": "arc", "center": [fx, fy], "radius": rho,
                     "start_angle": float(np.arctan2(q1y - fy, q1x - fx)),
                     "sweep": -fs * fswp, "free": True})
            where += locate.arc((fx, fy, rho, fs), -1, (q1x, q1y, q2x, q2y, fswp),
                                len(segments) - 1 if fswp > 0.0 else None)
            backward[0] ^= bool(cusps & 2)
            where += straight((q2x, q2y, p2x, p2y))
        elif s < count - 1:
            p1x, p1y, p2x, p2y, exists = (float(v) for v in d.lines[s])
            drawn = bool(np.hypot(p2x - p1x, p2y - p1y) > TINY)
            if drawn:
                add({"type": "line", "start": [p1x, p1y], "end": [p2x, p2y]})
            where += locate.line((p1x, p1y, p2x, p2y), exists > 0.5,
                                 len(segments) - 1 if drawn else None)
            if d.gears is not None and bool(reversing.odd_leg(
                    int(legs[slots[s]]), sign, float(d.circles[s + 1][3]), s == 0, s == count - 2)):
                # the gene promised a free circle with a cusp that does not exist
                where.append({"kind": "missing cusp", "segment": len(segments) - 1 if drawn
                              else None, "obstacle": None})
                backward[0] = not backward[0]
    touched = [Touch(int(d.obstacle[s]) + 1, int(d.circles[s][3])) for s in range(1, count - 1)]
    if scenario.has_motion:  # in time: the float64 check of hga_jax.model.in_time.clearance
        if scenario.wrap_moving == "never":
            where += [{"kind": "moving obstacle wrapped", "segment": None,
                       "obstacle": t.obstacle} for t in touched if scenario.moving[t.obstacle - 1]]
        where += [{"kind": "moving obstacle", "segment": i, "obstacle": k + 1}
                  for i, k in clearance.segment_hits(scenario, segments)]
    return Path(float(d.length), int(d.violations), upper, lower, segments, touched, where,
                None if legs is None else [int(v) for v in legs])


class _Locator:
    """Which obstacle (or the field) each piece of a decoded path violates.

    The decoder's rules (:mod:`hga_jax.model.collision`) in float64, piece by piece,
    so the list has one entry per violation the decoder counted.
    """

    def __init__(self, scenario: Scenario, collision: str):
        sa = scenario.arrays(np.float64)
        self.obstacles = col.obstacles(np.asarray(sa.centres), np.asarray(sa.model_radii))
        self.bounds, self.collision = np.asarray(sa.bounds), collision
        self.tol = g.tolerances(np.float64).length

    def _obstacles(self, hit: np.ndarray, segment: int | None) -> list[dict[str, Any]]:
        return [{"kind": "obstacle", "segment": segment, "obstacle": int(k) + 1}
                for k in np.flatnonzero(hit)]

    @staticmethod
    def _field(out: Any, segment: int | None) -> list[dict[str, Any]]:
        return [{"kind": "field", "segment": segment, "obstacle": None}] if bool(out) else []

    def arc(self, circle, own: int, arc, segment: int | None) -> list[dict[str, Any]]:
        hit = col.arc_obstacles(circle, own, arc, self.obstacles, self.tol, self.collision)
        out = col.arc_leaves_field(circle, arc, self.bounds, self.tol)
        return self._obstacles(hit, segment) + self._field(out, segment)

    def line(self, ends, exists: bool, segment: int | None) -> list[dict[str, Any]]:
        hit = col.segment_obstacles(ends, self.obstacles, self.tol, self.collision)
        found = self._obstacles(hit, segment)
        if col.missing_tangent(exists):
            found.append({"kind": "missing tangent", "segment": segment, "obstacle": None})
        return found + self._field(col.segment_leaves_field(ends, self.bounds, self.tol), segment)


def segments_length(segments: Sequence[dict[str, Any]]) -> float:
    """Total length of a segment list of the result files (m): ``radius*|sweep|`` plus line lengths."""
    total = 0.0
    for seg in segments:
        if seg["type"] == "arc":
            total += seg["radius"] * abs(seg["sweep"])
        else:
            total += float(np.hypot(seg["end"][0] - seg["start"][0], seg["end"][1] - seg["start"][1]))
    return total
