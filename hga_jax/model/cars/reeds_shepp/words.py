"""The 48 words of Reeds and Shepp (1990) in closed form, for a unit turning radius.

Everything here is measured in turning radii: the start pose is the origin with
heading 0, the goal is ``(x, y, phi)`` (``phi`` in radians, counter-clockwise), and a
piece's length is its arc angle (rad) for a turn and its length for a line. A piece
is a kind, ``L`` (turning left, counter-clockwise relative to the car's heading),
``R`` (right) or ``S`` (straight), and a gear, ``+`` (forward) or ``-`` (backward);
its signed length carries the gear. :mod:`hga_jax.model.cars.reeds_shepp.closed_form` scales the
results to metres.

**Chain of circle centres.** A car at heading ``h`` has its left turning circle
centred at ``left(h) = (-sin h, cos h)`` from it and its right one at ``-left(h)``.
The centre of the circle the car is on stays put along an arc; switching from a left
circle to a right one at heading ``h`` moves it by ``-2 left(h)`` (by ``+2 left(h)``
from right to left, whatever the gears), and a line of signed length ``u`` at heading
``h`` moves it by ``u (cos h, sin h)``. So the vector ``D`` from the start's first
circle to the goal's last circle is a sum of such steps; every heading in it is the
first arc's angle ``t`` plus a part fixed by the middle pieces, hence
``D = rotate(t) w``, where ``w`` is the same chain walked with ``t = 0``. Each base
word below solves ``|w| = |D|`` for its middle pieces, then ``t`` is the angle from
``w`` to ``D`` and the last arc is what is left to reach the goal's heading.

**Base words** (all start with a forward left arc ``t``; ``u`` is the unknown middle
length, ``d = |D|``), with the paper's family names:

- ``L+S+L+`` (CSC): ``w = (u, 0)``, so ``u = d``.
- ``L+S+R+`` (CSC): ``w = (u, -2)``, ``u = sqrt(d^2 - 4)``.
- ``L+R-L+`` (C|C|C) and ``L+R-L-`` (C|CC): ``|w| = 4 sin(|u|/2)``,
  ``u = -2 asin(d/4)``.
- ``L+R+L-R-`` (CCu|CuC, middle arcs ``u, -u``): ``|w| = 2 (2 cos u - 1)``,
  ``cos u = (2 + d)/4`` (the root Reeds and Shepp give, ``u <= pi/3``).
- ``L+R-L-R+`` (C|CuCu|C, middle arcs ``u, u``): ``|w|^2 = 4 (5 - 4 cos u)``,
  ``cos u = (20 - d^2)/16`` with ``|u| <= pi/2``.
- ``L+R-S-L-`` and ``L+R-S-R-`` (C|C(pi/2)SC, the right arc a quarter turn):
  ``|w|^2 = 4 + (2 - u)^2`` and ``|w| = 2 - u``, with ``u <= 0``.
- ``L+R-S-L-R+`` (C|C(pi/2)SC(pi/2)|C): ``|w|^2 = 4 + (4 - u)^2``, ``u <= 0``.

Arcs ``t`` and the last arc are kept within half a turn (no longer arc is ever part
of a shortest path). Three symmetries give the other words from the goal mapped by:
*time flip* ``(-x, y, -phi)``: every gear reversed; *reflection* ``(x, -y, -phi)``:
``L`` and ``R`` swapped; *backwards* ``(x cos phi + y sin phi, x sin phi - y cos phi,
phi)``: the pieces in reverse order (from C|CC this gives CC|C, from C|C(pi/2)SC it
gives CSC(pi/2)|C). Each base word under each of its symmetries is one of the 48
words, and each of the 48 arises exactly once.
"""
from __future__ import annotations

import math
from typing import Callable, Iterator, NamedTuple

TWO_PI = 2.0 * math.pi
HALF_PI = 0.5 * math.pi
TOL = 1e-12  # radii or rad: rounding allowed past a word's bounds (clamped back onto them)
_SWAP_TURN = str.maketrans("LR", "RL")  # reflection
_SWAP_GEAR = str.maketrans("+-", "-+")  # time flip

Middle = Callable[[float], "tuple[float, ...] | None"]
"""The middle pieces' signed lengths of a base word from ``d``, or None if it does not exist."""


def _csc_same(d: float):
    """L+S+L+: the line is the centres' distance."""
    return (d,)


def _csc_opposite(d: float):
    """L+S+R+: the line of the inner tangent, ``sqrt(d^2 - 4)``."""
    if d < 2.0 - TOL:
        return None
    return (math.sqrt(max(d * d - 4.0, 0.0)),)


def _ccc(d: float):
    """L+R-L: the middle arc, driven backward, of the circle touching both ends."""
    if d > 4.0 + TOL:
        return None
    return (-2.0 * math.asin(min(d / 4.0, 1.0)),)


def _cc_u_cc(d: float):
    """L+R+L-R-: two middle arcs of equal length, ``cos u = (2 + d)/4``."""
    c = (2.0 + d) / 4.0
    if c > 1.0 + TOL:
        return None
    u = math.acos(min(c, 1.0))
    return (u, -u)


