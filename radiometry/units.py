"""Unit conversion and input validation helpers (float64 numpy, no bpy).

Blender distances are in scene units; Cycles ignores ``unit_settings.scale_length`` when it
renders, so one scene unit is ``scale_length`` metres.
"""

import numpy as np

__all__ = [
    "scene_to_metres",
    "as_finite_array",
    "check_finite",
    "check_nonnegative",
    "check_positive",
    "frozen_array",
]


def _validated_scale(scale_length):
    scale = float(scale_length)
    if not np.isfinite(scale) or scale <= 0.0:
        raise ValueError(f"scale_length must be a finite positive number of metres per scene unit, got {scale_length!r}")
    return scale


def scene_to_metres(values, scale_length):
    """Convert scene-unit lengths to metres.

    Parameters
    ----------
    values : array_like
        Lengths or coordinates in Blender scene units.
    scale_length : float
        ``scene.unit_settings.scale_length``: metres per scene unit (> 0).

    Returns
    -------
    numpy.ndarray
        ``values * scale_length`` in metres, float64, same shape.
    """
    return np.asarray(values, dtype=np.float64) * _validated_scale(scale_length)


def as_finite_array(values, name, shape_tail=None):
    """Return ``values`` as a float64 array, raising ValueError for NaN/inf or a wrong last axis."""
    array = np.asarray(values, dtype=np.float64)
    if shape_tail is not None and array.shape[-len(shape_tail):] != tuple(shape_tail):
        raise ValueError(f"{name} must have trailing shape {tuple(shape_tail)}, got {array.shape}")
    check_finite(array, name)
    return array


def check_finite(values, name):
    """Raise ValueError naming ``name`` if any value is NaN or infinite."""
    array = np.asarray(values, dtype=np.float64)
    if not np.all(np.isfinite(array)):
        raise ValueError(f"{name} contains NaN or infinite values")
    return array


def check_nonnegative(values, name):
    """Raise ValueError if any value is NaN, infinite or negative."""
    array = check_finite(values, name)
    if np.any(array < 0.0):
        raise ValueError(f"{name} must be >= 0, got a minimum of {array.min()!r}")
    return array


def check_positive(values, name):
    """Raise ValueError if any value is NaN, infinite, zero or negative."""
    array = check_finite(values, name)
    if np.any(array <= 0.0):
        raise ValueError(f"{name} must be > 0, got a minimum of {array.min()!r}")
    return array


def frozen_array(values):
    """A read-only float64 copy of ``values`` (for frozen dataclasses that hold arrays)."""
    array = np.array(values, dtype=np.float64)
    array.setflags(write=False)
    return array
