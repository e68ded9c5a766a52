"""Argument checks at the API boundary: each returns the clean value or raises a one-line
``RadiometerError`` saying which argument is wrong and what is expected.

Called at the top of every ``api`` function so that garbage (wrong types, shapes, NaN/inf, huge or
empty values) never reaches numpy or bpy as a ValueError, TypeError, IndexError, OverflowError,
MemoryError, ... deep inside. Pure Python + numpy; the checks of Blender arguments (a scene, an
object) are host code in ``measure/blender/arguments.py``.
Bounds are stated here once (``MAX_*``), in the units of the argument.
"""

import math
import numbers
import os

import numpy as np

from .errors import RadiometerError

#: Largest accepted coordinate magnitude (m / scene units): beyond it float32 geometry has no precision.
MAX_COORDINATE = 1e12
#: At most this many points in one call (meters, grid points): ~1 GB of per-point state.
MAX_POINTS = 1_000_000
#: Largest radiance-map height / irradiance-map side (pixels).
MAX_MAP_SIDE = 8192
#: Largest photometric or image input file read whole (bytes).
MAX_INPUT_BYTES = 64 * 1024 * 1024
#: Largest time budget (s): a week.
MAX_TIME_BUDGET_S = 7 * 24 * 3600.0
#: Largest fixed sample count per meter (Cycles' float32 accumulation is exact to 2**24).
MAX_SAMPLES = 1 << 24
#: Seeds are Cycles' int seed (32-bit signed).
MAX_SEED = 2**31 - 1


def shown_value(value, limit=60):
    """``value`` as one short line for a message (an array's repr spans several)."""
    text = " ".join(repr(value).split())  # one line: an array's repr spans several
    return text if len(text) <= limit else text[:limit - 3] + "..."


def fail(name, expected, value):
    """Raise the one-line RadiometerError "<name> must be <expected>, got <value>"."""
    raise RadiometerError(f"{name} must be {expected}, got {shown_value(value)}")


def real(value, name, *, low=-math.inf, high=math.inf, low_open=False, high_open=False, allow_none=False):
    """A finite float in [low, high] (open ends when asked); bools and strings are refused."""
    if value is None and allow_none:
        return None
    lo = "(" if low_open else "["
    hi = ")" if high_open else "]"
    expected = "a finite number" + ("" if (low, high) == (-math.inf, math.inf) else f" in {lo}{low:g}, {high:g}{hi}")
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Real, np.floating, np.integer)):
        fail(name, expected, value)
    try:
        x = float(value)
    except (TypeError, ValueError, OverflowError):
        fail(name, expected, value)
    if not math.isfinite(x) or x < low or x > high or (low_open and x == low) or (high_open and x == high):
        fail(name, expected, value)
    return x


def positive(value, name, *, high=math.inf, allow_none=False):
    """A finite float > 0 (and <= ``high``)."""
    return real(value, name, low=0.0, low_open=True, high=high, allow_none=allow_none)


def integer(value, name, *, low=0, high=2**62, allow_none=False):
    """An int in [low, high]; floats with an integral value (4.0) are accepted, others refused."""
    if value is None and allow_none:
        return None
    expected = f"an integer in [{low}, {high}]"
    if isinstance(value, (bool, np.bool_)):
        fail(name, expected, value)
    if isinstance(value, (numbers.Integral, np.integer)):
        n = int(value)
    elif isinstance(value, (numbers.Real, np.floating)):
        x = float(value)
        if not math.isfinite(x) or x != int(x):
            fail(name, expected, value)
        n = int(x)
    else:
        fail(name, expected, value)
    if not low <= n <= high:
        fail(name, expected, value)
    return n


def seed(value, name="seed"):
    return integer(value, name, low=0, high=MAX_SEED)


def fraction(value, name, *, allow_none=False):
    """A relative error or tolerance: a finite number in (0, 1)."""
    return real(value, name, low=0.0, high=1.0, low_open=True, high_open=True, allow_none=allow_none)


def time_budget(value, name="time_budget_s"):
    return positive(value, name, high=MAX_TIME_BUDGET_S, allow_none=True)


def samples(value, name="samples"):
    return integer(value, name, low=1, high=MAX_SAMPLES, allow_none=True)


def callable_or_none(value, name):
    if value is not None and not callable(value):
        fail(name, "a callable or None", value)
    return value


def choice(value, name, options):
    if not isinstance(value, str) or value not in options:
        raise RadiometerError(f"unknown {name} {shown_value(value)}: must be one of "
                              + ", ".join(repr(o) for o in options))
    return value


def _array(value, name, expected):
    if isinstance(value, (str, bytes, dict, set)) or value is None:
        fail(name, expected, value)
    try:
        a = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        fail(name, expected, value)
    return a


