"""An independent spectral reference for issue 35: numpy radiosity of a closed Lambertian box, 5 nm steps.

Test and bench code only (never imported by the product). The box is 4 x 3 x 2.7 m (x, y, z), its four
walls the saturated **red** of the ColorChecker, its ceiling the ColorChecker's **white 9.5** and its
floor **neutral 8** (reflectance spectra: Ohta's ColorChecker data as colour-science 0.4.6 ships them,
380-780 nm at 5 nm). One isotropic point light of known spectrum hangs inside it.

Method (everything at 5 nm, 380-780 nm, 81 wavelengths):

- every face is cut into square-ish patches of side <= ``h``; radiosity is constant per patch;
- the direct irradiance of patch i is exact: I(lambda) Omega_i / A_i, Omega_i the solid angle the patch
  subtends at the light (Van Oosterom-Strackee, two triangles);
- form factors F_ij = (1/A_i) integral over patch i of the exact point-to-polygon form factor to
  patch j (Lambert's contour formula), by a q x q Gauss-Legendre rule over patch i; the box is convex,
  so nothing is occluded;
- per wavelength: (I - diag(rho) F) B = rho E0 (every bounce: a linear solve, no truncation);
- at the meter: E(lambda) = I(lambda) cos / d^2 (direct, closed form) + sum_j B_j F_meter->j, the meter's
  form factors exact (polygons clipped at the meter's plane).

E_v = K sum E V 5 nm (K = the scene's efficacy, 683 lm/W), alpha-opic irradiance sum E s_alpha 5 nm (W/m^2),
alpha-opic EDI = K sum E s_alpha 5 nm x (sum D65 V / sum D65 s_alpha) (lx), with CIE S 026's action
spectra and V(lambda) sampled at 5 nm. The only approximation is the piecewise-constant radiosity: it is
shown to converge by refinement (docs/spectral.md, ``bench/spectral_room.md``); the pure checks are in
``tests/test_spectral_bands.py``.
"""

import numpy as np

WAVELENGTHS_NM = np.arange(380.0, 781.0, 5.0)
STEP_NM = 5.0
BOX_M = (4.0, 3.0, 2.7)
LIGHT_M = (1.6, 1.4, 2.1)
LIGHT_POWER_W = 100.0
#: Meters: (location m, unit normal). A vertical one at seated eye level facing the room, a desk one facing up.
METERS = {"eye": ((3.2, 1.1, 1.2), (-1.0, 0.0, 0.0)), "desk": ((2.8, 2.2, 0.8), (0.0, 0.0, 1.0))}

_X, _Y, _Z = BOX_M
#: Faces as corner lists, counter-clockwise seen from inside (the normal points into the box).
FACES = {
    "floor": np.array([(0, 0, 0), (_X, 0, 0), (_X, _Y, 0), (0, _Y, 0)], float),
    "ceiling": np.array([(0, 0, _Z), (0, _Y, _Z), (_X, _Y, _Z), (_X, 0, _Z)], float),
    "wall y0": np.array([(0, 0, 0), (0, 0, _Z), (_X, 0, _Z), (_X, 0, 0)], float),
    "wall y1": np.array([(0, _Y, 0), (_X, _Y, 0), (_X, _Y, _Z), (0, _Y, _Z)], float),
    "wall x0": np.array([(0, 0, 0), (0, _Y, 0), (0, _Y, _Z), (0, 0, _Z)], float),
    "wall x1": np.array([(_X, 0, 0), (_X, 0, _Z), (_X, _Y, _Z), (_X, _Y, 0)], float),
}
FACE_GROUPS = {"red walls": ["wall y0", "wall y1", "wall x0", "wall x1"], "ceiling": ["ceiling"], "floor": ["floor"]}
MATERIAL_OF = {"red walls": "red", "ceiling": "white 9.5 (.05 D)", "floor": "neutral 8 (.23 D)"}

