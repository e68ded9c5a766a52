"""CIE standard general skies (pure numpy): relative luminance, zenith luminance from the horizontal
illuminance, and the exact illuminance on any plane under the sky and a uniform ground.

Sky models
----------
* Types 1-15 of ISO 15469:2004 / CIE S 011/E:2003 ("Spatial distribution of daylight - CIE standard
  general sky"), relative luminance of a sky element at zenith angle Z and angle chi from the sun
  (sun zenith angle Zs)::

      L / Lz = f(chi) phi(Z) / (f(Zs) phi(0))
      phi(Z) = 1 + a exp(b / cos Z)          (0 <= Z < 90 deg; phi(90 deg) = 1)
      f(chi) = 1 + c (exp(d chi) - exp(d pi / 2)) + e cos^2 chi

  with the gradation parameters a, b and indicatrix parameters c, d, e of the standard's Table 1
  (``CIE_GENERAL_SKIES``; the same table as S. Darula, R. Kittler, "CIE general sky standard
  defining luminance distributions", Proc. eSim 2002, Table 1). Types 1, 3 and 5 have c = e = 0:
  they do not depend on the sun.
* ``"overcast"``: the traditional CIE overcast sky (Moon & Spencer 1942, CIE 1955),
  L = Lz (1 + 2 cos Z) / 3, for which E_h = 7 pi Lz / 9.

The sun's disc is NOT part of any of these skies (a Sun light does that); the circumsolar region is.

Ground and horizon
------------------
Below a SHARP horizon the ground is uniform, of luminance Lg = rho_g E_h / pi (E_h = the sky's
unobstructed horizontal illuminance), so a plane with unit normal n receives from the ground
E_g = rho_g E_h (1 - n_z) / 2 exactly. (Radiance's ``gensky`` blends sky and ground glow over
about +-10 deg around the horizon instead; Radiometer does not.)

Quadrature (``sky_integral``)
-----------------------------
I(n) = integral over the upper hemisphere of g(w) max(0, n . w) dw, g = f(chi) phi(Z), is computed
in spherical coordinates (chi, psi) whose pole is the sun (the zenith for sun-independent skies), so
the circumsolar cusp exp(d chi) becomes a smooth function of chi. Along each half great circle
psi = const from the pole, both constraints (w_z > 0 and n . w > 0) have the form
A cos chi + B sin chi > 0, whose solution is an interval found in closed form; the integrand is
smooth on their intersection, which is integrated by Gauss-Legendre on two panels. The integral
over psi is piecewise smooth, with kinks only at the rays through the two points where the horizon
and the plane's horizon cross (+-(z x n)) and where a constraint's B changes sign; psi is split at
those points and each piece integrated by Gauss-Legendre. The returned error estimate is
|I(order) - I(order / 2)|, a generous bound for the higher order (tests: < 1e-9 relative for every
type, sun position and tilt tried; the difference to an independent brute-force integration is
below 1e-6).

All angles in radians inside, directions as unit vectors (+Z up, +Y north, +X east); illuminance in
lux, luminance in cd/m^2.
"""

import numpy as np

from ..emitters.environment import EnvironmentEmitter

__all__ = ["CIE_GENERAL_SKIES", "SKY_TYPES", "TYPICAL_HORIZONTAL_ILLUMINANCE", "parse_sky_type", "parameters",
           "needs_sun", "relative_luminance", "sky_integral", "zenith_luminance", "plane_illuminance",
           "ground_luminance", "CIESkyWorld"]

