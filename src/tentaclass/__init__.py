"""tentaclass: recognise objects from one-dimensional data arrays.

The data flow is arrays -> descriptors -> classifiers -> reports:

- :mod:`tentaclass.geometry`: joint angles <-> points of a planar chain;
- :mod:`tentaclass.features`: turning function, periodic signal, Fourier features;
- :mod:`tentaclass.classifiers`: PNN and the end-to-end :class:`TentacleClassifier`;
- :mod:`tentaclass.datasets`: the thesis's arrays and grids;
- :mod:`tentaclass.report`: results as columns / JSON.
"""

from .geometry import angles_to_points, points_to_angles, resample_closed

__version__ = "0.1.0"

__all__ = [
    "__version__",
    "angles_to_points",
    "points_to_angles",
    "resample_closed",
]