#: The daylit variant (the world's light, issue 35): wall y0 has a floor-to-ceiling opening over x in
#: WINDOW_X_M. A uniform world of radiance L seen through it makes the opening a Lambertian emitter of
#: radiance L towards the room (every inward direction from it sees the world), and it reflects nothing
#: (light that leaves through it is lost; the walls' outer sides cannot send light into it: they face away
#: from it or lie in its plane). No light hangs in the room.
WINDOW_X_M = (1.2, 2.8)
_W0, _W1 = WINDOW_X_M
FACES_DAYLIT = {k: v for k, v in FACES.items() if k != "wall y0"} | {
    "wall y0 left": np.array([(0, 0, 0), (0, 0, _Z), (_W0, 0, _Z), (_W0, 0, 0)], float),
    "wall y0 right": np.array([(_W1, 0, 0), (_W1, 0, _Z), (_X, 0, _Z), (_X, 0, 0)], float),
    "window": np.array([(_W0, 0, 0), (_W0, 0, _Z), (_W1, 0, _Z), (_W1, 0, 0)], float),
}
FACE_GROUPS_DAYLIT = {"red walls": ["wall y0 left", "wall y0 right", "wall y1", "wall x0", "wall x1"],
                      "ceiling": ["ceiling"], "floor": ["floor"], "window": ["window"]}


def reflectance(name):
    """ColorChecker reflectance ``name`` (Ohta, colour-science 0.4.6) at :data:`WAVELENGTHS_NM`."""
    import colour

    sd = colour.SDS_COLOURCHECKERS["ColorChecker N Ohta"][name]
    return np.interp(WAVELENGTHS_NM, sd.wavelengths, sd.values)


def _cmfs():
    import colour

    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    return np.stack([np.interp(WAVELENGTHS_NM, cmfs.wavelengths, cmfs.values[:, k]) for k in range(3)], axis=1)


def _d65():
    import colour

    sd = colour.SDS_ILLUMINANTS["D65"]
    return np.interp(WAVELENGTHS_NM, sd.wavelengths, sd.values)


def rec709_of_reflectance(refl):
    """Linear Rec.709 RGB of a reflectance under D65 (white reflectance 1 -> (1, 1, 1)): the base colour a
    user would give the material (colour-science's XYZ -> Rec.709 matrix)."""
    import colour

    xyz = (refl * _d65()) @ _cmfs()
    xyz_w = _d65() @ _cmfs()
    rgb = colour.RGB_COLOURSPACES["ITU-R BT.709"].matrix_XYZ_to_RGB @ (xyz / xyz_w[1])
    white = colour.RGB_COLOURSPACES["ITU-R BT.709"].matrix_XYZ_to_RGB @ (xyz_w / xyz_w[1])
    return np.clip(rgb / white, 0.0, None)


def action_spectra():
    """(V, {alpha: s_alpha}) at 5 nm, sampled from CIE's 1 nm tables (CIE S 026 Table 2, CIE 018 V)."""
    from radiometer.radiometry.photometry import _spectral_tables as t

    take = slice(0, None, 5)
    return t.PHOTOPIC_V_1NM[take], {"s_cone": t.S026_S_CONE[take], "m_cone": t.S026_M_CONE[take],
                                     "l_cone": t.S026_L_CONE[take], "rhodopic": t.S026_RHODOPIC[take],
                                     "melanopic": t.S026_MELANOPIC[take]}


# --- geometry -------------------------------------------------------------------------------------

def patches(h, daylit=False):
    """(corners (P, 4, 3), normals (P, 3), areas (P,), face group name per patch) of side <= h m; ``daylit``:
    the box with its opening (:data:`FACES_DAYLIT`)."""
    faces_of, groups = (FACES_DAYLIT, FACE_GROUPS_DAYLIT) if daylit else (FACES, FACE_GROUPS)
    corners, names = [], []
    for group, faces in groups.items():
        for face in faces:
            c = faces_of[face]
            u, v = c[1] - c[0], c[3] - c[0]
            nu, nv = int(np.ceil(np.linalg.norm(u) / h - 1e-9)), int(np.ceil(np.linalg.norm(v) / h - 1e-9))
            for i in range(nu):
                for j in range(nv):
                    p0 = c[0] + u * i / nu + v * j / nv
                    corners.append([p0, p0 + u / nu, p0 + u / nu + v / nv, p0 + v / nv])
                    names.append(group)
    corners = np.array(corners)
    n = np.cross(corners[:, 1] - corners[:, 0], corners[:, 3] - corners[:, 0])
    areas = np.linalg.norm(n, axis=1)
    return corners, n / areas[:, None], areas, np.array(names)


