"""An example plugin: a permutation crossover and a selection, registered at import.

Use it with ``hga-jax run SCENARIO.toml --plugin configs/plugins/example_ops.py
--perm-crossover one_point_order --selection truncation``, in a study file with
``plugins = ["../plugins/example_ops.py"]``, or in Python by importing it before
building the settings (docs/operators.md).

Both operators follow :mod:`hga_jax.search.registry`: they work on one pair (the
crossover) or one population (the selection), are pure JAX functions whose shapes
depend on ``n`` (obstacles) and ``P`` (population) only, and take their
randomness from ``key`` (a typed JAX key).
"""
import jax
import jax.numpy as jnp

from hga_jax.search import registry


def one_point_order(key, a, b):
    """One-point order crossover of two permutations ``a, b`` (int32, (n,)).

    A cut ``c`` is drawn uniformly in ``0..n``; child 1 keeps ``a[:c]`` and fills
    positions ``c..n-1`` with the remaining genes in the order they appear in ``b``;
    child 2 is the mirror (``b[:c]``, then the rest in ``a``'s order).
    """
    n = a.shape[0]
    cut = jax.random.randint(key, (), 0, n + 1)
    pos = jnp.arange(n)

    def child(head, other):
        kept = jnp.zeros(n, bool).at[head].set(pos < cut)  # gene -> in the kept head
        rest = other[jnp.argsort(kept[other], stable=True)]  # the other genes first, in order
        return jnp.where(pos < cut, head, rest[jnp.clip(pos - cut, 0, n - 1)])

    return child(a, b), child(b, a)


def truncation(key, fitness):
    """Truncation selection: the better half of the population (by ``fitness`` (P,),
    higher is better) are the parents, each twice, in a random mating order.
    Returns int32 indices (P,) in ``0..P-1``."""
    p = fitness.shape[0]
    better_first = jnp.argsort(-fitness, stable=True)
    parents = better_first[jnp.arange(p) // 2]  # the best twice, the second twice, ...
    return jax.random.permutation(key, parents).astype(jnp.int32)


registry.register("perm_crossover", "one_point_order", one_point_order)
registry.register("selection", "truncation", truncation)
