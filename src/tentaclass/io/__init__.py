"""Model files: every fitted model as arrays plus JSON metadata, never pickle.

Also what a deployed model needs: the chain it was trained for
(:func:`check_chain_length`), rejection of unknown objects
(:func:`best_class_score`) and the bundled default models (:func:`bundled_model`).
"""

from ._deploy import (
    best_class_score,
    bundled_links,
    bundled_model,
    check_chain_length,
    rejection_threshold,
)
from ._model_file import load_model, model_info, save_model

__all__ = [
    "best_class_score",
    "bundled_links",
    "bundled_model",
    "check_chain_length",
    "load_model",
    "model_info",
    "rejection_threshold",
    "save_model",
]
