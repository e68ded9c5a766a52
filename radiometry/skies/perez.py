"""Perez all-weather sky (pure numpy): sky parameters from hourly irradiances, luminous efficacy,
and the luminance of every sky patch, normalised to the diffuse horizontal illuminance.

Models and sources
------------------
* Relative luminance (Perez, Seals & Michalsky 1993, "All-weather model for sky luminance
  distribution - preliminary configuration and validation", Solar Energy 50(3):235-245, eq. 1):
  l(zeta, gamma) = [1 + a exp(b / cos zeta)] [1 + c exp(d gamma) + e cos^2 gamma]
  (zeta: zenith angle of the sky element, gamma: its angle from the sun). Parameters x = x1 + x2 Z
  + Delta (x3 + x4 Z) per sky-clearness bin (Table 1, with the erratum in Solar Energy 51(5):423),
  except in the first bin c = exp((Delta (c1 + c2 Z))^c3) - c4 and d = -exp(Delta (d1 + d2 Z)) + d3
  + Delta d4 (eqs. 7, 8); Z = solar zenith angle (rad).
* Sky clearness epsilon and brightness Delta (Perez et al. 1990, "Modeling daylight availability and
  irradiance components from direct and global irradiance", Solar Energy 44(5):271-289, eqs. 1, 2):
  epsilon = ((D_h + I_n) / D_h + 1.041 Z^3) / (1 + 1.041 Z^3), Delta = D_h m / (1367 E_0), with the
  relative air mass m of Kasten (1966) and the eccentricity correction E_0 (Spencer 1971).
* Luminous efficacy of diffuse and direct light (Perez et al. 1990, Table 4, eqs. 7, 8), with the
  precipitable water W = exp(0.07 T_d - 0.075) cm from the dew point T_d (eq. 3).
* Limits as Radiance's gendaymtx applies them (so the two-phase comparisons use the same sky):
  epsilon in [1, 11.9], Delta in [0.01, 0.6], Delta >= 0.2 for 1.065 < epsilon < 2.8, the sun's
  zenith angle clamped to [3, 90] deg; patch luminance evaluated at the patch centre. Not as gendaymtx:
  normalised so that sum_p L_p kappa_p = E_dh with kappa_p the EXACT integral of cos(zeta) over patch p
  (``SkyPatches.cos_solid_angle``), i.e. the piecewise-constant patch sky, integrated exactly as daylight
  coefficients integrate it, gives the weather file's diffuse horizontal illuminance; gendaymtx's
  sum_p L_p cos(zeta_centre) omega_p = E_dh leaves that sky 0.55 % short on every plane (MF:1;
  bench/sky_matrix_check.py). The sun's direct normal illuminance is spread over the 4 patches
  nearest to it with weights 1 / (1.002 - cos) (the two-phase approximation of gendaymtx).
"""

import numpy as np

__all__ = ["PEREZ_1993", "CLEARNESS_BINS", "clearness", "brightness", "air_mass", "eccentricity",
           "precipitable_water", "efficacy", "parameters", "relative_luminance", "sky_vector"]

#: Perez, Seals & Michalsky 1993, Table 1 (with the erratum): per clearness bin a1..a4, b1..b4,
#: c1..c4, d1..d4, e1..e4.
PEREZ_1993 = np.array([
    [1.3525, -0.2576, -0.2690, -1.4366, -0.7670, 0.0007, 1.2734, -0.1233, 2.8000, 0.6004, 1.2375, 1.0000,
     1.8734, 0.6297, 0.9738, 0.2809, 0.0356, -0.1246, -0.5718, 0.9938],
    [-1.2219, -0.7730, 1.4148, 1.1016, -0.2054, 0.0367, -3.9128, 0.9156, 6.9750, 0.1774, 6.4477, -0.1239,
     -1.5798, -0.5081, -1.7812, 0.1080, 0.2624, 0.0672, -0.2190, -0.4285],
    [-1.1000, -0.2515, 0.8952, 0.0156, 0.2782, -0.1812, -4.5000, 1.1766, 24.7219, -13.0812, -37.7000, 34.8438,
     -5.0000, 1.5218, 3.9229, -2.6204, -0.0156, 0.1597, 0.4199, -0.5562],
    [-0.5484, -0.6654, -0.2672, 0.7117, 0.7234, -0.6219, -5.6812, 2.6297, 33.3389, -18.3000, -62.2500, 52.0781,
     -3.5000, 0.0016, 1.1477, 0.1062, 0.4659, -0.3296, -0.0876, -0.0329],
    [-0.6000, -0.3566, -2.5000, 2.3250, 0.2937, 0.0496, -5.6812, 1.8415, 21.0000, -4.7656, -21.5906, 7.2492,
     -3.5000, -0.1554, 1.4062, 0.3988, 0.0032, 0.0766, -0.0656, -0.1294],
    [-1.0156, -0.3670, 1.0078, 1.4051, 0.2875, -0.5328, -3.8500, 3.3750, 14.0000, -0.9999, -7.1406, 7.5469,
     -3.4000, -0.1078, -1.0750, 1.5702, -0.0672, 0.4016, 0.3017, -0.4844],
    [-1.0000, 0.0211, 0.5025, -0.5119, -0.3000, 0.1922, 0.7023, -1.6317, 19.0000, -5.0000, 1.2438, -1.9094,
     -4.0000, 0.0250, 0.3844, 0.2656, 1.0468, -0.3788, -2.4517, 1.4656],
    [-1.0500, 0.0289, 0.4260, 0.3590, -0.3250, 0.1156, 0.7781, 0.0025, 31.0625, -14.5000, -46.1148, 55.3750,
     -7.2312, 0.4050, 13.3500, 0.6234, 1.5000, -0.6426, 1.8564, 0.5636]])
