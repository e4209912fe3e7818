"""The ``scattered`` scene family (held-out scenes for the search): robots, obstacle
sizes and fields that vary, walls in about half of the scenes, poses that may hug a wall
(seeded, blocked and solvable: tests/test_held_out_generators.py)."""
import numpy as np
import pytest
from test_held_out_generators import pool as held_out_pool

from hga_jax.host.config import scenario_from_dict

@pytest.fixture(scope="module")
def pool():
    """24 scenes: n in (6, 12), two seeds, six each (the generators' shared test scenes)."""
    return held_out_pool("scattered")


def test_robots_obstacles_fields_and_walls_vary(pool):
    scs = [scenario_from_dict(d) for d in pool.values()]
    for sc in scs:
        assert 0.05 <= sc.robot_radius <= 0.12 and 0.09 <= sc.min_turn_radius <= 0.25
        assert np.all((sc.radii >= 0.03) & (sc.radii <= 0.20))
        box = sc.field
        for x, y, _ in (sc.start, sc.goal):  # inside, at least the robot's radius from the edges
            assert box.xmin + sc.robot_radius <= x <= box.xmax - sc.robot_radius
            assert box.ymin + sc.robot_radius <= y <= box.ymax - sc.robot_radius
        assert np.all(sc.centres >= 0.1 - 1e-9)
        assert np.all(sc.centres <= np.array([box.xmax, box.ymax]) - 0.1 + 1e-9)
    walls = sum(sc.field.keep_inside for sc in scs)
    assert 6 <= walls <= 18  # about half of 24
    assert any(np.ptp(sc.model_radii) > 1e-6 for sc in scs)
    areas = [sc.field.xmax * sc.field.ymax / sc.n for sc in scs]  # m^2 per obstacle
    assert min(areas) < 0.6 and max(areas) > 1.0  # tight and wide fields
    # some pose lies closer to an edge than the robot's radius plus its turning radius
    near = [min(x - sc.field.xmin, sc.field.xmax - x, y - sc.field.ymin, sc.field.ymax - y)
            - sc.robot_radius - sc.min_turn_radius for sc in scs for x, y, _ in (sc.start, sc.goal)]
    assert min(near) < 0
