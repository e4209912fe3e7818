"""Baselines: the paper's GA against random search (the GA with 0 generations) at equal
evaluations and at equal time, on the scenes of reproduce_paper
(``configs/studies/baselines.toml``).

Usage: ``python3 experiments/baselines.py [--quick] [--out DIR]``
(the same as ``hga-jax study configs/studies/baselines.toml``).
"""

import sys

from hga_jax.study.cli import script


def main(argv=None) -> int:
    return script(__file__, argv, __doc__)


if __name__ == "__main__":
    sys.exit(main())