#: Lower bounds of the 8 sky-clearness bins (Perez et al. 1990, Table 1).
CLEARNESS_BINS = np.array([1.000, 1.065, 1.230, 1.500, 1.950, 2.800, 4.500, 6.200])
#: Perez et al. 1990 Table 4: diffuse (a, b, c, d) lm/W per bin: a + b W + c cos Z + d ln(Delta).
_DIFFUSE_EFFICACY = np.array([[97.24, -0.46, 12.00, -8.91], [107.22, 1.15, 0.59, -3.95], [104.97, 2.96, -5.53, -8.77],
                              [102.39, 5.59, -13.95, -13.90], [100.71, 5.94, -22.75, -23.74],
                              [106.42, 3.83, -36.15, -28.83], [141.88, 1.90, -53.24, -14.03],
                              [152.23, 0.35, -45.27, -7.98]])
#: ... direct (a, b, c, d) lm/W per bin: max(0, a + b W + c exp(5.73 Z - 5) + d Delta).
_DIRECT_EFFICACY = np.array([[57.20, -4.55, -2.98, 117.12], [98.99, -3.46, -1.21, 12.38], [109.83, -4.90, -1.71, -8.81],
                             [110.34, -5.84, -1.99, -4.56], [106.36, -3.97, -1.75, -6.16], [107.19, -1.25, -1.51, -26.73],
                             [105.75, 0.77, -1.26, -34.44], [101.18, 1.58, -1.10, -8.29]])
SOLAR_CONSTANT = 1367.0  # W/m^2, as in Perez et al. 1990


def air_mass(zenith):
    """Relative optical air mass (Kasten 1966), zenith angle in rad."""
    z = np.asarray(zenith, float)
    return 1.0 / (np.cos(z) + 0.15 * (93.885 - np.degrees(z)) ** -1.253)


def eccentricity(day_of_year):
    """Earth-orbit eccentricity correction E_0 (Spencer 1971), day of year 1..366."""
    g = (np.asarray(day_of_year, float) - 1.0) * 2 * np.pi / 365.0
    return 1.00011 + 0.034221 * np.cos(g) + 0.00128 * np.sin(g) + 0.000719 * np.cos(2 * g) + 0.000077 * np.sin(2 * g)


def clamp_zenith(zenith):
    """The sun's zenith angle as the model uses it: 90 deg below the horizon, >= 3 deg near the zenith."""
    return np.clip(np.asarray(zenith, float), np.radians(3.0), np.pi / 2)


def clearness(direct_normal, diffuse_horizontal, zenith):
    """Sky clearness epsilon from irradiances (W/m^2), limited to [1, 11.9]."""
    z3 = np.asarray(zenith, float) ** 3
    with np.errstate(divide="ignore", invalid="ignore"):
        eps = ((diffuse_horizontal + direct_normal) / diffuse_horizontal + 1.041 * z3) / (1 + 1.041 * z3)
    return np.clip(np.nan_to_num(eps, nan=1.0, posinf=11.9), 1.0, 11.9)


def brightness(diffuse_horizontal, zenith, day_of_year):
    """Sky brightness Delta = D_h m / (1367 E_0), limited to [0.01, 0.6]."""
    return np.clip(diffuse_horizontal * air_mass(zenith) / (SOLAR_CONSTANT * eccentricity(day_of_year)), 0.01, 0.6)


def bin_index(epsilon):
    return np.clip(np.searchsorted(CLEARNESS_BINS, np.asarray(epsilon, float), side="right") - 1, 0, 7)


def precipitable_water(dew_point_c):
    """Atmospheric precipitable water W (cm) from the dew point (deg C), Perez et al. 1990 eq. 3."""
    return np.exp(0.07 * np.asarray(dew_point_c, float) - 0.075)


