"""Fitted default recognisers shared by the model-file tests (each fit takes seconds)."""

import numpy as np
import pytest

from tentaclass.classifiers import TentacleClassifier
from tentaclass.datasets import synthetic_tentacle


@pytest.fixture(scope="package")
def wraps16():
    """Generated wraps of the four thesis shapes by 16 links, failed wraps left out."""
    d = synthetic_tentacle(120, 16, noise=(0.0, 0.02), random_state=0)
    ok = np.isfinite(d.data).all(axis=1)
    return d.data[ok], d.target[ok]


@pytest.fixture(scope="package")
def default_recognisers(wraps16):
    """``TentacleClassifier()`` and ``TentacleClassifier(reject=0.05)`` fitted on ``wraps16``.

    Shared: a test that changes a model works on a deep copy.
    """
    X, y = wraps16
    return {
        "default": TentacleClassifier().fit(X, y),
        "reject": TentacleClassifier(reject=0.05).fit(X, y),
    }
