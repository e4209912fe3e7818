"""The exception types a user may see: bad input, a model mismatch (a bug), a peer
that crashed, and an interruption."""


class ConfigError(ValueError):
    """Bad input: the message is one line naming the file (or source) and key.

    Format: ``"<source>: <key>: <problem>"``, e.g.
    ``"configs/scenarios/x.toml: robot.radius: must be > 0, got -0.1"``.
    """


class ModelMismatchError(RuntimeError):
    """The exact solver's tangent graph and the decoder disagree about a path (a bug in hga-jax): the message names the scenario and both figures."""


class PeerCrashed(RuntimeError):
    """A peer's process died (a crash in its native code, such as OMPL's) again after a
    retry: the message names the peer and says that the study resumes when run again."""


class Interrupted(KeyboardInterrupt):
    """Ctrl-C stopped a job between two blocks of generations; nothing was written.

    The message says where it stopped, e.g. ``"interrupted in batch 1 of 2 after
    12 of 51 generations"``.
    """
