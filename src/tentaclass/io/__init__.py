"""Model files: every fitted model as arrays plus JSON metadata, never pickle."""

from ._model_file import load_model, save_model

__all__ = ["load_model", "save_model"]