def points(value, name="location", *, allow_many=True):
    """(3,) or (N, 3) finite coordinates within ``MAX_COORDINATE``; returns a float64 array as given."""
    expected = "3 finite numbers" + (" or an (N, 3) array of them" if allow_many else "")
    if hasattr(value, "__len__") and not isinstance(value, np.ndarray) and len(value) > 3 * MAX_POINTS:
        fail(name, expected + f" (at most {MAX_POINTS} points)", value)
    a = _array(value, name, expected)
    if a.shape == (3,):
        pass
    elif allow_many and a.ndim == 2 and a.shape[1] == 3 and 1 <= a.shape[0] <= MAX_POINTS:
        pass
    else:
        fail(name, expected + f" (at most {MAX_POINTS} points)" if allow_many else expected,
              f"an array of shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise RadiometerError(f"{name} is not finite: it must be {expected}, got {shown_value(value)}")
    if np.any(np.abs(a) > MAX_COORDINATE):
        fail(name, f"coordinates within ±{MAX_COORDINATE:g}", value)
    return a


def directions(value, name="normal", *, allow_many=True):
    """(3,) or (N, 3) finite non-zero directions (normalised later by the meter)."""
    a = points(value, name, allow_many=allow_many)
    norms = np.linalg.norm(np.atleast_2d(a), axis=1)
    if not np.all(norms > 1e-12) or not np.all(np.isfinite(norms)):
        raise RadiometerError(f"{name} has zero length: it must be a non-zero finite direction, got {shown_value(value)}")
    return a


def same_count(locations, normals, a_name="location", b_name="normal"):
    """Two (N, 3) arrays must have the same N (or one of them a single 3-vector)."""
    na = 1 if np.ndim(locations) == 1 else len(locations)
    nb = 1 if np.ndim(normals) == 1 else len(normals)
    if nb not in (1, na):
        raise RadiometerError(f"{b_name} must be one direction or one per {a_name} ({na}), got {nb}")


def path(value, name="path"):
    """A non-empty path (str or os.PathLike, no NUL byte); returns it as an absolute str."""
    if isinstance(value, bytes) or not isinstance(value, (str, os.PathLike)):
        fail(name, "a file path", value)
    text = os.fspath(value)
    if not isinstance(text, str) or not text.strip() or "\0" in text:
        fail(name, "a non-empty file path", value)
    if len(text) > 4096:
        raise RadiometerError(f"{name} is too long ({len(text)} characters; at most 4096)")
    return os.path.abspath(text)


def output_file(value, name="path"):
    """A path whose folder exists and where a file can be created (tried, not ``access()``)."""
    from . import outputs

    full = path(value, name)
    outputs.check_writable(full, name)
    return full


def check_input_file(value, what="file", *, max_bytes=MAX_INPUT_BYTES):
    """An existing REGULAR file of at most ``max_bytes``: FIFOs, devices (/dev/zero) and folders are
    refused before anything is read (reading them blocks forever or never ends)."""
    from .outputs import shown
    from .radiometry import input_files

    full = path(value, what)
    try:
        st = os.stat(full)
    except FileNotFoundError:
        raise RadiometerError(f"no such file: {shown(value)}") from None
    except OSError as exc:
        raise RadiometerError(f"cannot read {what} {shown(value)}: {exc.strerror or exc}") from None
    why = input_files.refusal(st, what, max_bytes)
    if why:
        raise RadiometerError(f"{shown(value)} {why}")
    return full


# --- the API boundary -----------------------------------------------------------------------------

QUALITIES = ("preview", "standard", "reference")
METHODS = ("auto", "analytic", "hybrid", "render")

# Errors of the pure readers whose message is already one line for the user (file and line named).
_USER_ERRORS = ()


def _user_errors():
    global _USER_ERRORS
    if not _USER_ERRORS:
        from .radiometry.skies import environment
        from .radiometry.sun import epw
        from .radiometry.photometry import photometric_files

        _USER_ERRORS = (photometric_files.PhotometricFileError, environment.EnvironmentInputError, epw.EPWError)
    return _USER_ERRORS


def _where(exc):
    import traceback

    frames = traceback.extract_tb(exc.__traceback__)
    if not frames:
        return ""
    last = frames[-1]
    return f" at {os.path.basename(last.filename)}:{last.lineno}"


def _first_line(exc):
    text = str(exc).strip()
    return text.splitlines()[0][:300] if text else type(exc).__name__


#: Reading attributes that must be finite in a result (a NaN reading is never an answer).
_READING_VALUES = ("illuminance", "irradiance", "luminance", "radiance")


def check_finite_result(result, what):
    """RadiometerError when a reading in ``result`` (a reading, a list of them, or a dict with
    reading keys) is NaN or infinite: a wrong number must not pass as an answer."""
    items = result if isinstance(result, (list, tuple)) else [result]
    for k, item in enumerate(items):
        for key in _READING_VALUES:
            value = item.get(key) if isinstance(item, dict) else getattr(item, key, None)
            if isinstance(value, (float, np.floating)) and not math.isfinite(value):
                which = f" #{k}" if len(items) > 1 else ""
                raise RadiometerError(f"{what}{which} gave a non-finite {key} ({value}): an input of the scene is "
                                      "NaN or infinite (a light's power, a texture, a world image); fix it and measure "
                                      "again")
    return result


def boundary(func=None, *, finite=False):
    """Decorator for an ``api`` function: whatever goes wrong below it leaves as ONE error type,
    ``RadiometerError`` with one line (issue 21). Errors of the pure file readers keep their message;
    anything unexpected is wrapped with the function's name, the exception type and where it arose
    (chained, so a developer still gets the traceback); MemoryError says the request is too large.
    ``finite``: the result's readings must be finite. Ctrl-C (KeyboardInterrupt) passes through."""
    import functools

    def wrap(f):
        @functools.wraps(f)
        def guarded(*args, **kwargs):
            try:
                result = f(*args, **kwargs)
            except RadiometerError as exc:
                if "\n" in str(exc).strip():  # one line, whoever wrote the message (an array's repr)
                    exc.args = (" ".join(str(exc).split()),)
                raise
            except MemoryError:
                raise RadiometerError(f"{f.__name__}: not enough memory for this request (too many points or "
                                      "pixels); ask for less") from None
            except RecursionError as exc:
                raise RadiometerError(f"{f.__name__}: the input is nested too deeply ({_first_line(exc)})") from None
            except Exception as exc:  # noqa: BLE001 - the boundary: one error type for the caller
                if isinstance(exc, TypeError) and exc.__traceback__.tb_next is None:
                    # raised by the call itself, not below it: the arguments do not fit the signature
                    raise RadiometerError(f"{_first_line(exc)} (see help(radiometer.api.{f.__name__}))") from None
                if isinstance(exc, _user_errors()):
                    raise RadiometerError(_first_line(exc)) from None
                raise RadiometerError(f"{f.__name__}: unexpected {type(exc).__name__}: {_first_line(exc)}"
                                      f"{_where(exc)} (bad input not caught earlier, or a bug: please report it)"
                                      ) from exc
            if finite:
                check_finite_result(result, f.__name__)
            return result

        guarded.__radiometer_boundary__ = True
        return guarded

    return wrap(func) if func is not None else wrap


def quality(value, name="quality", *, allow_none=False):
    if value is None and allow_none:
        return None
    return choice(value, name, QUALITIES)


def method(value, name="method", *, allow_none=False, options=METHODS):
    if value is None and allow_none:
        return None
    return choice(value, name, options)


_UNSET = object()


def measurement(*, quality_=None, method_=_UNSET, target_rel_error=None, samples_=None,
                time_budget_s=None, progress=None, cancelled=None, seed_=0, allow_none_quality=False,
                allow_none_method=False):
    """The keywords most measurements share, checked together (returns nothing; raises one line). The
    scene is checked by ``measure.blender.arguments.scene`` (host code: it needs bpy)."""
    quality(quality_, allow_none=allow_none_quality)
    if method_ is not _UNSET:  # functions without a method argument do not pass one
        method(method_, allow_none=allow_none_method)
    fraction(target_rel_error, "target_rel_error", allow_none=True)
    samples(samples_)
    time_budget(time_budget_s)
    callable_or_none(progress, "progress")
    callable_or_none(cancelled, "cancelled")
    seed(seed_)


def resolution2(value, name="resolution", *, low=1, high=MAX_MAP_SIDE, allow_none=False):
    """Two integers (width, height) or (nx, ny) in [low, high]."""
    if value is None and allow_none:
        return None
    expected = f"two integers in [{low}, {high}] (at least {low} x {low})"
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != 2:
        fail(name, expected, value)
    try:
        return tuple(integer(v, name, low=low, high=high) for v in value)
    except RadiometerError:
        fail(name, expected, value)


def angles(value, name, *, low, high, allow_none=True, max_count=10_000):
    """None or a non-empty 1-D list of finite angles (deg) in [low, high]."""
    if value is None and allow_none:
        return None
    a = _array(value, name, f"a list of angles in degrees within [{low:g}, {high:g}]")
    if a.ndim != 1 or not 1 <= a.size <= max_count or not np.all(np.isfinite(a)) or np.any(a < low) \
            or np.any(a > high):
        fail(name, f"a list of 1 to {max_count} angles in degrees within [{low:g}, {high:g}]", value)
    return a


def distances(value, name="distances", *, max_count=10_000):
    """None or a non-empty 1-D list of finite distances > 0 (m)."""
    if value is None:
        return None
    a = _array(value, name, "a list of distances > 0 in m")
    if a.ndim != 1 or not 1 <= a.size <= max_count or not np.all(np.isfinite(a)) or np.any(a <= 0) \
            or np.any(a > MAX_COORDINATE):
        fail(name, f"a list of 1 to {max_count} finite distances > 0 in m", value)
    return a


def optional_output(value, name):
    """None, or a path a file can be written to (checked now, before the work)."""
    return None if value is None else output_file(value, name)