def point_to_polygon_ff(points, normals, polys):
    """Exact form factor from differential areas (points (P, 3), normals (P, 3)) to convex polygons wholly in
    front of them (polys (Q, K, 3)), Lambert's contour formula: shape (P, Q)."""
    r = polys[None, :, :, :] - points[:, None, None, :]  # (P, Q, K, 3)
    r /= np.linalg.norm(r, axis=-1, keepdims=True)
    r2 = np.roll(r, -1, axis=2)
    cross = np.cross(r, r2)
    sin = np.linalg.norm(cross, axis=-1)
    cos = np.clip(np.sum(r * r2, axis=-1), -1.0, 1.0)
    gamma = np.arctan2(sin, cos)
    with np.errstate(invalid="ignore", divide="ignore"):
        unit = np.where(sin[..., None] > 0, cross / sin[..., None], 0.0)
    total = np.einsum("pqk,pqkc,pc->pq", gamma, unit, normals)
    return np.abs(total) / (2.0 * np.pi)


def clip_polygon(poly, point, normal, eps=1e-12):
    """The part of a convex polygon (K, 3) on the side ``normal`` faces of the plane through ``point``."""
    d = (poly - point) @ normal
    out = []
    for k in range(len(poly)):
        a, b, da, db = poly[k], poly[(k + 1) % len(poly)], d[k], d[(k + 1) % len(poly)]
        if da > eps:
            out.append(a)
        if (da > eps) != (db > eps) and abs(da - db) > 0:
            out.append(a + (b - a) * (da / (da - db)))
    return np.array(out)


def gather_ff(point, normal, corners):
    """Exact form factor from a meter (point, normal) to every patch (clipped at the meter's plane), (P,)."""
    point, normal = np.asarray(point, float), np.asarray(normal, float)
    ff = np.zeros(len(corners))
    for k, poly in enumerate(corners):
        clipped = clip_polygon(poly, point, normal)
        if len(clipped) >= 3:
            ff[k] = point_to_polygon_ff(point[None], normal[None], clipped[None])[0, 0]
    return ff


def _triangle_solid_angle(o, a, b, c):
    ra, rb, rc = a - o, b - o, c - o
    la, lb, lc = (np.linalg.norm(x, axis=-1) for x in (ra, rb, rc))
    num = np.abs(np.einsum("...c,...c->...", ra, np.cross(rb, rc)))
    den = la * lb * lc + np.einsum("...c,...c->...", ra, rb) * lc + np.einsum("...c,...c->...", ra, rc) * lb \
        + np.einsum("...c,...c->...", rb, rc) * la
    return 2.0 * np.arctan2(num, den)


def patch_solid_angles(corners, light):
    """Solid angle (sr) of every quad patch from the light (exact, two triangles)."""
    o = np.asarray(light, float)
    return (_triangle_solid_angle(o, corners[:, 0], corners[:, 1], corners[:, 2])
            + _triangle_solid_angle(o, corners[:, 0], corners[:, 2], corners[:, 3]))


def form_factors(corners, normals, q=3, chunk=64):
    """F_ij (P, P): Gauss-Legendre q x q over patch i of the exact point-to-polygon form factor to j."""
    g, w = np.polynomial.legendre.leggauss(q)
    g, w = (g + 1.0) / 2.0, w / 2.0
    s, t = np.meshgrid(g, g, indexing="ij")
    ww = np.outer(w, w).ravel()
    p0, u, v = corners[:, 0], corners[:, 1] - corners[:, 0], corners[:, 3] - corners[:, 0]
    pts = p0[:, None] + s.ravel()[None, :, None] * u[:, None] + t.ravel()[None, :, None] * v[:, None]  # (P, q², 3)
    n = len(corners)
    f = np.zeros((n, n))
    for a in range(0, n, chunk):
        b = min(n, a + chunk)
        p = pts[a:b].reshape(-1, 3)
        nn = np.repeat(normals[a:b], q * q, axis=0)
        ff = point_to_polygon_ff(p, nn, corners).reshape(b - a, q * q, n)
        f[a:b] = np.einsum("iqj,q->ij", ff, ww)
    coplanar = np.abs(normals @ normals.T - 1.0) < 1e-9  # same face: nothing seen (a flat face)
    same_plane = coplanar & (np.abs(np.einsum("ic,ic->i", normals, corners[:, 0])[:, None]
                                    - np.einsum("ic,jc->ij", normals, corners[:, 0])) < 1e-9)
    f[same_plane] = 0.0
    return f


