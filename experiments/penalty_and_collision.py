"""Penalty and collision: how often the paper's Appendix B segment test accepts a best
path that the full test finds colliding, and penalty weights other than 2*pi*R
(``configs/studies/penalty_and_collision.toml``).

Usage: ``python3 experiments/penalty_and_collision.py [--quick] [--out DIR]``
(the same as ``hga-jax study configs/studies/penalty_and_collision.toml``).
"""

import sys

from hga_jax.study.cli import script


def main(argv=None) -> int:
    return script(__file__, argv, __doc__)


if __name__ == "__main__":
    sys.exit(main())
