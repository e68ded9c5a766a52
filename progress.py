"""One adapter for progress callbacks (pure Python).

Radiometer calls ``progress(done, total, seconds_left)`` (``seconds_left`` in s, or None before an
estimate exists); callbacks written for ``progress(done, total)`` are accepted too. Which form a
callback takes is decided once from its signature, not by catching ``TypeError`` around the call:
that retried a callback whose own body raised TypeError and hid the error.
"""

import inspect

__all__ = ["reporter"]


def _takes_seconds_left(callback):
    try:
        signature = inspect.signature(callback)
    except (TypeError, ValueError):  # no signature (some builtins): the documented three-argument form
        return True
    try:
        signature.bind(0, 1, None)
        return True
    except TypeError:
        return False


def reporter(progress):
    """``report(done, total, seconds_left=None)`` calling ``progress`` in the form it accepts; None for None.

    Parameters
    ----------
    progress : callable or None
        ``progress(done, total, seconds_left)`` or ``progress(done, total)``.
    """
    if progress is None or getattr(progress, "is_radiometer_reporter", False):
        return progress
    if _takes_seconds_left(progress):
        def report(done, total, seconds_left=None):
            progress(done, total, seconds_left)
    else:
        def report(done, total, seconds_left=None):
            progress(done, total)
    report.is_radiometer_reporter = True
    return report
