"""Analytic direct irradiance from Blender/Cycles lights, in SI: the functional front of :mod:`.emitters`.

Deprecated names kept for their callers: ``LightSpec`` is :class:`.emitters.CyclesLight` (constructing
one returns the emitter of its kind), ``light_spec_from_values`` is :func:`.emitters.from_blender_values`,
and ``irradiance``, ``irradiance_with_bound``, ``exactness``, ``radiant_intensity`` call the emitter's
own methods. The maths lives in the kind modules (:mod:`.emitters.point`, ``spot``, ``sun``, ``area``,
``photometric``); new code should use the emitter directly.

Every model follows what Cycles (Blender 5.0) renders, read from its source
(``intern/cycles/scene/light.cpp`` device_update_lights and ``Light::area``;
``kernel/light/{point,spot,area,distant}.h``) and checked by renders in
``tests/bpy/test_cycles_lights_*.py``:

* point/spot, radius 0: radiant intensity I = P/(4 pi) (``eval_fac = 1/(pi * 4)``), E = I cos/r^2;
  a spot multiplies by ``smoothstep((z - cos(size/2)) / ((1 - cos(size/2)) * blend))`` where z is the
  cosine to -Z of the direction *in the object's scaled local frame* (non-uniform scale stretches
  the cone); blend 0 is a hard edge.
* point/spot, radius R, soft falloff OFF: Lambertian sphere of radiance P/(4 pi^2 R^2).
* point/spot, radius R, soft falloff ON: a disk of radius R always facing the receiver, same
  radiance, so E = P cos / (4 pi (R^2 + r^2)) above the horizon.
* spot with R > 0: the cone attenuation is applied per incoming direction (quadrature).
* sun: uniform cone of half-angle angle/2 whose normal irradiance is ``energy``.
* area: Lambertian emitter L = P/(pi A) on the -Z side; ``spread`` < 180 deg multiplies the
  radiance by max((tan(s/2) - tan a) / (tan(s/2) - s/2), 0) (soft-box slats, flux preserving).
* photometric point light (radius 0, node tree Emission <- IES Texture; ``intensity_table``):
  I(dir) = rgb_power * table(dir) W/sr with Cycles' IES lookup (see :class:`IntensityTable`),
  E = I cos / r^2.

Units: positions in metres, rgb_power in W per channel (sun: W/m^2 per channel), results in
W/m^2 per channel. A delta light (point/spot of radius 0) at zero distance raises ValueError.

References
----------
See :mod:`.geometry` for the projected-solid-angle formulas (Lambert 1760, Arvo 1995, Baum 1989,
Snyder 1996, Lagarde & de Rousiers 2014); spread: Blender differential D10594 (soft-box spread).
"""

from .emitters.area import DISK_POLYGON_SIDES, QUADRATURE_ANGULAR, QUADRATURE_RADIAL, SHEARED_MIS_BOUND
from .emitters.cycles_light import KINDS, SHAPES, CyclesLight, from_blender_values
from .emitters.photometric import IntensityTable
from .emitters.spot import QUADRATURE_SPOT_PHI, QUADRATURE_SPOT_T, spot_attenuation

__all__ = ["LightSpec", "IntensityTable", "light_spec_from_values", "irradiance", "irradiance_with_bound", "exactness",
           "radiant_intensity", "spot_attenuation", "DISK_POLYGON_SIDES", "KINDS", "SHAPES", "SHEARED_MIS_BOUND",
           "QUADRATURE_RADIAL", "QUADRATURE_ANGULAR", "QUADRATURE_SPOT_PHI", "QUADRATURE_SPOT_T"]

#: Deprecated name of :class:`.emitters.CyclesLight` (``LightSpec(kind=...)`` returns that kind's emitter).
LightSpec = CyclesLight
#: Deprecated name of :func:`.emitters.from_blender_values`.
light_spec_from_values = from_blender_values


def irradiance(spec, points, normals):
    """Direct irradiance (no occlusion) from one light, W/m^2 per RGB channel.

    Parameters
    ----------
    spec : CyclesLight (any analytic emitter)
    points : array_like, shape (..., 3)
        Receiver positions, m.
    normals : array_like, shape (..., 3)
        Receiver normals (normalised here; zero vectors raise ValueError).

    Returns
    -------
    numpy.ndarray, shape (..., 3)
        Irradiance; 0 behind area/spot lights, outside cones and below the horizon. A light of
        negative energy gives negative irradiance (Cycles subtracts it).

    Raises
    ------
    ValueError
        NaN/inf inputs, or a receiver exactly at a delta light's position ("zero distance").
    """
    return spec.relative_irradiance(points, normals)[0]


def irradiance_with_bound(spec, points, normals):
    """Direct irradiance and a per-receiver relative error bound of the model against Cycles.

    Parameters are those of :func:`irradiance`.

    Returns
    -------
    (E, rel_bound)
        E : numpy.ndarray (..., 3), W/m^2 per channel, identical to :func:`irradiance`.
        rel_bound : numpy.ndarray (...), dimensionless, >= 0: |E - E_cycles| / |E| is expected
        below it (0 where E = 0 exactly). 0 for closed forms (float64 round-off aside).
        Quadratures: |Q_fine - Q_coarse| / |Q_fine| computed per receiver (spot with radius:
        256 against 128 azimuths, 8 nodes per smooth polar piece; spread < 180 deg: 48 x 192 against
        24 x 96; disk/ellipse: the 2048-gon against the 1024-gon). Sheared area lights: quadrature error plus
        :data:`SHEARED_MIS_BOUND` (measured gap between Cycles' light-sampling estimate, which is
        modelled, and its MIS result, which mixes in BSDF hits on a differently shaped region).
        NaN: not modelled (sheared area light with spread < 180 deg).
    """
    return spec.relative_irradiance(points, normals)


def exactness(spec):
    """(is_exact, model_name, note) describing how :func:`irradiance` computes this light.

    ``is_exact`` is True for closed forms (and the disk's 2048-gon, rel. error below 1e-8); the
    per-receiver error of every model is :func:`irradiance_with_bound`'s.
    """
    return spec.exactness()


def radiant_intensity(spec, direction):
    """Far-field radiant intensity, W/sr per channel, for world directions leaving the light.

    Point/sphere/disk: P/(4 pi); spot: times the cone factor; area: L A cos(theta) times the
    spread factor (0 behind); photometric: its table; sun: ValueError (no position, inverse square
    does not apply).
    """
    return spec.intensity_towards(direction)