# --- the solution -------------------------------------------------------------------------------------

_GEOMETRY = {}


def _geometry(h, q, daylit=False):
    """Patches and form factors of the box at (h, q), computed once per process."""
    if (h, q, daylit) not in _GEOMETRY:
        corners, normals, areas, names = patches(h, daylit)
        _GEOMETRY[(h, q, daylit)] = corners, normals, areas, names, form_factors(corners, normals, q=q)
    return _GEOMETRY[(h, q, daylit)]


def _solve_radiosity(rho, f, e0):
    """Radiosity B (P, K) of (I - diag(rho) F) B = rho E0, every bounce."""
    if len(rho) <= 2000:
        b = np.empty_like(e0)
        eye = np.eye(len(rho))
        for j in range(e0.shape[1]):
            b[:, j] = np.linalg.solve(eye - rho[:, j, None] * f, rho[:, j] * e0[:, j])
        return b
    b = rho * e0  # every bounce, summed until the next adds < 1e-12 of the total (all channels at once)
    bounce = b
    while np.max(bounce / np.where(b > 0, b, 1.0)) > 1e-12:
        bounce = rho * (f @ bounce)
        b = b + bounce
    return b


def transport_daylit(reflectances, radiance, *, h=0.2, q=3, meters=None):
    """The daylit box: irradiance at the meters per channel from the opening, a Lambertian emitter of
    ``radiance`` (K,) W/(m² sr nm) (or per RGB channel). Returns {meter: (direct (K,), reflected (K,))}, with
    direct the light straight from the opening (exact form factors) and reflected everything the room's
    surfaces send; and the patch count."""
    meters = METERS if meters is None else meters
    corners, normals, areas, names, f = _geometry(h, q, daylit=True)
    window = names == "window"
    rho = np.stack([np.zeros_like(np.asarray(radiance, float)) if g == "window" else
                    np.asarray(reflectances[g], float) for g in names])  # (P, K)
    exitance = np.pi * np.asarray(radiance, float)
    e0 = f[:, window].sum(axis=1)[:, None] * exitance[None, :]  # E_i = sum_j F_ij M_j over the opening
    b = _solve_radiosity(rho, f, e0)
    out = {"patches": len(areas)}
    for name, (loc, nrm) in meters.items():
        loc, nrm = np.asarray(loc, float), np.asarray(nrm, float) / np.linalg.norm(nrm)
        g = gather_ff(loc, nrm, corners)
        out[name] = (g[window].sum() * exitance, g[~window] @ b[~window])
    return out


def solve_daylit(spectrum, luminance_cd_m2, *, h=0.2, q=3, meters=None, efficacy=683.0, materials=None):
    """:func:`solve` for the daylit box: a uniform world of luminance ``luminance_cd_m2`` (its scale: L_v = K
    sum L V 5 nm) and relative ``spectrum`` at :data:`WAVELENGTHS_NM`. Same return shape (``direct``: the
    world seen through the opening; ``reflected``: the room's surfaces)."""
    v, _ = action_spectra()
    spectrum = np.asarray(spectrum, float)
    k = luminance_cd_m2 / (efficacy * np.sum(spectrum * v) * STEP_NM)
    materials = MATERIAL_OF if materials is None else materials
    res = transport_daylit({g: reflectance(materials[g]) for g in FACE_GROUPS}, k * spectrum, h=h, q=q,
                           meters=meters)
    return _summary(res, {"patches": res["patches"]}, meters, efficacy)


def _summary(res, out, meters, efficacy):
    """``out`` with, per meter, the direct and reflected spectral irradiance and their ``quantities``."""
    for name in (METERS if meters is None else meters):
        direct, reflected = res[name]
        out[name] = {"direct": direct, "reflected": reflected,
                     "quantities": {part: quantities(e, efficacy) for part, e in
                                    (("direct", direct), ("reflected", reflected), ("total", direct + reflected))}}
    return out


