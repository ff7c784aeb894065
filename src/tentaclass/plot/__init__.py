"""Every figure of the project, one convention for all.

matplotlib is imported only when a plotting function is called. Each function
draws on ``ax`` (a new figure's axes when ``ax`` is None), returns the artists
it drew and never calls ``plt.show()``.

- :mod:`tentaclass.plot.features`: a joint-angle array as shape, turning
  function, periodic signal and Fourier features (the thesis's panel);
- :mod:`tentaclass.plot.wrapping`: a chain on its object, grasping spectra,
  the sampling error against link length;
- :mod:`tentaclass.plot.scanner`: an inspected object, a belt with its objects;
- :mod:`tentaclass.plot.physics`: a physical grasp with its contacts, and its
  closing as an animation;
- :mod:`tentaclass.plot.confusion`: a confusion matrix with its counts.
"""

from typing import TYPE_CHECKING

from .._lazy import lazy_exports

if TYPE_CHECKING:
    from .confusion import plot_confusion_matrix
    from .features import (
        plot_features,
        plot_periodic_signal,
        plot_shape,
        plot_thesis_panel,
        plot_turning,
    )
    from .physics import animate_grasp, plot_grasp
    from .scanner import plot_belt, plot_inspection, save_belt_figure
    from .wrapping import grasp_spectrum, plot_capture_error, plot_grasp_spectra, plot_wrap

_HOME = {
    "animate_grasp": "physics",
    "plot_grasp": "physics",
    "grasp_spectrum": "wrapping",
    "plot_confusion_matrix": "confusion",
    "plot_belt": "scanner",
    "plot_capture_error": "wrapping",
    "plot_features": "features",
    "plot_grasp_spectra": "wrapping",
    "plot_inspection": "scanner",
    "plot_periodic_signal": "features",
    "plot_shape": "features",
    "plot_thesis_panel": "features",
    "plot_turning": "features",
    "plot_wrap": "wrapping",
    "save_belt_figure": "scanner",
}
__getattr__, __dir__ = lazy_exports(__name__, _HOME, globals())

__all__ = [
    "animate_grasp",
    "grasp_spectrum",
    "plot_belt",
    "plot_capture_error",
    "plot_confusion_matrix",
    "plot_features",
    "plot_grasp",
    "plot_grasp_spectra",
    "plot_inspection",
    "plot_periodic_signal",
    "plot_shape",
    "plot_thesis_panel",
    "plot_turning",
    "plot_wrap",
    "save_belt_figure",
]
