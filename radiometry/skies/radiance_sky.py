"""A Radiometer CIE sky as Radiance text: the exact sky (a ``brightfunc`` over a function file) and the
nearest ``gensky`` command line, for the Radiance export (``measure.reports.radiance_export``).

The exact sky is what the meter integrates (:mod:`.cie_sky`): above the horizon L = Lz x L/Lz of the
ISO 15469 / CIE S 011 type (or the traditional overcast (1 + 2 cos Z)/3), below a sharp horizon the
uniform ground luminance rho_g E_h / pi. Radiance sees it as a ``glow`` over a ``source`` of 360
degrees modified by ``brightfunc skyfunc`` (the form gensky writes), so ``rtrace -ab N`` samples it
through the ambient calculation like a gensky sky.

``gensky`` (gensky(1)) differs in two ways, both stated in the export's README: its ground glow
blends into the sky over about 10 degrees of the horizon (skybright.cal: wmean((Dz + 1.01)^10, sky,
(Dz + 1.01)^-10, ground)), and it has only the overcast (-c, the traditional overcast here), the
CIE clear sky (-s, ISO type 12) and its own intermediate (-i) and uniform (-u) skies. For other ISO
types no gensky line is exact and none is written as if it were.

This module never imports bpy.
"""

import numpy as np

from . import cie_sky, sky_models
from ..scene import radiance_format as rad

SKY_CAL = "radiometer_sky.cal"


def sky_cal(sky_type, sun_direction, zenith_radiance, ground_radiance):
    """The function file defining ``rm_skybr`` (Radiance watts/(m^2 sr)) for directions (Dx, Dy, Dz):
    ``zenith_radiance`` x the type's L/Lz above the horizon, ``ground_radiance`` below it."""
    t = cie_sky.parse_sky_type(sky_type)
    lz, lg = float(zenith_radiance), float(ground_radiance)
    head = (f"{{ Radiometer CIE sky ({'traditional overcast' if t == 'overcast' else f'ISO 15469 type {t}'}), "
            f"sharp horizon: written by Radiometer's Radiance export }}\n"
            f"rm_Lz = {lz:.12g};\nrm_Lg = {lg:.12g};\n")
    if t == "overcast":
        return head + "rm_skybr = if(Dz, rm_Lz*(1 + 2*Dz)/3, rm_Lg);\n"
    # Python floats' repr (the shortest that round-trips), never numpy's: a numpy scalar's repr follows the
    # process's print options, which a library can change (measured: 17 digits in one test run, 16 in
    # another), and the file must be the same bytes for the same sky.
    a, b, c, d, e = (float(v) for v in cie_sky.parameters(t))
    sun = [float(v) for v in np.asarray(cie_sky.sun_for_sky(t, sun_direction), float)]
    zeta = float(cie_sky.zenith_shape(t, np.asarray(sun)))
    return head + (
        f"rm_a = {a!r}; rm_b = {b!r}; rm_c = {c!r}; rm_d = {d!r}; rm_e = {e!r};\n"
        f"rm_sx = {sun[0]!r}; rm_sy = {sun[1]!r}; rm_sz = {sun[2]!r};\n"
        f"rm_zeta = {zeta:.17g};\n"
        "rm_clip(x) = if(x - 1, 1, if(-1 - x, -1, x));\n"
        "rm_cz = if(Dz - 1e-6, Dz, 1e-6);\n"
        "rm_phi = 1 + rm_a*exp(rm_b/rm_cz);\n"
        "rm_cchi = rm_clip(Dx*rm_sx + Dy*rm_sy + Dz*rm_sz);\n"
        "rm_f = 1 + rm_c*(exp(rm_d*acos(rm_cchi)) - exp(rm_d*PI/2)) + rm_e*rm_cchi*rm_cchi;\n"
        "rm_skybr = if(Dz, rm_Lz*rm_f*rm_phi/rm_zeta, rm_Lg);\n")


def gensky_command(sky_type, sun_direction, horizontal_illuminance_lux, ground_reflectance):
    """The nearest ``gensky`` command line (a string without the leading ``!``), or None when no gensky
    sky is this ISO type. Its overcast sky is this one (zenith 9 E_h / (7 pi), ground rho E_h / pi: the
    same numbers, checked against gensky's output in the tests) but for the blended horizon; its clear
    sky (-s) normalises the zenith its own way (0.2 % apart at 30 deg sun) and lights its ground with
    the sun as well, so -s is the nearest line, not the same sky. The sun's altitude and azimuth are gensky's -ang (degrees; azimuth measured
    from south towards west, Radiance's convention, with +Y north and +X east as in Radiometer);
    -B the horizontal diffuse irradiance in Radiance watts (E_h / 179)."""
    model = sky_models.sky_model(sky_type)
    t, flag = model.sky_type, model.gensky_flag
    if flag is None:
        return None
    sun = np.asarray(cie_sky.sun_for_sky(t, sun_direction), float)
    alt = float(np.degrees(np.arcsin(np.clip(sun[2], -1, 1))))
    az = float(np.degrees(np.arctan2(-sun[0], -sun[1])))  # from south (-Y) towards west (-X)
    return (f"gensky -ang {alt:.6g} {az:.6g} {flag} -B {float(horizontal_illuminance_lux) / rad.RADIANCE_EFFICACY:.9g} "
            f"-g {float(ground_reflectance):.6g}")


def sky_rad(cal_name=SKY_CAL):
    """The sky's primitives: ``skyfunc`` (brightfunc over ``cal_name``), its glow and a 360-degree
    source (sky and ground in one, as the meter's world is one sphere)."""
    return (rad.primitive("void", "brightfunc", "skyfunc", strings=("rm_skybr", cal_name))
            + rad.glow("sky_glow", 1.0, modifier="skyfunc")
            + rad.source("sky_glow", "sky", (0.0, 0.0, 1.0), 360.0))


def gensky_rad(command):
    """A gensky sky file: the ``!`` command line and gensky's usual glow and source lines."""
    return (f"!{command}\n"
            + rad.glow("sky_glow", 1.0, modifier="skyfunc") + rad.source("sky_glow", "sky", (0.0, 0.0, 1.0), 180.0)
            + rad.glow("ground_glow", 1.0, modifier="skyfunc")
            + rad.source("ground_glow", "ground", (0.0, 0.0, -1.0), 180.0))
