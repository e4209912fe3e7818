"""Result folders: atomic files with the usual mode, and one result per folder.

A result folder holds the files of one result only: ``result.json`` and, from
``run``, ``history.csv``; the plots ``path.png`` and ``convergence.png``; and the
redrawn paths ``path_run<K>.png`` of ``hga-jax plot`` and the poses
``poses.csv``, ``poses.json`` (``poses_run<K>.*``) of ``hga-jax export``, and the
``partial.npz`` of an interrupted run (its finished runs, for ``--resume``), which
belong to the result beside them. Writing a result into a
folder that holds any of these needs ``force``; the files of the new result
replace them and the ones it does not write are removed, so a folder never
mixes two results. Other files in the folder are left alone.

Every file is written through a temporary file in the same folder and renamed
into place (never half a file), with mode ``0666`` less the process umask (the
mode ``open`` would give).
"""
from __future__ import annotations

import csv
import json
import os
import re
import tempfile
from typing import Any, Callable, Mapping

from hga_jax.errors import ConfigError

RESULT_FILES = ("result.json", "history.csv", "path.png", "convergence.png", "partial.npz")
_REDRAWN = re.compile(r"path_run\d+\.png|poses(_run\d+)?\.(csv|json)")  # plot's, export's


def is_result_file(name: str) -> bool:
    """Whether ``name`` (a file name, no folder) is one of the files a result writes."""
    return name in RESULT_FILES or bool(_REDRAWN.fullmatch(name))


def result_files_in(folder: str) -> list[str]:
    """Names of the result files already in ``folder`` (sorted; none if it does not exist)."""
    try:
        names = os.listdir(folder)
    except (FileNotFoundError, NotADirectoryError):
        return []
    return sorted(n for n in names if is_result_file(n) and os.path.isfile(os.path.join(folder, n)))


def check_folder(folder: str, force: bool) -> None:
    """Raise :class:`ConfigError` unless a new result may be written to ``folder``.

    Refused: a path that is not a folder, a folder (or nearest existing parent)
    that cannot be written, and, without ``force``, a folder that already holds a
    result's files. Creates nothing, so a run that is refused or interrupted
    leaves no trace.
    """
    writable_folder(folder)
    old = result_files_in(folder)
    if old and not force:
        raise ConfigError(f"{folder}: output folder: already holds a result ({', '.join(old)}); "
                          "use --force (force=True in Python) to replace it, or another folder")


def writable_folder(folder: str) -> None:
    """Raise :class:`ConfigError` unless ``folder`` is a folder, or can be made, that can
    be written: the rule of every command that writes a folder. Creates nothing."""
    if os.path.exists(folder) and not os.path.isdir(folder):
        raise ConfigError(f"{folder}: output folder: exists and is a file, not a folder")
    parent = os.path.abspath(folder)
    while not os.path.exists(parent):
        parent = os.path.dirname(parent)
    if not os.path.isdir(parent):
        raise ConfigError(f"{folder}: output folder: {parent} is a file, not a folder, so "
                          "nothing can be made under it")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise ConfigError(f"{folder}: output folder: {parent} is not writable")


Writer = Callable[[Any], None]


def write_result(folder: str, files: Mapping[str, tuple[Writer, bool]],
                 force: bool) -> list[str]:
    """Write one result's ``files`` (name -> (writer, binary)) into ``folder``.

    Checks the folder first (:func:`check_folder`), creates it, writes every file
    atomically, then removes the result files of an earlier result that this one
    does not write. Returns the paths written, in the order given.
    """
    check_folder(folder, force)
    os.makedirs(folder, exist_ok=True)
    written = []
    for name, (write, binary) in files.items():
        path = os.path.join(folder, name)
        atomic_write(path, write, binary)
        written.append(path)
    for name in result_files_in(folder):
        if name not in files:
            os.unlink(os.path.join(folder, name))
    return written


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def atomic_write(path: str, write: Writer, binary: bool = False) -> None:
    """Write ``path`` through a temporary file in its folder, then rename it into place.

    ``write(fh)`` fills the file (text with ``newline=""``, or bytes when ``binary``).
    The file gets mode ``0666 & ~umask``, like a file created by ``open``.
    """
    folder = os.path.dirname(os.path.abspath(path))
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".tmp-", suffix="-" + os.path.basename(path))
    try:
        os.fchmod(fd, 0o666 & ~_umask())
        with os.fdopen(fd, "wb" if binary else "w", **({} if binary else {"newline": ""})) as fh:
            write(fh)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise


def write_file(path: str, write: Writer, binary: bool = False) -> None:
    """:func:`atomic_write` after creating the file's parent folders."""
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    atomic_write(path, write, binary)


def write_json(path: str, data: Any) -> None:
    """Write ``data`` as strict JSON, atomically."""
    write_file(path, json_writer(data))


def write_csv(path: str, rows: list[dict[str, Any]]) -> None:
    """Write ``rows`` (dicts with the same keys) as CSV with a header, atomically."""
    write_file(path, csv_writer(rows))


def json_writer(data: Any) -> Writer:
    """A writer of ``data`` as JSON (strict: no NaN or infinity)."""
    return lambda fh: json.dump(data, fh, indent=1, allow_nan=False)


def csv_writer(rows: list[dict[str, Any]]) -> Writer:
    """A writer of ``rows`` (dicts with the same keys) as CSV with a header."""
    def write(fh) -> None:
        writer = csv.DictWriter(fh, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)

    return write


def figure_writer(fig: Any, dpi: int = 140, format: str = "png") -> Writer:
    """A writer of a matplotlib figure as PNG (or ``format``: ``"pdf"``, ``"svg"``),
    cropped to what is drawn. A figure with constrained layout already fits its page:
    its layout is worked out once, on the first write, and then kept (matplotlib would
    work it out again on every write, twice when cropping), so each format is drawn
    once."""
    from matplotlib.layout_engine import PlaceHolderLayoutEngine

    def write(fh) -> None:
        if not fix_layout(fig) and not isinstance(fig.get_layout_engine(),
                                                  PlaceHolderLayoutEngine):
            fig.savefig(fh, dpi=dpi, format=format, bbox_inches="tight", pad_inches=0.05)
            return
        fig.savefig(fh, dpi=dpi, format=format)

    return write


def fix_layout(fig: Any) -> bool:
    """Work out a constrained layout once and keep it (the layout :func:`figure_writer`
    writes); False, and nothing done, for a figure without one."""
    from matplotlib.layout_engine import ConstrainedLayoutEngine

    if not isinstance(fig.get_layout_engine(), ConstrainedLayoutEngine):
        return False
    fig.draw_without_rendering()
    fig.set_layout_engine("none")  # the positions just found stay
    return True
