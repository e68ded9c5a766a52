"""Discomfort glare: the Unified Glare Rating of CIE 117-1995 (pure numpy).

    UGR = 8 log10( 0.25 / Lb * sum_i L_i^2 omega_i / p_i^2 )

- ``L_i`` (cd/m²): the luminance of source i's luminous parts towards the eye;
- ``omega_i`` (sr): the solid angle those parts subtend at the eye (here exact: :func:`polygon_solid_angle`,
  Van Oosterom & Strackee 1983, for a flat polygon; projected area / d² for an IES file's luminous
  opening, as CIE 117 defines it);
- ``p_i``: Guth's position index in Levin's closed form (IES Lighting Handbook; the same expression as
  Radiance's ``evalglare``):
  p = exp[(35.2 - 0.31889 tau - 1.22 exp(-2 tau / 9)) 1e-3 sigma + (21 + 0.26667 tau - 0.002963 tau²) 1e-5 sigma²],
  sigma (deg) the angle between the line of sight and the direction to the source, tau (deg) the angle
  between the vertical plane through the line of sight and the plane through the line of sight and the
  source (0 straight above the line of sight, 90 beside it);
- ``Lb`` (cd/m²): the background luminance, CIE 117's E_ind / pi with E_ind the *indirect* illuminance
  on the vertical plane at the eye (every luminaire's direct light left out).

CIE 117's field: Guth's position index was measured for sources *above* the line of sight and in front
of the eye, so only sources with an elevation above the horizontal plane through the line of sight and
sigma < 90 deg count (:func:`in_field`); the others are reported as left out. CIE 117 states UGR for
sources of 3e-4 sr to 0.1 sr; outside that range the rating is given with a note (CIE 147:2002 treats
small and large sources separately).

Coordinates: any right-handed frame with +Z up (Blender's), metres.
"""

import math

import numpy as np

__all__ = ["position_index", "view_angles", "in_field", "polygon_solid_angle", "disk_polygon", "ugr",
           "OMEGA_RANGE_SR"]

#: CIE 117-1995: the solid angles (sr) of the sources its formula was validated for.
OMEGA_RANGE_SR = (3e-4, 0.1)


def _unit(v):
    v = np.asarray(v, float)
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    if np.any(n == 0):
        raise ValueError("a direction has zero length")
    return v / n


def view_frame(view_direction, up=(0.0, 0.0, 1.0)):
    """(forward, up, right) unit vectors: ``up`` made orthogonal to the line of sight.

    A line of sight along ``up`` (looking straight up or down) has no vertical plane: ValueError.
    """
    f = _unit(view_direction)
    u = np.asarray(up, float) - (np.asarray(up, float) @ f) * f
    if np.linalg.norm(u) < 1e-9:
        raise ValueError("the line of sight is vertical: the position index needs a horizontal-ish view")
    u = _unit(u)
    return f, u, np.cross(f, u)


def view_angles(view_direction, directions, up=(0.0, 0.0, 1.0)):
    """(sigma, tau, elevation) in degrees for unit ``directions`` (..., 3) from the eye to the sources.

    sigma: angle from the line of sight; tau: angle of the plane (line of sight, source) from the
    vertical plane through the line of sight (0..180, 0 = straight above, > 90 below the line of sight);
    elevation: angle of the direction above the plane of the line of sight and the horizontal axis.
    """
    f, u, r = view_frame(view_direction, up)
    d = _unit(directions)
    sigma = np.degrees(np.arccos(np.clip(d @ f, -1.0, 1.0)))
    tau = np.degrees(np.arctan2(np.abs(d @ r), d @ u))
    elevation = np.degrees(np.arcsin(np.clip(d @ u, -1.0, 1.0)))
    return sigma, tau, elevation


def position_index(sigma_deg, tau_deg):
    """Guth's position index p in Levin's closed form (see module docstring); angles in degrees."""
    s = np.asarray(sigma_deg, float)
    t = np.asarray(tau_deg, float)
    return np.exp((35.2 - 0.31889 * t - 1.22 * np.exp(-2.0 * t / 9.0)) * 1e-3 * s
                  + (21.0 + 0.26667 * t - 0.002963 * t * t) * 1e-5 * s * s)


def in_field(sigma_deg, elevation_deg):
    """True where a source counts in CIE 117's field: above the line of sight and in front (sigma < 90)."""
    return (np.asarray(elevation_deg) > 0.0) & (np.asarray(sigma_deg) < 90.0)


def polygon_solid_angle(eye, vertices):
    """Exact solid angle (sr) of a flat polygon seen from ``eye``: a fan of triangles, each by Van
    Oosterom & Strackee (1983), tan(Omega/2) = |a.(b x c)| / (abc + (a.b)c + (a.c)b + (b.c)a).

    ``vertices`` (K, 3) in order around a convex polygon; the result does not depend on the winding.
    """
    p = np.asarray(vertices, float) - np.asarray(eye, float)
    total = 0.0
    for k in range(1, len(p) - 1):
        a, b, c = p[0], p[k], p[k + 1]
        la, lb, lc = np.linalg.norm(a), np.linalg.norm(b), np.linalg.norm(c)
        num = a @ np.cross(b, c)
        den = la * lb * lc + (a @ b) * lc + (a @ c) * lb + (b @ c) * la
        total += 2.0 * math.atan2(num, den)
    return abs(total)


