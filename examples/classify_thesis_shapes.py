"""Train on the thesis's four shapes and classify rotated, restarted, noisy wraps.

Run: ``python examples/classify_thesis_shapes.py``
"""

import numpy as np
from sklearn.model_selection import GridSearchCV

from tentaclass import FourierClassifier
from tentaclass.datasets import thesis_tentacle

rng = np.random.default_rng(0)
X, y = thesis_tentacle(64, return_X_y=True)

# Every start point, both directions, with joint-sensor noise of 0.03 rad.
starts = np.concatenate([np.roll(X, k, axis=1) for k in range(64)])
labels = np.tile(y, 64)
both_ways = np.concatenate([starts, -starts[:, ::-1]])
labels = np.concatenate([labels, labels])
noisy = both_ways + rng.normal(0, 0.03, both_ways.shape)

clf = FourierClassifier(detrend=True).fit(X, y)
print(
    f"trained on {len(X)} arrays, accuracy on {len(noisy)} noisy variants:",
    clf.score(noisy, labels),
)

grid = GridSearchCV(FourierClassifier(detrend=True), {"spread": [0.1, 1.0, 10.0]}, cv=3)
grid.fit(noisy, labels)
print("best spread:", grid.best_params_["spread"], "cv accuracy:", round(grid.best_score_, 3))
