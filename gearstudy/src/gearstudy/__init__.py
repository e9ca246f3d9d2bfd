"""Parameter studies of GearedRotor.fmu: ``gearstudy sweep STUDY.toml`` / :func:`sweep`,
``gearstudy plot RESULTS`` / :func:`plot`. See docs/studies.md."""

from .engine import SweepSummary, sweep
from .results import column_units, read_results
from .study import Study, load_study, point_key, study_from_dict
from .units import Catalog, StudyError

__all__ = [
    "Catalog",
    "Study",
    "StudyError",
    "SweepSummary",
    "column_units",
    "load_study",
    "plot",
    "point_key",
    "read_results",
    "study_from_dict",
    "sweep",
]


def plot(results, out_dir=None, **kwargs):
    """Draw the maps of a results directory (see plots.plot_results), or the dynamic factor
    of a continuation's (continuation.plot)."""
    from . import continuation

    if continuation.is_continuation(results):
        return continuation.plot(results, out_dir=out_dir)
    from .plots import plot_results

    return plot_results(results, out_dir=out_dir, **kwargs)
