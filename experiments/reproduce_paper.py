"""Reproduce the paper: its GA settings on the bundled RoboCup scene and on obstructed
9-obstacle scenes; Fig. 4 and Fig. 5 analogues, a table beside the paper's claims,
and the hit rate within 50 generations (``configs/studies/reproduce_paper.toml``).

Usage: ``python3 experiments/reproduce_paper.py [--quick] [--out DIR]``
(the same as ``hga-jax study configs/studies/reproduce_paper.toml``).
"""
import os
import sys

from hga_jax.study.cli import script

CONFIG = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "configs", "studies",
                      "reproduce_paper.toml")


def main(argv=None) -> int:
    return script(CONFIG, argv, __doc__.splitlines()[0])


if __name__ == "__main__":
    sys.exit(main())