def _c_cu_cu_c(d: float):
    """L+R-L-R+: two backward middle arcs of equal length, ``cos u = (20 - d^2)/16``."""
    c = (20.0 - d * d) / 16.0
    if not -TOL <= c <= 1.0 + TOL:
        return None
    u = -math.acos(min(max(c, 0.0), 1.0))
    return (u, u)


def _ccsc_same(d: float):
    """L+R-S-L-: a backward quarter turn, then the line ``2 - sqrt(d^2 - 4) <= 0``."""
    if d * d < 8.0 - TOL:
        return None
    return (-HALF_PI, min(2.0 - math.sqrt(d * d - 4.0), 0.0))


def _ccsc_opposite(d: float):
    """L+R-S-R-: a backward quarter turn, then the line ``2 - d <= 0``."""
    if d < 2.0 - TOL:
        return None
    return (-HALF_PI, min(2.0 - d, 0.0))


def _ccscc(d: float):
    """L+R-S-L-R+: quarter turn, line ``4 - sqrt(d^2 - 4) <= 0``, quarter turn (backward)."""
    if d * d < 20.0 - TOL:
        return None
    return (-HALF_PI, min(4.0 - math.sqrt(d * d - 4.0), 0.0), -HALF_PI)


class Base(NamedTuple):
    """A base word: its kinds and gears, its middle pieces, and whether its backwards
    form is another word (the other two symmetries always are)."""

    kinds: str
    gears: str
    middle: Middle
    backwards: bool


BASES = (
    Base("LSL", "+++", _csc_same, False),
    Base("LSR", "+++", _csc_opposite, False),
    Base("LRL", "+-+", _ccc, False),
    Base("LRL", "+--", _ccc, True),
    Base("LRLR", "++--", _cc_u_cc, False),
    Base("LRLR", "+--+", _c_cu_cu_c, False),
    Base("LRSL", "+---", _ccsc_same, True),
    Base("LRSR", "+---", _ccsc_opposite, True),
    Base("LRSLR", "+---+", _ccscc, False),
)


def _arc(a: float, gear: str) -> float | None:
    """The arc of ``gear`` that turns by ``a`` (mod 2 pi), or None when it is longer than
    half a turn; within ``TOL`` of 0 on the wrong side it is 0."""
    g = 1.0 if gear == "+" else -1.0
    m = math.fmod(g * a, TWO_PI)
    if m < 0.0:
        m += TWO_PI
    if m >= TWO_PI - TOL:
        return 0.0 * g
    return g * m if m <= math.pi + TOL else None


def _solve(base: Base, x: float, y: float, phi: float, c: float, s: float):
    """Signed lengths of ``base``'s pieces from the origin to ``(x, y, phi)`` (``c, s``:
    cos and sin of ``phi``), or None when the word does not exist there."""
    last = base.kinds[-1]
    dx, dy = (x - s, y + c - 1.0) if last == "L" else (x + s, y - c - 1.0)
    middle = base.middle(math.hypot(dx, dy))
    if middle is None:
        return None
    wx = wy = h = 0.0
    on = "L"
    for kind, a in zip(base.kinds[1:-1], middle):
        if kind == "S":
            wx, wy = wx + a * math.cos(h), wy + a * math.sin(h)
            continue
        if kind != on:
            k = 2.0 if kind == "R" else -2.0
            wx, wy, on = wx + k * math.sin(h), wy - k * math.cos(h), kind
        h += a if kind == "L" else -a
    if last != on:
        k = 2.0 if last == "R" else -2.0
        wx, wy = wx + k * math.sin(h), wy - k * math.cos(h)
    t = _arc(math.atan2(dy, dx) - math.atan2(wy, wx), base.gears[0])
    if t is None:
        return None
    h += t
    v = _arc(phi - h if last == "L" else h - phi, base.gears[-1])
    if v is None:
        return None
    return (t, *middle, v)


def solutions(x: float, y: float, phi: float) -> Iterator[tuple[str, str, tuple[float, ...]]]:
    """Every word that exists from the origin to ``(x, y, phi)`` (radii, rad), as
    ``(kinds, gears, signed lengths)``, e.g. ``("LRL", "+-+", (t, u, v))``. Gears come
    from the word, so a piece of length zero still has one."""
    c, s = math.cos(phi), math.sin(phi)
    xb, yb = x * c + y * s, x * s - y * c
    for base in BASES:
        for backwards in ((False, True) if base.backwards else (False,)):
            gx, gy = (xb, yb) if backwards else (x, y)
            for flip in (False, True):
                for mirror in (False, True):
                    turned = flip != mirror  # the goal's heading is negated
                    found = _solve(base, -gx if flip else gx, -gy if mirror else gy,
                                   -phi if turned else phi, c, -s if turned else s)
                    if found is None:
                        continue
                    kinds, gears = base.kinds, base.gears
                    if mirror:
                        kinds = kinds.translate(_SWAP_TURN)
                    if flip:
                        gears = gears.translate(_SWAP_GEAR)
                        found = tuple(-a for a in found)
                    if backwards:
                        kinds, gears, found = kinds[::-1], gears[::-1], found[::-1]
                    yield kinds, gears, found