#: ISO 15469:2004 / CIE S 011/E:2003 Table 1: type -> (gradation group, indicatrix group, a, b, c, d, e, description).
CIE_GENERAL_SKIES = {
    1: ("I", 1, 4.0, -0.70, 0.0, -1.0, 0.00, "CIE standard overcast sky, steep luminance gradation towards zenith, azimuthal uniformity"),
    2: ("I", 2, 4.0, -0.70, 2.0, -1.5, 0.15, "overcast, steep luminance gradation and slight brightening towards the sun"),
    3: ("II", 1, 1.1, -0.80, 0.0, -1.0, 0.00, "overcast, moderately graded, azimuthal uniformity"),
    4: ("II", 2, 1.1, -0.80, 2.0, -1.5, 0.15, "overcast, moderately graded and slight brightening towards the sun"),
    5: ("III", 1, 0.0, -1.00, 0.0, -1.0, 0.00, "sky of uniform luminance"),
    6: ("III", 2, 0.0, -1.00, 2.0, -1.5, 0.15, "partly cloudy sky, no gradation towards zenith, slight brightening towards the sun"),
    7: ("III", 3, 0.0, -1.00, 5.0, -2.5, 0.30, "partly cloudy sky, no gradation towards zenith, brighter circumsolar region"),
    8: ("III", 4, 0.0, -1.00, 10.0, -3.0, 0.45, "partly cloudy sky, no gradation towards zenith, distinct solar corona"),
    9: ("IV", 2, -1.0, -0.55, 2.0, -1.5, 0.15, "partly cloudy, with the obscured sun"),
    10: ("IV", 3, -1.0, -0.55, 5.0, -2.5, 0.30, "partly cloudy, with brighter circumsolar region"),
    11: ("IV", 4, -1.0, -0.55, 10.0, -3.0, 0.45, "white-blue sky with distinct solar corona"),
    12: ("V", 4, -1.0, -0.32, 10.0, -3.0, 0.45, "CIE standard clear sky, low luminance turbidity"),
    13: ("V", 5, -1.0, -0.32, 16.0, -3.0, 0.30, "CIE standard clear sky, polluted atmosphere"),
    14: ("VI", 5, -1.0, -0.15, 16.0, -3.0, 0.30, "cloudless turbid sky with broad solar corona"),
    15: ("VI", 6, -1.0, -0.15, 24.0, -2.8, 0.15, "white-blue turbid sky with broad solar corona"),
}
#: Every accepted sky type: the 15 ISO types and the traditional overcast sky.
SKY_TYPES = ("overcast",) + tuple(CIE_GENERAL_SKIES)
#: Default unobstructed horizontal illuminance (lux) when none is given: 10 000 lx, the overcast-sky
#: design value of daylight-factor practice (CIBSE LG10; EN 17037's median values are 10-20 klx in Europe).
TYPICAL_HORIZONTAL_ILLUMINANCE = 10_000.0

_ORDER = 48  # Gauss-Legendre nodes per panel (psi pieces and each of the two chi panels)


def parse_sky_type(sky_type):
    """``"overcast"`` or an int 1..15 (also "7", "cie7", "cie:7"); raises ValueError otherwise."""
    if isinstance(sky_type, str):
        s = sky_type.strip().lower()
        if s == "overcast":
            return "overcast"
        for prefix in ("cie:", "cie", "type"):
            if s.startswith(prefix):
                s = s[len(prefix):]
                break
        try:
            sky_type = int(s)
        except ValueError:
            raise ValueError(f"unknown sky type {sky_type!r}: use 'overcast' or a CIE general sky type 1..15") from None
    if isinstance(sky_type, (bool, float)) or not isinstance(sky_type, (int, np.integer)) or int(sky_type) not in CIE_GENERAL_SKIES:
        raise ValueError(f"unknown sky type {sky_type!r}: use 'overcast' or a CIE general sky type 1..15")
    return int(sky_type)


def parameters(sky_type):
    """(a, b, c, d, e) of an ISO type, or None for the traditional overcast sky."""
    t = parse_sky_type(sky_type)
    return None if t == "overcast" else tuple(CIE_GENERAL_SKIES[t][2:7])


def needs_sun(sky_type):
    """True when the sky's luminance depends on the sun's position (c or e not 0)."""
    p = parameters(sky_type)
    return p is not None and (p[2] != 0.0 or p[4] != 0.0)


def _unit(v, name):
    v = np.asarray(v, float)
    if v.shape != (3,) or not np.all(np.isfinite(v)) or np.linalg.norm(v) == 0:
        raise ValueError(f"{name} must be a finite non-zero 3-vector, got {v.tolist() if v.ndim else v}")
    return v / np.linalg.norm(v)


def sun_for_sky(sky_type, sun_direction):
    """The unit sun direction, or +Z when the sky does not depend on it; ValueError when it is needed and
    missing or below the horizon."""
    if not needs_sun(sky_type):
        return np.array([0.0, 0.0, 1.0])
    if sun_direction is None:
        raise ValueError(f"CIE sky type {sky_type} depends on the sun: give sun_direction")
    s = _unit(sun_direction, "sun_direction")
    if s[2] < 0.0:
        raise ValueError(f"the sun is below the horizon (elevation {np.degrees(np.arcsin(s[2])):.3g} deg): "
                         "the CIE general skies are defined for a sun at or above it")
    return s


