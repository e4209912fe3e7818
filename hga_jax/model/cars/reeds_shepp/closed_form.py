"""The shortest path of a Reeds-Shepp car between two poses, in closed form.

A Reeds-Shepp car drives forward or backward and turns with radius at least ``rho``
(m) either way. Reeds and Shepp (1990) showed that its shortest path between two poses
is one of 48 *words* in nine families: CSC, C|C|C, C|CC, CC|C, CCu|CuC, C|CuCu|C,
C|C(pi/2)SC, CSC(pi/2)|C and C|C(pi/2)SC(pi/2)|C (``C`` an arc of radius ``rho``,
``S`` a line, ``|`` a cusp, where the car stops and changes gear; ``Cu`` two arcs of
equal length, ``C(pi/2)`` a quarter turn). The formulas of the words are in
:mod:`hga_jax.model.cars.reeds_shepp.words`; this module moves the problem into the
start's frame, keeps the shortest word and turns words into poses and segments.

Conventions: metres and radians; a pose is ``(x, y, heading)`` with the heading
counter-clockwise from +x (any value: headings are taken modulo 2 pi). A word's
pieces are arcs ``L`` (turning left, counter-clockwise relative to the car's
heading) and ``R`` (right) of radius ``rho``, and lines ``S``, each with a signed
length in metres: positive when driven forward, negative when driven backward.
Cusps are where consecutive pieces' signs differ. A word is named by its pieces and
gears, e.g. ``"L+R-L+"`` (a forward left arc, a backward right arc, a forward left
arc: family C|C|C). Pure float64 Python, one pose pair at a time.
"""
from __future__ import annotations

import math
from typing import Any, NamedTuple

from hga_jax.model.cars.reeds_shepp.words import solutions

Pose = tuple[float, float, float]
"""``(x, y, heading)``: metres, metres, radians counter-clockwise from +x."""

TINY = 1e-12  # m: a piece shorter than this is left out of the segments

FAMILIES = {  # cusp pattern of a word (see Word.family) -> the paper's family name
    "CSC": "CSC", "C|C|C": "C|C|C", "C|CC": "C|CC", "CC|C": "CC|C",
    "CC|CC": "CCu|CuC", "C|CC|C": "C|CuCu|C", "C|CSC": "C|C(pi/2)SC",
    "CSC|C": "CSC(pi/2)|C", "C|CSC|C": "C|C(pi/2)SC(pi/2)|C",
}


class Word(NamedTuple):
    """One Reeds-Shepp word between two poses.

    word: kinds and gears, e.g. ``"L+R-S-L-"`` (gears come from the word, so a piece
      of length zero still has one). pieces: ``(kind in "LRS", signed length in m)``
      in travel order, negative when driven backward. length: total length (m).
    """

    word: str
    pieces: tuple[tuple[str, float], ...]
    length: float

    @property
    def family(self) -> str:
        """The word's family in the paper's notation, e.g. ``"C|C(pi/2)SC"``."""
        pattern = ""
        for i in range(0, len(self.word), 2):
            if i and self.word[i + 1] != self.word[i - 1]:
                pattern += "|"
            pattern += "S" if self.word[i] == "S" else "C"
        return FAMILIES[pattern]


def candidates(p: Pose, q: Pose, rho: float) -> list[Word]:
    """Every one of the 48 words that exists from pose ``p`` to pose ``q`` with turning
    radius ``rho`` (m), shortest first; each word at most once, with arcs of at most half
    a turn (a longer arc is never part of a shortest path)."""
    if not rho > 0.0:
        raise ValueError(f"rho: must be positive, got {rho!r}")
    rho = float(rho)
    dx, dy = float(q[0]) - float(p[0]), float(q[1]) - float(p[1])
    c, s = math.cos(float(p[2])), math.sin(float(p[2]))
    x, y = (c * dx + s * dy) / rho, (c * dy - s * dx) / rho
    phi = math.remainder(float(q[2]) - float(p[2]), 2.0 * math.pi)
    words = []
    for kinds, gears, lengths in solutions(x, y, phi):
        words.append(Word("".join(k + g for k, g in zip(kinds, gears)),
                          tuple((k, rho * a) for k, a in zip(kinds, lengths)),
                          rho * sum(abs(a) for a in lengths)))
    words.sort(key=lambda w: w.length)
    return words


def shortest(p: Pose, q: Pose, rho: float) -> Word:
    """The shortest Reeds-Shepp word from pose ``p`` to pose ``q`` with turning radius
    ``rho`` (m). Ties between words: any shortest one. ``p == q`` gives length 0."""
    return candidates(p, q, rho)[0]


def length(p: Pose, q: Pose, rho: float) -> float:
    """The Reeds-Shepp distance (m) from ``p`` to ``q``: the length of :func:`shortest`."""
    return shortest(p, q, rho).length


def _drive(x: float, y: float, h: float, kind: str, d: float, rho: float) -> Pose:
    """The pose after driving piece ``(kind, d)`` (signed length, m) from ``(x, y, h)``."""
    if kind == "S":
        return x + d * math.cos(h), y + d * math.sin(h), h
    a = d / rho if kind == "L" else -d / rho  # heading change, counter-clockwise
    # The centre is rho to the car's side; the car turns by ``a`` around it.
    side = 1.0 if kind == "L" else -1.0
    return (x + side * rho * (math.sin(h + a) - math.sin(h)),
            y - side * rho * (math.cos(h + a) - math.cos(h)), h + a)


def integrate(p: Pose, pieces, rho: float) -> Pose:
    """The pose (heading in ``[-pi, pi]``) reached by driving ``pieces`` (``(kind,
    signed length in m)``, as in :attr:`Word.pieces`) from pose ``p`` with turning
    radius ``rho`` (m): exact arc and line updates, no stepping."""
    x, y, h = float(p[0]), float(p[1]), float(p[2])
    for kind, d in pieces:
        x, y, h = _drive(x, y, h, kind, float(d), rho)
    return x, y, math.remainder(h, 2.0 * math.pi)


def segments(p: Pose, pieces, rho: float) -> list[dict[str, Any]]:
    """The path of ``pieces`` (as in :func:`integrate`) from pose ``p`` as segments of
    the result files (:attr:`hga_jax.model.path.Path.segments`), in travel order.

    Arcs: ``{"type": "arc", "center": [cx, cy], "radius": rho, "start_angle": angle
    of the start point seen from the centre, "sweep": signed angle the point sweeps
    around the centre, positive counter-clockwise}`` (m, rad): a left arc driven
    forward and a right arc driven backward sweep counter-clockwise. Lines: ``{"type":
    "line", "start": [x, y], "end": [x, y]}`` (m). A piece driven backward also has
    ``"reverse": True``. Pieces shorter than 1e-12 m are left out.
    """
    x, y, h = float(p[0]), float(p[1]), float(p[2])
    out: list[dict[str, Any]] = []
    for kind, d in pieces:
        d = float(d)
        nx, ny, nh = _drive(x, y, h, kind, d, rho)
        if abs(d) >= TINY:
            if kind == "S":
                seg: dict[str, Any] = {"type": "line", "start": [x, y], "end": [nx, ny]}
            else:
                side = 1.0 if kind == "L" else -1.0
                cx, cy = x - side * rho * math.sin(h), y + side * rho * math.cos(h)
                seg = {"type": "arc", "center": [cx, cy], "radius": rho,
                       "start_angle": math.atan2(y - cy, x - cx), "sweep": side * d / rho}
            if d < 0.0:
                seg["reverse"] = True
            out.append(seg)
        x, y, h = nx, ny, nh
    return out
