"""Reproduce the paper: its GA settings on the bundled RoboCup scene and on obstructed
9-obstacle scenes; Fig. 4 and Fig. 5 analogues, a table beside the paper's claims,
and the hit rate within 50 generations (``configs/studies/reproduce_paper.toml``).

Usage: ``python3 experiments/reproduce_paper.py [--quick] [--out DIR]``
(the same as ``hga-jax study configs/studies/reproduce_paper.toml``).
"""

import sys

from hga_jax.study.cli import script


def main(argv=None) -> int:
    return script(__file__, argv, __doc__)


if __name__ == "__main__":
    sys.exit(main())