def _gradation(cos_z, a, b):
    """phi(Z) for cos Z > 0 (the horizon value phi = 1 is the limit, reached smoothly since b < 0)."""
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        return 1.0 + a * np.exp(b / np.maximum(cos_z, 1e-300))


def _indicatrix(cos_chi, c, d, e):
    chi = np.arccos(np.clip(cos_chi, -1.0, 1.0))
    return 1.0 + c * (np.exp(d * chi) - np.exp(d * np.pi / 2)) + e * cos_chi ** 2


def _shape(w, sky_type, sun):
    """Unnormalised g(w) = f(chi) phi(Z) (ISO) or 1 + 2 cos Z (overcast) for directions above the horizon."""
    p = parameters(sky_type)
    cos_z = w[..., 2]
    if p is None:
        return 1.0 + 2.0 * cos_z
    a, b, c, d, e = p
    return _indicatrix(w @ sun, c, d, e) * _gradation(cos_z, a, b)


def zenith_shape(sky_type, sun):
    """The unnormalised shape g at the zenith (the divisor that makes L / Lz = 1 there)."""
    return float(_shape(np.array([0.0, 0.0, 1.0]), sky_type, sun))


def relative_luminance(directions, sky_type, sun_direction=None):
    """L / Lz of the sky for unit ``directions`` (..., 3); 0 at and below the horizon (the sky only).

    Non-finite or zero directions give NaN.
    """
    t = parse_sky_type(sky_type)
    sun = sun_for_sky(t, sun_direction)
    w = np.asarray(directions, float)
    with np.errstate(invalid="ignore", divide="ignore"):
        w = w / np.linalg.norm(w, axis=-1, keepdims=True)
    rel = _shape(w, t, sun) / zenith_shape(t, sun)
    out = np.where(w[..., 2] > 0.0, rel, 0.0)
    return np.where(np.all(np.isfinite(w), axis=-1), out, np.nan)


# --- exact integration -------------------------------------------------------------------------------

