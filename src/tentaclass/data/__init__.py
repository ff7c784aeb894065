"""Package data: the bundled default models (``default-<n_links>.tcm``)."""
