"""Doctest collection of the package: skip modules whose optional extra is not installed."""

import importlib.util

collect_ignore = []
if importlib.util.find_spec("fastapi") is None:  # the web extra
    collect_ignore.append("src/tentaclass/web/_app.py")
