"""Every figure of the project, one convention for all.

matplotlib is imported only when a plotting function is called. Each function
draws on ``ax`` (a new figure's axes when ``ax`` is None), returns the artists
it drew and never calls ``plt.show()``.

- :mod:`tentaclass.plot.features`: a joint-angle array as shape, turning
  function, periodic signal and Fourier features (the thesis's panel);
- :mod:`tentaclass.plot.wrapping`: a chain on its object, grasping spectra,
  the sampling error against link length;
- :mod:`tentaclass.plot.scanner`: an inspected object, a belt with its objects.
"""

from .features import (
    plot_features,
    plot_periodic_signal,
    plot_shape,
    plot_thesis_panel,
    plot_turning,
)
from .scanner import plot_belt, plot_inspection, save_belt_figure
from .wrapping import grasp_spectrum, plot_capture_error, plot_grasp_spectra, plot_wrap

__all__ = [
    "grasp_spectrum",
    "plot_belt",
    "plot_capture_error",
    "plot_features",
    "plot_grasp_spectra",
    "plot_inspection",
    "plot_periodic_signal",
    "plot_shape",
    "plot_thesis_panel",
    "plot_turning",
    "plot_wrap",
    "save_belt_figure",
]