def transport(reflectances, intensity, *, h=0.2, q=3, meters=None, light=LIGHT_M):
    """Irradiance at the meters per channel: ``reflectances`` {face group: (K,)} and the light's intensity
    (K,) W/sr per channel (81 wavelengths, or 3 RGB channels to emulate an RGB renderer). Returns
    {meter: (direct (K,), reflected (K,))} and the patch count and form factors' row sums."""
    meters = METERS if meters is None else meters
    corners, normals, areas, names, f = _geometry(h, q)
    rho = np.stack([np.asarray(reflectances[g], float) for g in names])  # (P, K)
    intensity = np.asarray(intensity, float)
    e0 = (patch_solid_angles(corners, light) / areas)[:, None] * intensity[None, :]  # (P, K)
    b = _solve_radiosity(rho, f, e0)
    out = {"patches": len(areas), "row_sums": f.sum(axis=1)}
    for name, (loc, nrm) in meters.items():
        loc, nrm = np.asarray(loc, float), np.asarray(nrm, float) / np.linalg.norm(nrm)
        d = np.asarray(light, float) - loc
        dist = np.linalg.norm(d)
        out[name] = (intensity * max(float(d @ nrm) / dist, 0.0) / dist**2, gather_ff(loc, nrm, corners) @ b)
    return out


def solve(spectrum, luminous_intensity_cd, *, h=0.2, q=3, meters=None, efficacy=683.0, light=LIGHT_M,
          materials=None):
    """Spectral irradiance at the meters. ``spectrum``: the light's relative spectral power at
    :data:`WAVELENGTHS_NM`; ``luminous_intensity_cd``: its intensity (its scale: I_v = K sum I V 5 nm);
    ``materials``: {face group: ColorChecker name} (default :data:`MATERIAL_OF`).

    Returns a dict per meter: ``direct`` and ``reflected`` spectral irradiance W/(m² nm) at 5 nm, and the
    summary ``quantities(...)`` of each part and of the total; plus ``patches`` (their count) and
    ``row_sums`` (form factors, 1 in a closed box)."""
    v, _ = action_spectra()
    spectrum = np.asarray(spectrum, float)
    k = luminous_intensity_cd / (efficacy * np.sum(spectrum * v) * STEP_NM)
    materials = MATERIAL_OF if materials is None else materials
    res = transport({g: reflectance(materials[g]) for g in FACE_GROUPS}, k * spectrum, h=h, q=q, meters=meters,
                    light=light)
    return _summary(res, {"patches": res["patches"], "row_sums": res["row_sums"]}, meters, efficacy)


def quantities(e, efficacy=683.0):
    """E_v (lx), alpha-opic irradiance (W/m²) and EDI (lx) of a spectral irradiance at 5 nm."""
    v, s = action_spectra()
    d65 = _d65()
    ev = efficacy * np.sum(e * v) * STEP_NM
    irr = {a: float(np.sum(e * sa) * STEP_NM) for a, sa in s.items()}
    edi = {a: float(efficacy * irr[a] * np.sum(d65 * v) / np.sum(d65 * sa)) for a, sa in s.items()}
    return {"illuminance_lx": float(ev), "alpha_opic_irradiance_w_m2": irr, "alpha_opic_edi_lx": edi,
            "mel_edi_lx": edi["melanopic"]}


def light_spectrum(spec):
    """A light's relative spectrum at 5 nm from a product spectrum setting (blackbody: Planck, c2 = 1.4388e-2)."""
    if spec.startswith("blackbody:"):
        t = float(spec.split(":")[1])
        wl = WAVELENGTHS_NM * 1e-9
        return 1.0 / wl**5 / np.expm1(1.4388e-2 / (wl * t))
    raise ValueError(spec)


if __name__ == "__main__":  # the refinement study (bench/spectral_room.md)
    import json
    import sys
    import time

    rows = []
    for h, q in [(0.4, 3), (0.2, 3), (0.1, 2), (0.1, 3)][: int(sys.argv[1]) if len(sys.argv) > 1 else None]:
        t0 = time.perf_counter()
        r = solve(light_spectrum("blackbody:4000"), 100.0, h=h, q=q)
        rows.append({"h": h, "q": q, "patches": r["patches"], "row_sum_min": float(r["row_sums"].min()),
                     "row_sum_max": float(r["row_sums"].max()), "seconds": time.perf_counter() - t0,
                     **{m: {p: {"E_v": r[m]["quantities"][p]["illuminance_lx"],
                                "mel_edi": r[m]["quantities"][p]["mel_edi_lx"]} for p in ("direct", "reflected")}
                        for m in METERS}})
        print(json.dumps(rows[-1]), flush=True)
