"""An independent float64 check of a Reeds–Shepp path, written apart from the solver.

It reads only the segments of the result files and the scenario's numbers (no code of
hga_jax's model): the path starts at the start pose and ends at the goal pose, its
pieces join, the car's heading is continuous (a piece driven backward, ``"reverse":
true``, heads against its direction of travel), the direction of travel flips exactly
where the gear changes (a cusp) and nowhere else, every arc turns with radius rho or
more, points sampled every millimetre keep out of every model circle and inside the
kept field, and the lengths add up to the reported length.
"""
from __future__ import annotations

import math

import numpy as np

JOIN = 1e-7  # m
ANGLE = 1e-6  # rad
CLEAR = 1e-6  # m


def _ends(seg):
    """(start point, end point, direction of travel at start and at end) of a segment."""
    if seg["type"] == "line":
        a, b = np.asarray(seg["start"], float), np.asarray(seg["end"], float)
        d = (b - a) / max(np.linalg.norm(b - a), 1e-300)
        return a, b, d, d
    c, rad = np.asarray(seg["center"], float), float(seg["radius"])
    a0, swp = float(seg["start_angle"]), float(seg["sweep"])
    s = math.copysign(1.0, swp)  # +1: counter-clockwise about the centre
    p = lambda t: c + rad * np.array([math.cos(t), math.sin(t)])  # noqa: E731
    t = lambda t: s * np.array([-math.sin(t), math.cos(t)])  # noqa: E731
    return p(a0), p(a0 + swp), t(a0), t(a0 + swp)


def _points(seg, step=1e-3):
    if seg["type"] == "line":
        a, b = np.asarray(seg["start"], float), np.asarray(seg["end"], float)
        k = max(2, int(np.linalg.norm(b - a) / step) + 2)
        return a + np.linspace(0, 1, k)[:, None] * (b - a)
    c, rad = np.asarray(seg["center"], float), float(seg["radius"])
    a0, swp = float(seg["start_angle"]), float(seg["sweep"])
    k = max(2, int(abs(swp) * rad / step) + 2)
    t = a0 + swp * np.linspace(0, 1, k)
    return c + rad * np.stack([np.cos(t), np.sin(t)], axis=1)


def _length(seg):
    if seg["type"] == "line":
        return float(np.linalg.norm(np.subtract(seg["end"], seg["start"])))
    return float(seg["radius"]) * abs(float(seg["sweep"]))


def _angle(u, v):
    return math.atan2(u[0] * v[1] - u[1] * v[0], u[0] * v[0] + u[1] * v[1])


def problems(scenario: dict, segments: list[dict], length: float) -> list[str]:
    """What is wrong with the path ``segments`` of the scenario mapping (scenario file
    layout: metres, degrees) reported as ``length`` metres; empty when nothing is."""
    out = []
    rho, r = float(scenario["robot"]["min_turn_radius"]), float(scenario["robot"]["radius"])
    pose = {k: (np.array([scenario[k]["x"], scenario[k]["y"]], float),
                math.radians(scenario[k]["heading_deg"])) for k in ("start", "goal")}
    total = sum(_length(s) for s in segments)
    if abs(total - length) > 1e-9 * max(1.0, length):
        out.append(f"segments add up to {total!r} m, reported {length!r} m")
    if not segments:
        if np.linalg.norm(pose["start"][0] - pose["goal"][0]) > JOIN:
            out.append("no segments between different points")
        return out
    heading = lambda d, seg: d * (-1.0 if seg.get("reverse") else 1.0)  # noqa: E731
    prev = None
    for i, seg in enumerate(segments):
        a, b, da, db = _ends(seg)
        if seg["type"] == "arc" and float(seg["radius"]) < rho - 1e-9:
            out.append(f"segment {i}: radius {seg['radius']} below rho {rho}")
        if prev is None:
            p, h = pose["start"]
            if np.linalg.norm(a - p) > JOIN:
                out.append(f"segment 0 starts {np.linalg.norm(a - p):.3g} m from the start")
            hd = heading(da, seg)
            if abs(_angle(hd, (math.cos(h), math.sin(h)))) > ANGLE:
                out.append("the heading at the start is not the start's")
        else:
            pseg, pb, pdb = prev
            if np.linalg.norm(a - pb) > JOIN:
                out.append(f"segments {i - 1} and {i} do not join ({np.linalg.norm(a - pb):.3g} m)")
            if abs(_angle(heading(pdb, pseg), heading(da, seg))) > ANGLE:
                out.append(f"the heading jumps between segments {i - 1} and {i}")
            cusp = bool(pseg.get("reverse")) != bool(seg.get("reverse"))
            turn = abs(_angle(pdb, da))
            if cusp and abs(turn - math.pi) > ANGLE:
                out.append(f"gear changes between {i - 1} and {i} but travel does not reverse")
            if not cusp and turn > ANGLE:
                out.append(f"travel reverses between {i - 1} and {i} without a cusp")
        prev = (seg, b, db)
    seg, b, db = prev
    p, h = pose["goal"]
    if np.linalg.norm(b - p) > JOIN:
        out.append(f"the path ends {np.linalg.norm(b - p):.3g} m from the goal")
    if abs(_angle(heading(db, seg), (math.cos(h), math.sin(h)))) > ANGLE:
        out.append("the heading at the goal is not the goal's")
    pts = np.concatenate([_points(s) for s in segments])
    for k, o in enumerate(scenario.get("obstacles", []), start=1):
        big = max(rho, float(o.get("radius", r)) + r)
        gap = np.hypot(pts[:, 0] - o["x"], pts[:, 1] - o["y"]).min() - big
        if gap < -CLEAR:
            out.append(f"the path enters obstacle {k}'s model circle by {-gap:.3g} m")
    f = scenario.get("field")
    if f and f.get("keep_inside"):
        lo = np.array([f["xmin"] + r, f["ymin"] + r]) - CLEAR
        hi = np.array([f["xmax"] - r, f["ymax"] - r]) + CLEAR
        if np.any(pts < lo) or np.any(pts > hi):
            out.append("the path leaves the kept field")
    return out