def efficacy(epsilon, delta, zenith, dew_point_c):
    """(diffuse, direct) luminous efficacy, lm/W (Perez et al. 1990 Table 4)."""
    k = bin_index(epsilon)
    w = precipitable_water(dew_point_c)
    a, b, c, d = _DIFFUSE_EFFICACY[k].T
    diffuse = a + b * w + c * np.cos(zenith) + d * np.log(delta)
    a, b, c, d = _DIRECT_EFFICACY[k].T
    direct = np.maximum(a + b * w + c * np.exp(5.73 * zenith - 5.0) + d * delta, 0.0)
    return diffuse, direct


def parameters(zenith, epsilon, delta):
    """(a, b, c, d, e) of the all-weather model for one sky (scalars)."""
    k = int(bin_index(epsilon))
    if 1.065 < epsilon < 2.8:
        delta = max(delta, 0.2)
    x = PEREZ_1993[k].reshape(5, 4)
    z = float(zenith)
    p = [x[i, 0] + x[i, 1] * z + delta * (x[i, 2] + x[i, 3] * z) for i in range(5)]
    if k == 0:
        p[2] = np.exp((delta * (x[2, 0] + x[2, 1] * z)) ** x[2, 2]) - x[2, 3]
        p[3] = -np.exp(delta * (x[3, 0] + x[3, 1] * z)) + x[3, 2] + delta * x[3, 3]
    return tuple(float(v) for v in p)


def relative_luminance(zeta, gamma, params):
    """l(zeta, gamma) of eq. 1 (zenith angle and angle from the sun in rad), clamped at 0."""
    a, b, c, d, e = params
    with np.errstate(over="ignore", divide="ignore"):
        value = (1 + a * np.exp(b / np.cos(zeta))) * (1 + c * np.exp(d * gamma) + e * np.cos(gamma) ** 2)
    return np.maximum(value, 0.0)


def sky_vector(patches, sun_direction, direct_normal, diffuse_horizontal, day_of_year, dew_point_c=11.0,
               ground_reflectance=0.2, include_sky=True, include_sun=True, direct_normal_lux=None,
               diffuse_horizontal_lux=None):
    """Luminance (cd/m^2) of every patch (index 0 = ground) for one hour; see the module docstring.

    ``sun_direction``: unit vector towards the sun (+X east, +Y north, +Z up); irradiances in W/m^2;
    illuminances from the weather file may be given instead of the efficacy model. Returns
    (luminance (P,), info dict with epsilon, delta, parameters, diffuse/direct illuminance).
    """
    out = np.zeros(patches.count)
    s = np.asarray(sun_direction, float)
    altitude = np.arcsin(np.clip(s[2], -1, 1))
    info = {"epsilon": None, "delta": None, "parameters": None, "diffuse_lux": 0.0, "direct_normal_lux": 0.0}
    if not (direct_normal + diffuse_horizontal > 1e-4):
        return out, info
    z = float(clamp_zenith(np.pi / 2 - altitude))
    eps = float(clearness(direct_normal, diffuse_horizontal, z))
    delta = float(brightness(diffuse_horizontal, z, day_of_year))
    k_dif, k_dir = efficacy(eps, delta, z, dew_point_c)
    e_dh = float(diffuse_horizontal_lux) if diffuse_horizontal_lux is not None else diffuse_horizontal * float(k_dif)
    e_dn = float(direct_normal_lux) if direct_normal_lux is not None else direct_normal * float(k_dir)
    info.update(epsilon=eps, delta=delta, diffuse_lux=e_dh, direct_normal_lux=e_dn)
    ground = e_dh + (e_dn * np.sin(altitude) if altitude > 0 else 0.0)
    out[0] = ground_reflectance * ground / np.pi if include_sky else 0.0
    if include_sky:
        params = parameters(z, eps, delta)
        info["parameters"] = params
        zeta = np.pi / 2 - patches.altitude[1:]
        # angle between the patch centre and the sun, from the sun's clamped zenith and the azimuths
        az_s = np.arctan2(s[0], s[1])
        cos_g = np.cos(z) * np.cos(zeta) + np.sin(z) * np.sin(zeta) * np.cos(np.abs(patches.azimuth[1:] - az_s))
        lum = relative_luminance(zeta, np.arccos(np.clip(cos_g, -1, 1)), params)
        # E_dh of the piecewise-constant patch sky integrated exactly (as any daylight coefficient sees
        # it); gendaymtx's cos(centre) x solid angle makes that sky 0.55 % darker than E_dh (MF:1)
        norm = float(np.sum(lum * patches.cos_solid_angle[1:]))
        if norm <= 1e-12:
            lum, norm = np.ones_like(lum), np.pi
        out[1:] = lum * e_dh / norm
    if include_sun and e_dn > 1e-4 and altitude > -np.radians(0.533 / 2):
        dots = patches.direction[1:] @ s
        near = np.argsort(-dots)[:4]
        w = 1.0 / (1.002 - dots[near])
        out[1 + near] += w / w.sum() * e_dn / patches.solid_angle[1 + near]
    return out, info
