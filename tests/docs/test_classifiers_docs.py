import warnings

import numpy as np

from docs_helpers import run_python_blocks


def test_classifier_guide_runs():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the MLP example stops early on four arrays
        ns = run_python_blocks("classifiers.md", min_blocks=3)
    X, y = np.load(ns["path"]).values()
    assert X.shape == (60, 32) and sorted(set(y)) == ["circle", "rectangle", "square"]
