"""The one exception type a user should ever see from bad input."""


class ConfigError(ValueError):
    """Bad input: the message is one line naming the file (or source) and key.

    Format: ``"<source>: <key>: <problem>"``, e.g.
    ``"configs/scenarios/x.toml: robot.radius: must be > 0, got -0.1"``.
    """


class ModelMismatchError(RuntimeError):
    """The exact solver's tangent graph and the decoder disagree about a path (a bug in hga-jax): the message names the scenario and both figures."""
