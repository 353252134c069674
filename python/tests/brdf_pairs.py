"""Random light/view pairs above the surface, for tests that compare two BRDF evaluations."""

import numpy as np


def random_pairs(count: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """`count` light and `count` view unit vectors (z = normal) up to 85 deg from the normal, at
    uniformly random azimuths; seeded, so a failure repeats."""
    rng = np.random.default_rng(seed)
    theta = np.radians(rng.uniform(0.0, 85.0, (count, 2)))
    phi = rng.uniform(0.0, 2 * np.pi, (count, 2))
    vectors = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)],
                       axis=-1)
    return vectors[:, 0], vectors[:, 1]
