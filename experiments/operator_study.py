"""Operator study: upper crossover (CX, PMX, OX1) x upper mutation (inversion, exchange),
positional labels against labels bound to the obstacle, roulette against tournament,
elitism, and a pc/pm grid, over clutter and obstructed scene families
(``configs/studies/operator_study.toml``).

Usage: ``python3 experiments/operator_study.py [--quick] [--out DIR]``
(the same as ``hga-jax study configs/studies/operator_study.toml``).
"""

import sys

from hga_jax.study.cli import script


def main(argv=None) -> int:
    return script(__file__, argv, __doc__)


if __name__ == "__main__":
    sys.exit(main())
