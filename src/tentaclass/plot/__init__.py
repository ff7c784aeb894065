"""Figures (matplotlib, imported lazily): every function takes ``ax=None`` and returns its artists.

- :mod:`tentaclass.plot.physics`: physical grasps, still and animated.
"""
