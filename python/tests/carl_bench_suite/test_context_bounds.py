import unittest

import numpy as np

from carl_spec.compat.context.utils import get_context_bounds


class TestContextBounds(unittest.TestCase):
    def test_context_bounds(self):
        DEFAULT_CONTEXT = {
            "min_position": -1.2,  # unit?
            "max_position": 0.6,  # unit?
            "max_speed": 0.07,  # unit?
            "goal_position": 0.5,  # unit?
            "goal_velocity": 0,  # unit?
            "force": 0.001,  # unit?
            "gravity": 0.0025,  # unit?
            "min_position_start": -0.6,
            "max_position_start": -0.4,
            "min_velocity_start": 0.0,
            "max_velocity_start": 0.0,
        }

        CONTEXT_BOUNDS = {
            "min_position": (-np.inf, np.inf, float),
            "max_position": (-np.inf, np.inf, float),
            "max_speed": (0, np.inf, float),
            "goal_position": (-np.inf, np.inf, float),
            "goal_velocity": (-np.inf, np.inf, float),
            "force": (-np.inf, np.inf, float),
            "gravity": (0, np.inf, float),
            "min_position_start": (-np.inf, np.inf, float),
            "max_position_start": (-np.inf, np.inf, float),
            "min_velocity_start": (-np.inf, np.inf, float),
            "max_velocity_start": (-np.inf, np.inf, float),
        }

        lower, upper = get_context_bounds(list(DEFAULT_CONTEXT.keys()), CONTEXT_BOUNDS)

        self.assertEqual(
            lower.all(),
            np.array(
                [
                    -np.inf,
                    -np.inf,
                    0.0,
                    -np.inf,
                    -np.inf,
                    -np.inf,
                    0.0,
                    -np.inf,
                    -np.inf,
                    -np.inf,
                    -np.inf,
                ]
            ).all(),
        )

        self.assertEqual(upper.all(), np.array([np.inf] * upper.shape[0]).all())


if __name__ == "__main__":
    TestContextBounds.test_context_bounds()
