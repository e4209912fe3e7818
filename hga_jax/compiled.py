"""Compiled programs, kept in memory and on disk, so a repeated command skips its compile.

A program here is ``jax.jit(fn).lower(*args).compile()``: what a GA batch or the
float64 decoder runs. :func:`program` returns the one for a key, from (in order)

1. this process's recent programs (a study reuses them across scenes of one size);
2. the program folder (:func:`enable_compilation_cache`), where a compiled program
   is stored as JAX's serialised executable; loading one skips both tracing and
   XLA's compile, which JAX's own compilation cache does not (it skips only the
   compile: tracing a GA generation costs 1-2 s);
3. a fresh compile, then stored there.

The folder is on by default: where nothing chose (neither
:func:`enable_compilation_cache` nor :func:`use_folder` was called), the first program
a process asks for turns it on, in the folder ``enable_compilation_cache()`` picks
(``$HGA_JAX_CACHE_DIR``, else ``~/.cache/hga-jax/programs``), unless
``HGA_JAX_CACHE_DIR=off`` or JAX's own compilation cache was configured (a
``jax_compilation_cache_dir``, or ``jax_enable_compilation_cache`` turned off): then
programs are kept in memory only. ``enable_compilation_cache(False)`` turns it off.

A stored program is found only by a key naming everything it was built from: the
caller's key (settings, shapes, dtypes), the hga_jax source (a hash of every module
file), the JAX and jaxlib versions and flags, the backend, its devices and this machine's
processor (an executable built for one CPU may not run on another). A stale,
unreadable or foreign file is compiled again and replaced, never trusted. Keys that
name a user's registered operator (code outside hga_jax) are kept in memory only.
"""
from __future__ import annotations

import contextlib
import hashlib
import os
import pickle
import platform
import tempfile
import warnings
from typing import Any, Callable, Iterator

_RECENT: dict[str, Any] = {}
_RECENT_KEEP = 16
_UNSET = object()  # no one chose a folder yet: the first program picks the default
_FOLDER: list[Any] = [_UNSET]
_KEEP_BYTES = 512 * 2**20  # the folder's size; the least recently used programs go first
_FINGERPRINT: list[str] = []
_TALLY: dict[str, dict[str, int]] = {}
WAYS = ("compiled", "loaded", "reused")
"""How :func:`program` found a program: compiled now, loaded from the program folder,
or reused from this process's recent programs."""


def use_folder(folder: str | None) -> None:
    """Store compiled programs in ``folder`` (created by the caller); None: memory only."""
    _FOLDER[0] = folder


@contextlib.contextmanager
def memory_only() -> Iterator[None]:
    """Within the block, programs are kept in memory only (``--no-cache``); the folder
    chosen before (or none chosen yet) comes back after it."""
    before = _FOLDER[0]
    use_folder(None)
    try:
        yield
    finally:
        _FOLDER[0] = before


def folder() -> str | None:
    """The program folder in use (None: programs are kept in memory only, or no program
    was asked for yet and nothing chose: the first one picks the default)."""
    return None if _FOLDER[0] is _UNSET else _FOLDER[0]


def program(key: tuple, lower: Callable[[], Any], *, disk: bool = True,
            options: dict[str, Any] | None = None) -> Any:
    """The compiled program for ``key``; ``lower()`` returns the ``jax.stages.Lowered``
    to compile when none is kept. ``key`` must determine the program: a tuple of
    values whose ``repr`` is stable across processes (numbers, strings, shapes,
    frozen settings). ``disk=False`` keeps it in memory only. ``options``: XLA
    compiler options of this program (part of its key), e.g.
    :data:`hga_jax.jax_compat.SEARCH_COMPILER_OPTIONS`."""
    import jax

    from hga_jax.jax_compat import compile_with_options

    options = dict(options or {})
    if disk and _FOLDER[0] is _UNSET:
        _by_default()
    text = repr((key, jax.config.jax_enable_x64, jax.config.jax_threefry_partitionable)
                + ((tuple(sorted(options.items())),) if options else ()))
    found = _RECENT.pop(text, None)
    path, way = None, "reused"
    if found is None:
        way = "loaded"
        if disk and _FOLDER[0] is not None and " at 0x" not in text:
            name = hashlib.sha256((_fingerprint() + "\n" + text).encode()).hexdigest()[:32]
            path = os.path.join(_FOLDER[0], name + ".jaxprog")
            found = _load(path)
        if found is None:
            found, way = compile_with_options(lower, options), "compiled"
            if path is not None and not _jax_cache_on():
                _store(path, found)
    kind = key[0] if key and isinstance(key[0], str) else "program"
    counts = _TALLY.setdefault(kind, dict.fromkeys(WAYS, 0))
    counts[way] += 1
    _RECENT[text] = found
    while len(_RECENT) > _RECENT_KEEP:
        _RECENT.pop(next(iter(_RECENT)))
    return found


