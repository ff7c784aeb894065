import numpy as np

from tentaclass.geometry import resample_closed

#: A plus sign: no built-in class looks like it.
CROSS = np.array(
    [(1, 0), (2, 0), (2, 1), (3, 1), (3, 2), (2, 2), (2, 3), (1, 3), (1, 2), (0, 2), (0, 1),
     (1, 1)], float,
)  # fmt: skip


def hand_drawn(outline, seed, size=300.0, centre=(300.0, -300.0)):
    """A wobbly stroke around an outline (world frame, y up), overshooting a little."""
    rng = np.random.default_rng(seed)
    p = resample_closed(np.asarray(outline, float), 120)
    p = np.roll(p, rng.integers(120), axis=0)
    p = np.concatenate([p, p[:6]])
    p = (p - p.mean(axis=0)) / np.ptp(p, axis=0).max()
    a = rng.uniform(0, 2 * np.pi)
    rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
    p = p @ rot.T + rng.normal(0, 0.006, p.shape)
    return p * size + centre


def figure_eight(n=80):
    t = np.linspace(0, 2 * np.pi, n)
    return np.stack([150 * np.sin(t) + 300, -(100 * np.sin(2 * t)) - 300], axis=1)
