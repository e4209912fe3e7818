"""The paper's car model, the tight rope (``turns = "tight-rope"``, the default).

:mod:`~hga_jax.model.cars.tight_rope.model` holds its car model: paths that turn only on
the pose circles and the obstacles' model circles, searched in the shared turn table
(:mod:`hga_jax.model.turns`) and solved exactly by :mod:`hga_jax.model.exact`.
"""
