"""Multilayer perceptrons: scikit-learn's MLPClassifier with two presets.

Back-propagation is scikit-learn's; this module only chooses settings.
"""

from __future__ import annotations

import warnings
from typing import Any

from sklearn.exceptions import ConvergenceWarning
from sklearn.neural_network import MLPClassifier
from sklearn.pipeline import Pipeline
from sklearn.preprocessing import StandardScaler

from .._dask import DaskMixin
from .._typing import ArrayLike

__all__ = ["FixedEpochsMLPClassifier", "modern_mlp", "thesis_mlp"]


class FixedEpochsMLPClassifier(DaskMixin, MLPClassifier):
    """An :class:`~sklearn.neural_network.MLPClassifier` trained for a fixed budget.

    Same parameters and behaviour as ``MLPClassifier``. The only difference:
    stopping after ``max_iter`` epochs is the plan, not a failure, so ``fit``
    does not raise scikit-learn's ``ConvergenceWarning`` for it. The number of
    epochs run is ``n_iter_``.

    Examples
    --------
    >>> import warnings
    >>> clf = FixedEpochsMLPClassifier(max_iter=3, random_state=0)
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("error")
    ...     _ = clf.fit([[0.0], [1.0]], [0, 1])
    >>> clf.n_iter_
    3
    """

    def fit(self, X: ArrayLike, y: ArrayLike) -> FixedEpochsMLPClassifier:
        """Train for at most ``max_iter`` epochs, without a convergence warning.

        Parameters
        ----------
        X : array_like of shape (n_samples, n_features)
        y : array_like of shape (n_samples,)

        Returns
        -------
        self : FixedEpochsMLPClassifier
        """
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            return super().fit(X, y)


def thesis_mlp(**overrides: Any) -> FixedEpochsMLPClassifier:
    """The thesis's multilayer perceptron, as a scikit-learn classifier.

    The thesis trains a back-propagation network with sigmoid units for 50
    epochs at learning rate 0.6 (section 5.1.1.2, ``net.trainParam.epochs =
    50``). Its hidden-layer size is not given; 10 is MATLAB's default
    (``feedforwardnet``). The preset:

    - ``hidden_layer_sizes=(10,)``: one hidden layer of 10 units;
    - ``activation="logistic"``: sigmoid units (the output layer of a
      scikit-learn classifier is softmax, or logistic for two classes);
    - ``solver="sgd"``, ``momentum=0``, ``learning_rate="constant"``,
      ``learning_rate_init=0.6``: plain gradient descent, no momentum;
    - ``batch_size="auto"``: mini-batches of ``min(200, n_samples)``, which is
      full-batch gradient descent (MATLAB's ``traingd``) on the thesis's small
      training sets;
    - ``max_iter=50``, ``n_iter_no_change=50``: exactly 50 epochs, with no
      early stop and (by design) no convergence warning;
    - ``alpha=0``: no weight decay, as in back-propagation of the time.

    No feature scaling: the thesis fed the Fourier magnitudes as they are.

    Parameters
    ----------
    **overrides
        Any :class:`~sklearn.neural_network.MLPClassifier` parameter, e.g.
        ``random_state=0`` or ``hidden_layer_sizes=(4,)``.

    Returns
    -------
    FixedEpochsMLPClassifier
        An unfitted ``MLPClassifier`` (subclass).

    Examples
    --------
    >>> from tentaclass.classifiers import thesis_mlp
    >>> from tentaclass.features import fourier_features
    >>> from tentaclass.datasets import thesis_tentacle
    >>> X, y = thesis_tentacle(16, return_X_y=True)
    >>> clf = thesis_mlp(random_state=0).fit(fourier_features(X), y)
    >>> clf.n_iter_, clf.learning_rate_init, clf.activation
    (50, 0.6, 'logistic')
    """
    params: dict[str, Any] = {
        "hidden_layer_sizes": (10,),
        "activation": "logistic",
        "solver": "sgd",
        "learning_rate": "constant",
        "learning_rate_init": 0.6,
        "momentum": 0.0,
        "nesterovs_momentum": False,
        "batch_size": "auto",
        "max_iter": 50,
        "n_iter_no_change": 50,
        "alpha": 0.0,
        "shuffle": True,
        "early_stopping": False,
    }
    params.update(overrides)
    return FixedEpochsMLPClassifier(**params)


def modern_mlp(**overrides: Any) -> Pipeline:
    """A multilayer perceptron with good present-day defaults, in a pipeline.

    ``StandardScaler`` then ``MLPClassifier`` with:

    - ``hidden_layer_sizes=(64,)``, ``activation="relu"``;
    - ``solver="adam"``, ``learning_rate_init=1e-2``, ``alpha=1e-4`` (L2);
    - ``early_stopping=True`` with a 10 % validation split and
      ``n_iter_no_change=20``, within ``max_iter=500`` epochs.

    The step size is ten times Adam's usual 1e-3: with early stopping on a
    small validation split (whose accuracy saturates quickly), 1e-3 stops
    before the network has learnt much on training sets of a few hundred
    arrays.

    Scaling matters: Fourier magnitudes differ by orders of magnitude between
    low and high frequencies. Early stopping needs at least two samples per
    class in the validation split; for very small training sets pass
    ``early_stopping=False``.

    Parameters
    ----------
    **overrides
        Parameters of the ``MLPClassifier`` step (e.g. ``random_state=0``).

    Returns
    -------
    sklearn.pipeline.Pipeline
        Steps ``"scale"`` and ``"mlp"``, unfitted.

    Examples
    --------
    >>> import numpy as np
    >>> from tentaclass.classifiers import modern_mlp
    >>> rng = np.random.default_rng(0)
    >>> X = np.concatenate([rng.normal(0, 1, (100, 3)), rng.normal(4, 1, (100, 3))])
    >>> y = np.repeat(["a", "b"], 100)
    >>> clf = modern_mlp(random_state=0).fit(X, y)
    >>> clf.named_steps["mlp"].activation, clf.score(X, y) > 0.95
    ('relu', True)
    """
    params: dict[str, Any] = {
        "hidden_layer_sizes": (64,),
        "activation": "relu",
        "solver": "adam",
        "learning_rate_init": 1e-2,
        "alpha": 1e-4,
        "early_stopping": True,
        "validation_fraction": 0.1,
        "n_iter_no_change": 20,
        "max_iter": 500,
    }
    params.update(overrides)
    return Pipeline([("scale", StandardScaler()), ("mlp", MLPClassifier(**params))])