def triangle_solid_angles(eye, triangles):
    """Exact solid angles (sr) of triangles (T, 3, 3) seen from ``eye`` (Van Oosterom & Strackee, as
    :func:`polygon_solid_angle`), vectorised; independent of the winding."""
    p = np.asarray(triangles, float).reshape(-1, 3, 3) - np.asarray(eye, float)
    a, b, c = p[:, 0], p[:, 1], p[:, 2]
    la, lb, lc = (np.linalg.norm(v, axis=1) for v in (a, b, c))
    num = np.einsum("ij,ij->i", a, np.cross(b, c))
    den = (la * lb * lc + np.einsum("ij,ij->i", a, b) * lc + np.einsum("ij,ij->i", a, c) * lb
           + np.einsum("ij,ij->i", b, c) * la)
    return np.abs(2.0 * np.arctan2(num, den))


def patches_as_one_source(centres, areas, luminances, solid_angles):
    """One CIE 117 source made of patches (an emitting mesh's triangles): (L cd/m², omega sr, centre m).

    omega = the sum of the patches' solid angles; L = sqrt(sum L_i^2 omega_i / omega), so that
    L^2 omega / p^2 is the sum of the patches' terms at one position index p (exact for a uniform
    luminance, which is what CIE 117 assumes of a luminaire); the centre, where p is taken, is the
    centre of the luminous area (area-weighted mean of the patch centres), as for a luminaire.
    """
    w = np.asarray(solid_angles, float)
    a = np.asarray(areas, float)
    omega = float(w.sum())
    if not omega > 0 or not a.sum() > 0:
        return 0.0, 0.0, np.zeros(3)
    centre = (a[:, None] * np.asarray(centres, float)).sum(axis=0) / a.sum()
    return float(np.sqrt(w @ np.asarray(luminances, float) ** 2 / omega)), omega, centre


def disk_polygon(centre, edge_u, edge_v, sides=2048):
    """Vertices of an ellipse (full diameters ``edge_u``, ``edge_v``) as an inscribed ``sides``-gon.

    The polygon's area is sin(2 pi / n) n / (2 pi) of the ellipse's: 1.6e-6 relative short at 2048
    sides, the error of a solid angle computed from it (the disk's own solid angle is not elementary
    off its axis).
    """
    phi = 2 * np.pi * np.arange(sides) / sides
    return (np.asarray(centre, float) + 0.5 * np.cos(phi)[:, None] * np.asarray(edge_u, float)
            + 0.5 * np.sin(phi)[:, None] * np.asarray(edge_v, float))


def ugr(background_luminance, luminances, solid_angles, position_indices):
    """CIE 117 UGR of sources (cd/m², sr, position index) over a background luminance Lb (cd/m²).

    No sources (or all dark) gives -inf (no glare at all; CIE tables would print "< 10"). Lb <= 0:
    ValueError (the formula has no meaning without a background).
    """
    lb = float(background_luminance)
    if not lb > 0 or not math.isfinite(lb):
        raise ValueError(f"the background luminance must be > 0 cd/m², got {lb}")
    L = np.asarray(luminances, float)
    w = np.asarray(solid_angles, float)
    p = np.asarray(position_indices, float)
    s = float(np.sum(L * L * w / (p * p)))
    if s <= 0:
        return -math.inf
    return 8.0 * math.log10(0.25 / lb * s)


def projected_opening_area(width_m, length_m, height_m, gamma_deg):
    """Projected area (m²) of an IES luminous opening seen at ``gamma_deg`` from the nadir.

    LM-63 shapes: width, length > 0 and height 0: a flat rectangle (w l cos gamma); width = length < 0,
    height 0: a flat circle of diameter |w| (pi w² / 4 cos gamma). None for anything else (points,
    luminous sides, spheres and cylinders are not modelled here). Seen from above (gamma >= 90): 0.
    """
    w, l, h = float(width_m), float(length_m), float(height_m)
    c = max(math.cos(math.radians(gamma_deg)), 0.0)
    if h != 0:
        return None
    if w > 0 and l > 0:
        return w * l * c
    if w < 0 and l < 0 and abs(w - l) <= 1e-9 * abs(w):
        return math.pi * w * w / 4 * c
    return None


def luminous_opening_m(metadata):
    """(width, length, height) in metres of a photometric file's luminous opening, from the reader's
    metadata (``radiometry.photometry.photometric_files``): LM-63 in feet (units type 1) or metres (2), EULUMDAT
    in mm (width 0: a circle of diameter = the length, written here as LM-63 does, negative).
    None when the file gives no opening."""
    md = metadata or {}
    if "luminous_width" in md:
        k = 0.3048 if int(md.get("units_type", 2)) == 1 else 1.0
        w, l, h = (float(md.get(key) or 0.0) * k for key in ("luminous_width", "luminous_length", "luminous_height"))
    elif "luminous_length_mm" in md:
        w, l = float(md.get("luminous_width_mm") or 0.0) / 1000, float(md.get("luminous_length_mm") or 0.0) / 1000
        heights = [float(md.get(f"luminous_height_c{c}_mm") or 0.0) for c in (0, 90, 180, 270)]
        h = max(heights) / 1000
        if w == 0 and l > 0:
            w = l = -l
    else:
        return None
    if w == 0 and l == 0:
        return None
    return w, l, h