def enable_compilation_cache(path: str | bool | None = None,
                             on_error: Callable[[str], None] | None = None) -> str | None:
    """Keep compiled programs on disk, so a repeated run skips its compile.

    ``path`` defaults to ``$HGA_JAX_CACHE_DIR``, else
    ``$XDG_CACHE_HOME/hga-jax/programs`` (``~/.cache/hga-jax/programs``);
    ``HGA_JAX_CACHE_DIR=off`` disables it, and so does ``path=False`` (programs are
    then kept in memory only; ``True`` is the default folder). The GA's and the
    decoder's programs are stored there (:func:`program`). It is on by default (the
    module doc says when not): call this to choose another folder, or with ``False``
    to turn it off. Returns the folder used, or None. A folder that cannot be created
    or written only costs compile time: ``on_error`` (default :func:`warnings.warn`)
    is told why, in one line.
    """
    if path is False:
        use_folder(None)
        return None
    if path is True:
        path = None
    env = os.environ.get("HGA_JAX_CACHE_DIR")
    where = path if path is not None else env
    if where in ("", "off"):
        use_folder(None)
        return None
    if where is None:
        base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        where = os.path.join(base, "hga-jax", "programs")
    named = "HGA_JAX_CACHE_DIR=" if path is None and env is not None else ""
    problem = None
    try:
        os.makedirs(where, exist_ok=True)
        if not os.access(where, os.W_OK | os.X_OK):
            problem = "not writable"
    except OSError as e:
        problem = e.strerror or str(e)
    if problem:
        use_folder(None)
        (on_error or warnings.warn)(f"{named}{where}: cannot keep compiled programs there "
                                    f"({problem}); compiling without a cache")
        return None
    use_folder(where)
    return where


def _by_default() -> None:
    """The first program of a process where nothing chose a folder: the default one
    (:func:`enable_compilation_cache`), unless JAX's own compilation cache was
    configured (a folder named, or the cache turned off): then memory only."""
    import jax

    use_folder(None)
    if jax.config.jax_compilation_cache_dir or not jax.config.jax_enable_compilation_cache:
        return
    enable_compilation_cache()


def _jax_cache_on() -> bool:
    """Whether JAX's own compilation cache is set: an executable it loaded from there
    does not serialise whole on the CPU (a stored copy fails with "Function ... not
    found"), so nothing is stored while it is on."""
    import jax

    return bool(jax.config.jax_compilation_cache_dir) and jax.config.jax_enable_compilation_cache


def tally() -> dict[str, dict[str, int]]:
    """Programs asked for so far in this process, per kind (the key's first element:
    ``"ga-block"`` a GA batch, ``"decode64"`` the float64 decoder) and per way found
    (:data:`WAYS`); a copy."""
    return {kind: dict(counts) for kind, counts in _TALLY.items()}


def tally_since(before: dict[str, dict[str, int]]) -> dict[str, dict[str, int]]:
    """:func:`tally` minus an earlier ``tally()``, kinds with nothing new left out."""
    out = {}
    for kind, counts in tally().items():
        old = before.get(kind, {})
        new = {way: counts[way] - old.get(way, 0) for way in WAYS}
        if any(new.values()):
            out[kind] = new
    return out


def forget() -> None:
    """Drop the programs kept in memory (the folder is left as it is)."""
    _RECENT.clear()


def _load(path: str) -> Any | None:
    from hga_jax.jax_compat import load_executable

    try:
        with open(path, "rb") as fh:
            blob = fh.read()
        found = load_executable(*pickle.loads(blob))
    except FileNotFoundError:
        return None
    except Exception:  # noqa: BLE001 - a bad file only costs a compile
        return None
    try:
        os.utime(path)  # recently used: pruned last
    except OSError:
        pass
    return found


def _store(path: str, compiled: Any) -> None:
    """Write ``compiled`` to ``path`` atomically; a folder that cannot take it is skipped."""
    from hga_jax.jax_compat import save_executable

    where = os.path.dirname(path)
    try:
        blob = pickle.dumps(save_executable(compiled), protocol=pickle.HIGHEST_PROTOCOL)
        fd, tmp = tempfile.mkstemp(dir=where, prefix=".tmp-", suffix=".jaxprog")
        with os.fdopen(fd, "wb") as fh:
            fh.write(blob)
        os.replace(tmp, path)
        _prune(where)
    except Exception:  # noqa: BLE001 - not storing only costs the next compile
        return


def _prune(where: str) -> None:
    """Remove the least recently used programs while the folder holds more than
    :data:`_KEEP_BYTES` of them (a GA program is 0.5-5 MB)."""
    files = []
    for f in os.listdir(where):
        if f.endswith(".jaxprog") and not f.startswith("."):
            try:
                st = os.stat(os.path.join(where, f))
            except OSError:
                continue
            files.append((st.st_mtime, st.st_size, os.path.join(where, f)))
    total = sum(size for _, size, _ in files)
    for _, size, path in sorted(files):
        if total <= _KEEP_BYTES:
            break
        try:
            os.remove(path)
            total -= size
        except OSError:
            pass


def _fingerprint() -> str:
    """What every stored program depends on besides its key: hga_jax's source, JAX's
    versions and flags, the backend and its devices, and the processor."""
    if not _FINGERPRINT:
        import jax
        import jaxlib

        src = hashlib.sha256()
        root = os.path.dirname(os.path.abspath(__file__))
        for base, dirs, files in sorted(os.walk(root)):
            dirs.sort()
            for f in sorted(files):
                if f.endswith(".py"):
                    src.update(f.encode())
                    with open(os.path.join(base, f), "rb") as fh:
                        src.update(fh.read())
        backend = jax.devices()[0].client
        parts = [src.hexdigest(), jax.__version__, jaxlib.__version__, backend.platform,
                 backend.platform_version, repr([d.device_kind for d in jax.devices()]),
                 str(jax.process_count()), os.environ.get("XLA_FLAGS", ""),
                 platform.machine(), _processor()]
        _FINGERPRINT.append("\n".join(parts))
    return _FINGERPRINT[0]


def _processor() -> str:
    """This machine's processor model and features (an executable built for one
    processor may use instructions another lacks)."""
    try:
        with open("/proc/cpuinfo") as fh:
            lines = [ln for ln in fh if ln.startswith(("model name", "flags", "Features",
                                                        "CPU part"))]
        return hashlib.sha256("".join(sorted(set(lines))).encode()).hexdigest()
    except OSError:
        return platform.processor() or platform.platform()
