"""The one interface every light source implements (pbrt-v4's ``Light``, Mitsuba 3's ``Emitter``).

An :class:`Emitter` is a light source as Cycles renders it, in SI: flux in W, intensity in W/sr,
irradiance in W/m^2, all per RGB channel of the scene's working colour space (a "watt" of Blender's
is radiometric per channel; photometric values are K x the Y of that triple, see
:mod:`radiometer.radiometry.photometry.efficacy`). Every kind lives in its own module of this package and is
built only by the capture layer (``measure.capture.scene_capture``) or from plain values in tests.

Conventions
-----------
* Directions are world unit vectors *leaving* the emitter (intensity) or pointing from the receiver
  to the source (as in irradiance, implied by the geometry).
* ``irradiance_at`` is the unoccluded contribution: nothing between the source and the receiver
  (occlusion, glass and media are decided by :mod:`..scene_model`).
* A delta-position source (radius-0 point, spot, photometric point) has infinite irradiance at its
  own position: ``irradiance_at`` raises ``ValueError`` there. A source without position (sun,
  world) has no intensity: ``intensity_towards`` raises ``ValueError``; its power is infinite and
  ``power_w`` returns ``inf`` per channel (pbrt bounds it by the scene's sphere; nothing here needs it).
"""

import abc
import enum
from typing import NamedTuple

import numpy as np

from ..constants import K_M_LM_PER_W
from ..photometry.efficacy import luminance_weights
from ..scene.geometry import norm
from ..units import as_finite_array

__all__ = ["EmitterFlags", "RayVisibility", "SourceId", "Emitter", "prepare_receivers", "REC709_WEIGHTS_NAME"]

#: The working space whose Y weights ``luminous_flux_lm`` uses unless given others.
REC709_WEIGHTS_NAME = "Rec.709"


class EmitterFlags(enum.Flag):
    """What kind of source this is, as the planner and the samplers need to know it."""

    NONE = 0
    DELTA_POSITION = enum.auto()   # all light leaves one point (radius-0 point, spot, IES point)
    DELTA_DIRECTION = enum.auto()  # all light arrives from one direction (sun of angle 0)
    AREA = enum.auto()             # a finite emitting surface or volume (area light, sphere, mesh)
    INFINITE = enum.auto()         # at infinity: no position, no finite power (sun, world)
    RENDERED_ONLY = enum.auto()    # no closed form of what Cycles renders: only a render measures it


class RayVisibility(enum.Flag):
    """Cycles' ray-visibility switches of the light object (``Object.visible_*``) and the light's
    ``use_shadow``: which rays see the emitter, and whether it casts shadows."""

    NONE = 0
    CAMERA = enum.auto()
    DIFFUSE = enum.auto()
    GLOSSY = enum.auto()
    TRANSMISSION = enum.auto()
    VOLUME_SCATTER = enum.auto()
    SHADOW = enum.auto()
    ALL = CAMERA | DIFFUSE | GLOSSY | TRANSMISSION | VOLUME_SCATTER | SHADOW


class SourceId(NamedTuple):
    """A stable identity of an emitter within one capture, not its (editable, reusable) name.

    ``object_uid``: the Blender object's ``session_uid`` (unique for the session, survives renames);
    ``library``: the library path of a linked object ('' when local); ``instance``: the depsgraph's
    ``persistent_id`` tuple of an instance (() for the object itself); ``part``: an index inside the
    object (a material slot of an emissive mesh, -1 for the whole object).
    """

    object_uid: int = 0
    library: str = ""
    instance: tuple = ()
    part: int = -1


def prepare_receivers(points, normals):
    """Validate receivers: (points (N, 3) m, unit normals (N, 3), leading shape).

    Raises ValueError for NaN/inf, a last axis other than 3, or a zero normal.
    """
    p = as_finite_array(points, "points")
    n = as_finite_array(normals, "normals")
    if p.shape[-1:] != (3,) or n.shape[-1:] != (3,):
        raise ValueError("points and normals need a last axis of 3")
    p, n = np.broadcast_arrays(p, n)
    lead = p.shape[:-1]
    n_len = norm(n)
    if np.any(n_len == 0.0):
        raise ValueError("normals contain a zero vector")
    return p.reshape(-1, 3), (n / n_len[..., np.newaxis]).reshape(-1, 3), lead


class Emitter(abc.ABC):
    """A light source (see the module docstring for units and conventions).

    Every kind provides ``source_id`` (:class:`SourceId` or None when built outside a capture),
    ``flags`` (:class:`EmitterFlags`), ``visibility`` (:class:`RayVisibility`) and the four methods
    below. A new kind (a glass-filtered source, a daylight patch) subclasses this and registers
    nothing: the planner reads only this interface.
    """

    @property
    @abc.abstractmethod
    def flags(self):
        """:class:`EmitterFlags` of this source."""

    @abc.abstractmethod
    def power_w(self):
        """Radiant flux leaving the source, W per RGB channel, (3,) (``inf`` for INFINITE sources)."""

    @abc.abstractmethod
    def intensity_towards(self, directions):
        """Far-field radiant intensity (..., 3) W/sr per channel towards world ``directions`` (..., 3)
        leaving the source (normalised here). ValueError for a source without position."""

    @abc.abstractmethod
    def irradiance_at(self, points, normals):
        """Unoccluded irradiance from this source on receivers at ``points`` (..., 3) m facing
        ``normals`` (..., 3): (E (..., 3) W/m^2 per channel, bound). ``bound`` is an absolute bound
        (..., 3) W/m^2 on |E - E_Cycles| (0 for a closed form), or None where no closed form of what
        Cycles renders exists (E is then an estimate only)."""

    def luminous_flux_lm(self, weights=None, efficacy=K_M_LM_PER_W):
        """Luminous flux, lm: ``efficacy`` (lm/W) x the Y of :meth:`power_w` with RGB -> Y ``weights``
        (default: the Rec.709 / sRGB working space's)."""
        if weights is None:
            weights = luminance_weights(REC709_WEIGHTS_NAME)
        return float(efficacy) * float(np.asarray(self.power_w(), float) @ np.asarray(weights, float))

    @property
    def has_position(self):
        """False for a source at infinity (sun, world): no distance, no inverse-square law, no location."""
        return not self.flags & EmitterFlags.INFINITE

    def extent(self):
        """(points (K, 3) m, reach m): the emitting region lies within ``reach`` of the convex hull of
        ``points``; None for a source at infinity or one whose extent is not known (nothing is then proven
        about where its light can go: ``scene.sealed``)."""
        return None

    @property
    def is_delta(self):
        """True for a source a sampler can only hit by connecting to it (point, spot, sun of angle 0)."""
        return bool(self.flags & (EmitterFlags.DELTA_POSITION | EmitterFlags.DELTA_DIRECTION))