def _frame(pole):
    """Two unit vectors u, v with (u, v, pole) right-handed."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(pole[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    u = np.cross(helper, pole)
    u /= np.linalg.norm(u)
    return u, np.cross(pole, u)


def _positive_interval(a, b):
    """For A cos x + B sin x > 0 on x in [0, pi]: (lo, hi), empty when lo >= hi (arrays broadcast)."""
    delta = np.arctan2(b, a)  # A cos x + B sin x = R cos(x - delta)
    delta = np.where(delta < -np.pi / 2, delta + 2 * np.pi, delta)
    lo = np.clip(delta - np.pi / 2, 0.0, np.pi)
    hi = np.clip(delta + np.pi / 2, 0.0, np.pi)
    return lo, hi


def _split_angles(k, pole, u, v):
    """psi (<= 2 values) where B_k(psi) = (k . u) cos psi + (k . v) sin psi changes sign."""
    p, q = k @ u, k @ v
    if abs(p) < 1e-15 and abs(q) < 1e-15:
        return []
    base = np.arctan2(-p, q)  # p cos + q sin = 0
    return [base % (2 * np.pi), (base + np.pi) % (2 * np.pi)]


def _psi_of(w, pole, u, v):
    return float(np.arctan2(w @ v, w @ u) % (2 * np.pi))


def _integral_one(n, sky_type, sun, order):
    """I(n) for one unit normal at Gauss-Legendre order ``order``."""
    z = np.array([0.0, 0.0, 1.0])
    pole = sun
    u, v = _frame(pole)
    cuts = [0.0, 2 * np.pi]
    for k in (z, n):
        cuts += _split_angles(k, pole, u, v)
    cross = np.cross(z, n)
    if np.linalg.norm(cross) > 1e-12:
        cross /= np.linalg.norm(cross)
        for w in (cross, -cross):
            if abs(w @ pole) < 1.0 - 1e-14:
                cuts.append(_psi_of(w, pole, u, v))
    cuts = np.unique(np.clip(cuts, 0.0, 2 * np.pi))
    x, wts = np.polynomial.legendre.leggauss(order)
    a0, a1 = cuts[:-1], cuts[1:]
    psi = (a0[:, None] + a1[:, None]) / 2 + (a1 - a0)[:, None] / 2 * x          # (P, m)
    wpsi = (a1 - a0)[:, None] / 2 * wts                                          # (P, m)
    psi, wpsi = psi.ravel(), wpsi.ravel()
    cp, sp = np.cos(psi), np.sin(psi)
    lo, hi = 0.0, np.pi
    for k in (z, n):
        bk = (k @ u) * cp + (k @ v) * sp
        l_k, h_k = _positive_interval(np.full_like(bk, k @ pole), bk)
        lo, hi = np.maximum(lo, l_k), np.minimum(hi, h_k)
    length = np.maximum(hi - lo, 0.0)
    # Two chi panels per ray: [lo, mid], [mid, hi].
    t = np.concatenate([(x + 1) / 4, (x + 1) / 4 + 0.5])                        # (2m,) in [0, 1]
    wt = np.concatenate([wts, wts]) / 4
    chi = lo[:, None] + length[:, None] * t                                      # (R, 2m)
    wchi = length[:, None] * wt
    sc, cc = np.sin(chi), np.cos(chi)
    w = (cc[..., None] * pole + sc[..., None] * (cp[:, None, None] * u + sp[:, None, None] * v))
    g = _shape(w, sky_type, sun) * np.maximum(w @ n, 0.0) * sc
    g = np.where(w[..., 2] > 0.0, g, 0.0)
    return float(np.sum(wpsi * np.sum(wchi * g, axis=1)))


def sky_integral(normals, sky_type, sun_direction=None, *, order=_ORDER):
    """(I, error): I(n) = integral over the sky (Z < 90 deg) of (L / Lz) max(0, n . w) dw, sr.

    So a sky of zenith luminance Lz gives E = Lz I(n) on a plane facing ``normals`` (..., 3). See
    the module docstring for the quadrature; ``error`` = |I(order) - I(order / 2)|. Non-finite or
    zero normals give NaN.
    """
    t = parse_sky_type(sky_type)
    sun = sun_for_sky(t, sun_direction)
    n = np.asarray(normals, float)
    shape = n.shape[:-1]
    if n.shape[-1:] != (3,):
        raise ValueError(f"normals must have shape (..., 3), got {n.shape}")
    flat = n.reshape(-1, 3)
    zeta = zenith_shape(t, sun)
    out = np.full(len(flat), np.nan)
    err = np.full(len(flat), np.nan)
    for i, nk in enumerate(flat):
        length = np.linalg.norm(nk) if np.all(np.isfinite(nk)) else 0.0
        if not length > 0.0:
            continue
        nk = nk / length
        hi = _integral_one(nk, t, sun, order)
        lo = _integral_one(nk, t, sun, max(order // 2, 2))
        out[i], err[i] = hi / zeta, abs(hi - lo) / zeta
    return out.reshape(shape), err.reshape(shape)


def zenith_luminance(horizontal_illuminance, sky_type, sun_direction=None):
    """Lz (cd/m^2) giving the unobstructed horizontal illuminance (lux); the overcast sky: 9 E_h / (7 pi)."""
    e_h = np.asarray(horizontal_illuminance, float)
    i_h, _err = sky_integral(np.array([0.0, 0.0, 1.0]), sky_type, sun_direction)
    return e_h / float(i_h)


def ground_luminance(horizontal_illuminance, ground_reflectance=0.2):
    """Lg = rho_g E_h / pi (cd/m^2) of the uniform Lambertian ground below the sharp horizon."""
    return np.asarray(ground_reflectance, float) * np.asarray(horizontal_illuminance, float) / np.pi


def plane_illuminance(normals, sky_type, sun_direction=None, *, horizontal_illuminance=TYPICAL_HORIZONTAL_ILLUMINANCE,
                      ground_reflectance=0.2):
    """(E, error) lux on unobstructed planes facing ``normals`` (..., 3): sky + ground.

    E = Lz I(n) + rho_g E_h (1 - n_z) / 2 with Lz from ``zenith_luminance`` (module docstring).
    """
    e_h = float(horizontal_illuminance)
    if not (np.isfinite(e_h) and e_h >= 0.0):
        raise ValueError(f"horizontal_illuminance must be a finite number >= 0 lux, got {horizontal_illuminance!r}")
    rho = float(ground_reflectance)
    if not (np.isfinite(rho) and 0.0 <= rho <= 1.0):
        raise ValueError(f"ground_reflectance must be within 0..1, got {ground_reflectance!r}")
    n = np.asarray(normals, float)
    i_n, err = sky_integral(n, sky_type, sun_direction)
    i_h, err_h = sky_integral(np.array([0.0, 0.0, 1.0]), sky_type, sun_direction)
    lz = e_h / float(i_h)
    with np.errstate(invalid="ignore", divide="ignore"):
        nz = n[..., 2] / np.linalg.norm(n, axis=-1)
    e = lz * i_n + rho * e_h * (1.0 - nz) / 2.0
    return e, lz * err + lz * float(err_h) * np.abs(i_n) / float(i_h)


# --- the world as pure data (the meter's interface, like environment.WorldLight) ------------------------

class CIESkyWorld(EnvironmentEmitter):
    """A Radiometer CIE sky world, as the meter integrates it (``measure.authoring.world`` recognises the tag).

    Radiance (W/(m^2 sr), per scene unit^2 like every world) is ``zenith_radiance`` x L/Lz above the
    horizon and ``ground_radiance`` below, the same in R, G and B (white). ``irradiance(normals)``
    returns (E (..., 3), error (..., 3)) like ``environment.WorldLight.irradiance``; an emitter
    (:class:`.emitters.environment.EnvironmentEmitter`).
    """

    kind = "cie_sky"
    modelled = True
    image = ""
    interpolation = ""
    supersample = 1
    reason = ""

    def __init__(self, sky_type, sun_direction, zenith_radiance, ground_radiance, *, strength=1.0, node="", notes=()):
        self.sky_type = parse_sky_type(sky_type)
        self.sun_direction = sun_for_sky(self.sky_type, sun_direction)
        self.zenith_radiance = float(zenith_radiance)
        self.ground_radiance = float(ground_radiance)
        self.strength = float(strength)
        self.node = node
        self.exact = True
        self.notes = list(notes)

    def radiance_of(self, directions):
        """Radiance (...,) for world directions: the sky above the horizon, the ground below."""
        w = np.asarray(directions, float)
        rel = relative_luminance(w, self.sky_type, self.sun_direction)
        return np.where(w[..., 2] > 0.0, self.zenith_radiance * rel, np.where(np.isnan(rel), np.nan, self.ground_radiance))

    def irradiance(self, normals):
        n = np.asarray(normals, float)
        i_n, err = sky_integral(n, self.sky_type, self.sun_direction)
        with np.errstate(invalid="ignore", divide="ignore"):
            nz = n[..., 2] / np.linalg.norm(n, axis=-1)
        e = self.zenith_radiance * i_n + self.ground_radiance * np.pi * (1.0 - nz) / 2.0
        e3 = np.repeat(e[..., None], 3, axis=-1)
        return e3, np.repeat((self.zenith_radiance * err)[..., None], 3, axis=-1)

    def as_map(self, height=64, width=128):
        """An equirect map sampled at pixel centres (Environment Texture orientation): an illustration,
        not what the meter integrates."""
        from .environment import BLENDER_WORLD_ROTATION, pixel_directions

        d, _solid = pixel_directions(height, width, BLENDER_WORLD_ROTATION)
        value = self.radiance_of(d)
        return np.repeat(value[..., None], 3, axis=-1), BLENDER_WORLD_ROTATION

    def sampled_map(self):
        return self.as_map()[0]

    def brightest(self, weights=(0.2126, 0.7152, 0.0722)):
        """(direction, RGB radiance) of the brightest sky direction (sampled finely near the sun and zenith)."""
        cands = [np.array([0.0, 0.0, 1.0]), self.sun_direction]
        lmap, rot = self.as_map(180, 360)
        from .environment import pixel_directions

        d, _s = pixel_directions(180, 360, rot)
        cands += list(d.reshape(-1, 3)[np.argsort(lmap[..., 0].ravel())[-4:]])
        cands = np.array(cands)
        cands[:, 2] = np.maximum(cands[:, 2], 1e-9)
        values = self.radiance_of(cands)
        k = int(np.argmax(values))
        return cands[k] / np.linalg.norm(cands[k]), np.full(3, values[k])

    def scaled(self, factor):
        return CIESkyWorld(self.sky_type, self.sun_direction, self.zenith_radiance * factor,
                           self.ground_radiance * factor, strength=self.strength * factor, node=self.node,
                           notes=self.notes)
