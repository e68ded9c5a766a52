"""Environment lighting (pure numpy): equirectangular radiance maps, irradiance E(n), SH9.

A map is an (H, W, 3) array of radiance (W/(m^2 sr)), constant over each pixel, top row first.
Pixel (i, j) covers latitudes [pi/2 - pi (i+1)/H, pi/2 - pi i/H] and longitudes
[2 pi (j/W - 1/2), 2 pi ((j+1)/W - 1/2)] (README "Conventions"); in the map's LOCAL frame the
direction of (lat, lon) is ``(cos lat sin lon, sin lat, -cos lat cos lon)`` and a 3 x 3
``rotation`` takes local directions to world directions:

* ``RADIANCE_MAP_ROTATION``: maps written by ``measure.meter.camera.capture_radiance_map`` (image up =
  world +Z, image centre = world -Y);
* ``BLENDER_WORLD_ROTATION``: Blender's Environment Texture (equirectangular) with no mapping.
  MEASURED by rendering (tests/bpy/test_world.py): the image's centre column faces world +X, the
  column at u = 3/4 faces -Y, u = 1/4 faces +Y, the left/right edges face -X, the top row +Z
  (Cycles' ``direction_to_equirectangular``: u = (pi - atan2(y, x)) / (2 pi)).

Irradiance ("exact"): E(n) = sum over pixels of L_p * integral over the pixel of max(0, n . w) dw.
A pixel wholly above the horizon of n (centre within 90 deg minus the pixel's angular radius)
contributes L_p (n . m_p) with m_p = integral of w over the pixel, in closed form (the integrand is
a trigonometric polynomial in lat, lon); a pixel wholly below contributes 0. For a pixel the
horizon may cross, the clamped integrand is integrated over longitude in closed form (the positive
part of P sin(lon - beta) + Q is an arc), and over latitude by Gauss-Legendre (8 points) on each
piece between the latitudes where the horizon meets the pixel's meridian edges or is tangent to a
parallel, so that the integrand is smooth on every piece; the error estimate returned with each
value is |8-point - 4-point| (measured < 1e-9 relative on the tests' maps). So "exact" means exact
for the piecewise-constant function the pixels define, to that quadrature.

SH9 (Ramamoorthi & Hanrahan 2001): the 9 coefficients L_lm are projected EXACTLY from the
piecewise-constant map (closed-form integrals of the degree-2 polynomials over each pixel), and
E(n) = sum_l A_l sum_m L_lm Y_lm(n) with A_0 = pi, A_1 = 2 pi / 3, A_2 = pi / 4 (their eq. 8-9).
Error bound (derived here from the clamped-cosine kernel K(t) = max(0, t) and its 3-band
truncation K_9(t) = 3/32 + t/2 + 15 t^2 / 32): |E_9(n) - E(n)| <= max |K - K_9| * integral L dw
= (3/32) * integral of L over the sphere, attained at t = 0; for a single directional source this
is 9.4 % of its peak irradiance, the "at most 9 %" of Ramamoorthi & Hanrahan.

References
----------
R. Ramamoorthi, P. Hanrahan, "An Efficient Representation for Irradiance Environment Maps",
SIGGRAPH 2001, pp. 497-500 (eq. 8-13, the constants c1..c5 and the 9 % remark).
"""

import numpy as np

from ..emitters.environment import EnvironmentEmitter


class EnvironmentInputError(ValueError):
    """A radiance map that no finite answer can come from (NaN/inf pixels, wrong shape); one line."""


def check_finite_radiance(radiance, what="radiance map"):
    """``radiance`` as a float array (H, W, >= 3), or EnvironmentInputError when it is empty, has the
    wrong shape or any NaN/inf pixel (their integrals would be NaN/inf: issue 21)."""
    a = np.asarray(radiance, dtype=np.float64)
    if a.ndim != 3 or a.shape[0] < 1 or a.shape[1] < 1 or a.shape[2] < 3:
        raise EnvironmentInputError(f"{what}: expected an (H, W, 3) image, got shape {a.shape}")
    bad = ~np.isfinite(a[..., :3]).all(axis=-1)
    if bad.any():
        y, x = np.argwhere(bad)[0]
        raise EnvironmentInputError(f"{what}: {int(bad.sum())} pixel(s) are NaN or infinite (first at row {y}, "
                                    f"column {x}); no finite irradiance exists")
    return a

#: capture_radiance_map's panorama: local +Y (image up) -> world +Z, local +Z -> world -Y.
RADIANCE_MAP_ROTATION = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])
#: Blender's equirectangular Environment Texture (measured, see the module docstring).
BLENDER_WORLD_ROTATION = np.array([[0.0, 0.0, -1.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])

#: max |K(t) - K_9(t)| over t in [-1, 1] (at t = 0): |E_9 - E| <= SH9_KERNEL_ERROR * integral L dw.
SH9_KERNEL_ERROR = 3.0 / 32.0
#: Ramamoorthi & Hanrahan's A_l for l = 0, 1, 2.
SH9_A = (np.pi, 2.0 * np.pi / 3.0, np.pi / 4.0)
#: Real SH normalisation constants (R&H 2001, eq. 3): Y00, Y1m, Y21/Y2-1/Y2-2, Y20, Y22.
_Y00, _Y1, _Y2 = 0.5 / np.sqrt(np.pi), np.sqrt(3 / (4 * np.pi)), np.sqrt(15 / (4 * np.pi))  # 0.282095 ...
_Y20, _Y22 = np.sqrt(5 / (16 * np.pi)), np.sqrt(15 / (16 * np.pi))                          # 0.315392, 0.546274
#: Order of the 9 coefficients everywhere here.
SH9_NAMES = ("L00", "L1-1", "L10", "L11", "L2-2", "L2-1", "L20", "L21", "L22")



# --- pixels -----------------------------------------------------------------------------------------

def _edges(height, width):
    lat = np.pi / 2 - np.pi * np.arange(height + 1) / height
    lon = 2 * np.pi * (np.arange(width + 1) / width - 0.5)
    return lat, lon


def local_direction(lat, lon):
    """Unit direction(s) (..., 3) in the map's local frame."""
    lat, lon = np.broadcast_arrays(np.asarray(lat, float), np.asarray(lon, float))
    c = np.cos(lat)
    return np.stack([c * np.sin(lon), np.sin(lat), -c * np.cos(lon)], axis=-1)


def direction_to_pixel(directions, shape, rotation=np.eye(3)):
    """(row, column) integer arrays of the pixels holding world ``directions`` (..., 3)."""
    h, w = shape[:2]
    d = np.asarray(directions, float) @ np.asarray(rotation, float)  # world -> local (R orthonormal)
    d = d / np.linalg.norm(d, axis=-1, keepdims=True)
    lat = np.arcsin(np.clip(d[..., 1], -1, 1))
    lon = np.arctan2(d[..., 0], -d[..., 2])
    row = np.clip(((np.pi / 2 - lat) / np.pi * h).astype(int), 0, h - 1)
    col = np.clip(((lon / (2 * np.pi) + 0.5) * w).astype(int), 0, w - 1)
    return row, col


def _cell_terms(lat0, lat1, lon0, lon1):
    """Closed-form integrals over lat-lon cells (lat0 < lat1): solid angle and first moment (local)."""
    c2 = (lat1 - lat0) / 2 + (np.sin(2 * lat1) - np.sin(2 * lat0)) / 4      # int cos^2
    s1 = (np.sin(lat1) ** 2 - np.sin(lat0) ** 2) / 2                          # int sin cos
    dlon = lon1 - lon0
    solid = (np.sin(lat1) - np.sin(lat0)) * dlon
    m = np.stack([c2 * (np.cos(lon0) - np.cos(lon1)), s1 * dlon, -c2 * (np.sin(lon1) - np.sin(lon0))], axis=-1)
    return solid, m


def _cell_radius(lat0, lat1, lon0, lon1):
    """Centre direction (local) and angular radius: the largest angle to a corner bounds the cell
    (distance to a point grows monotonically along parallels and along short meridian arcs)."""
    centre = local_direction((lat0 + lat1) / 2, (lon0 + lon1) / 2)
    r = np.zeros(np.shape(lat0))
    for la in (lat0, lat1):
        for lo in (lon0, lon1):
            q = local_direction(la, lo)
            r = np.maximum(r, np.arctan2(np.linalg.norm(np.cross(centre, q), axis=-1), np.sum(centre * q, axis=-1)))
    return centre, r * (1 + 1e-9) + 1e-12


def pixel_geometry(height, width):
    """Per pixel (local frame): solid angle (H, W), first moment (H, W, 3), centre (H, W, 3), radius (H, W)."""
    lat, lon = _edges(height, width)
    la0, lo0 = np.meshgrid(lat[1:], lon[:-1], indexing="ij")
    la1, lo1 = np.meshgrid(lat[:-1], lon[1:], indexing="ij")
    solid, m = _cell_terms(la0, la1, lo0, lo1)
    centre, r = _cell_radius(la0, la1, lo0, lo1)
    return solid, m, centre, r


def pixel_directions(height, width, rotation=np.eye(3)):
    """World directions of the pixel centres (H, W, 3) and exact solid angles (H, W), sr."""
    solid, _m, centre, _r = pixel_geometry(height, width)
    return centre @ np.asarray(rotation, float).T, solid


def _second_moments(height, width):
    """Integral of w w^T over each pixel (H, W, 3, 3), local frame, closed form."""
    lat, lon = _edges(height, width)
    a, b = lat[1:], lat[:-1]
    p3 = (np.sin(b) - np.sin(b) ** 3 / 3) - (np.sin(a) - np.sin(a) ** 3 / 3)   # int cos^3
    q = (np.sin(b) ** 3 - np.sin(a) ** 3) / 3                                   # int sin^2 cos
    t = -(np.cos(b) ** 3 - np.cos(a) ** 3) / 3                                  # int sin cos^2
    l0, l1 = lon[:-1], lon[1:]
    lss = (l1 - l0) / 2 - (np.sin(2 * l1) - np.sin(2 * l0)) / 4
    lcc = (l1 - l0) / 2 + (np.sin(2 * l1) - np.sin(2 * l0)) / 4
    lsc = (np.sin(l1) ** 2 - np.sin(l0) ** 2) / 2
    ls = -(np.cos(l1) - np.cos(l0))
    lc = np.sin(l1) - np.sin(l0)
    out = np.empty((height, width, 3, 3))
    out[..., 0, 0] = np.outer(p3, lss)
    out[..., 1, 1] = np.outer(q, l1 - l0)
    out[..., 2, 2] = np.outer(p3, lcc)
    out[..., 0, 1] = out[..., 1, 0] = np.outer(t, ls)
    out[..., 0, 2] = out[..., 2, 0] = -np.outer(p3, lsc)
    out[..., 1, 2] = out[..., 2, 1] = -np.outer(t, lc)
    return out


# --- exact irradiance ---------------------------------------------------------------------------------

def _as_map(radiance):
    radiance = np.asarray(radiance, float)
    if radiance.ndim == 2:
        radiance = radiance[..., None]
    if radiance.ndim != 3:
        raise ValueError(f"a radiance map is (H, W, 3), got shape {radiance.shape}")
    return radiance[..., :3]


def _as_normals(normals):
    n = np.asarray(normals, float)
    shape = n.shape[:-1]
    n = n.reshape(-1, 3)
    length = np.linalg.norm(n, axis=1, keepdims=True)
    with np.errstate(invalid="ignore", divide="ignore"):
        n = n / length
    return n, shape


def irradiance(radiance, normals, rotation=np.eye(3), *, chunk=256):
    """E(n) = integral of L max(0, n . w) dw for the piecewise-constant map (module docstring).

    Parameters
    ----------
    radiance : array_like, (H, W, 3) or (H, W)
        Radiance per pixel, W/(m^2 sr).
    normals : array_like, (..., 3)
        World normals (any length > 0; NaN/zero give NaN).
    rotation : array_like, (3, 3)
        Local map frame -> world.

    Returns
    -------
    E : ndarray (..., 3), W/m^2
    error : ndarray (..., 3), error estimate (W/m^2) of the horizon pixels' latitude quadrature.
    """
    lmap = _as_map(radiance)
    h, w, nc = lmap.shape
    n_world, shape = _as_normals(normals)
    rot = np.asarray(rotation, float)
    n_local = n_world @ rot  # R^T n for each row
    solid, m, centre, r = pixel_geometry(h, w)
    flat_l = lmap.reshape(-1, nc)
    flat_m, flat_c, sin_r = m.reshape(-1, 3), centre.reshape(-1, 3), np.sin(np.minimum(r, np.pi / 2)).ravel()
    lat, lon = _edges(h, w)
    ii, jj = np.divmod(np.arange(h * w), w)
    cells = np.stack([lat[ii + 1], lat[ii], lon[jj], lon[jj + 1]], axis=-1)
    scale = np.max(np.abs(flat_l), axis=1)
    e = np.zeros((len(n_local), nc))
    bound = np.zeros((len(n_local), nc))
    good = np.all(np.isfinite(n_local), axis=1)
    for start in range(0, len(n_local), chunk):
        idx = np.arange(start, min(start + chunk, len(n_local)))
        idx = idx[good[idx]]
        if not idx.size:
            continue
        nk = n_local[idx]
        dots = flat_c @ nk.T                       # (P, K)
        above = dots >= sin_r[:, None]
        e[idx] = (np.where(above, flat_m @ nk.T, 0.0)).T @ flat_l
        straddle = np.abs(dots) < sin_r[:, None]
        p_i, k_i = np.nonzero(straddle & (scale[:, None] != 0))
        if p_i.size:
            add, err = _straddling(cells[p_i], nk[k_i], k_i, flat_l[p_i], len(idx))
            e[idx] += add
            bound[idx] += err
    e[~good] = np.nan
    bound[~good] = np.nan
    return e.reshape(shape + (nc,)), bound.reshape(shape + (nc,))


_GL8 = np.polynomial.legendre.leggauss(8)
_GL4 = np.polynomial.legendre.leggauss(4)


def _lon_integral(lat, lon0, lon1, n):
    """g(lat) = cos(lat) * integral over [lon0, lon1] of max(0, n . w(lat, lon)) dlon, closed form.

    n . w = P sin(lon - beta) + Q with P = rho cos(lat), Q = n_y sin(lat) (local frame); the positive
    set is the arc sin(psi) > -Q/P, intersected with the cell's longitudes (3 periods cover it)."""
    nx, ny, nz = n[..., 0], n[..., 1], n[..., 2]
    rho = np.hypot(nx, nz)
    beta = np.arctan2(nz, nx)
    p = rho * np.cos(lat)
    q = ny * np.sin(lat)
    a, b = lon0 - beta, lon1 - beta
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(p > 1e-300, -q / np.where(p > 1e-300, p, 1.0), np.where(q > 0, -np.inf, np.inf))

    def prim(psi):
        return -p * np.cos(psi) + q * psi

    whole = prim(b) - prim(a)
    alpha = np.arcsin(np.clip(s, -1.0, 1.0))
    part = np.zeros_like(whole)
    k0 = np.floor((a - alpha) / (2 * np.pi))
    for dk in (-1.0, 0.0, 1.0):
        k = k0 + dk
        lo = np.maximum(a, alpha + 2 * np.pi * k)
        hi = np.minimum(b, np.pi - alpha + 2 * np.pi * k)
        part += np.where(hi > lo, prim(hi) - prim(lo), 0.0)
    value = np.where(s <= -1.0, whole, np.where(s >= 1.0, 0.0, part))
    return np.cos(lat) * value


def _straddling_integrals(cells, normals):
    """Integral of max(0, n . w) over lat-lon cells (K, 4: lat0, lat1, lon0, lon1) that the horizon of
    n (K, 3, local frame) may cross: longitude in closed form (``_lon_integral``), latitude by
    8-point Gauss-Legendre on each piece between the latitudes where the horizon meets the cell's
    meridian edges or turns (tangent to a parallel), so every piece's integrand is smooth.
    Returns (integral (K,), error estimate (K,) = |8-point - 4-point| summed over pieces)."""
    la0, la1, lo0, lo1 = cells.T
    nx, ny, nz = normals.T
    cuts = [la0, la1]
    for lon in (lo0, lo1):  # n . w(lat, lon) = 0 on a meridian edge: tan(lat) = -A / n_y
        amp = nx * np.sin(lon) - nz * np.cos(lon)
        lat = np.arctan2(-amp, ny)
        lat = np.where(lat > np.pi / 2, lat - np.pi, np.where(lat < -np.pi / 2, lat + np.pi, lat))
        cuts.append(lat)
    tangent = np.arctan2(np.hypot(nx, nz), np.abs(ny))
    cuts += [tangent, -tangent]
    cuts = np.sort(np.clip(np.stack(cuts, axis=1), la0[:, None], la1[:, None]), axis=1)
    total = np.zeros(len(cells))
    err = np.zeros(len(cells))
    for i in range(cuts.shape[1] - 1):
        x0, x1 = cuts[:, i], cuts[:, i + 1]
        half, mid = (x1 - x0) / 2, (x1 + x0) / 2
        est = []
        for nodes, weights in (_GL8, _GL4):
            lat = mid[:, None] + half[:, None] * nodes[None, :]
            g = _lon_integral(lat, lo0[:, None], lo1[:, None], normals[:, None, :])
            est.append(half * (g @ weights))
        total += est[0]
        err += np.abs(est[0] - est[1])
    return total, err


def _straddling(cells, normals, owner, values, count):
    """Sum over (pixel, normal) pairs near the horizon: (E (count, C), error estimate (count, C))."""
    integral, err = _straddling_integrals(cells, normals)
    return (_per_owner(owner, values * integral[:, None], count),
            _per_owner(owner, np.abs(values) * err[:, None], count))


def _per_owner(owner, values, count):
    return np.stack([np.bincount(owner, values[:, c], minlength=count) for c in range(values.shape[1])], axis=1)


def total_radiance(radiance):
    """Integral of L over the sphere (..., 3), W/m^2 (the SH9 bound's scale)."""
    lmap = _as_map(radiance)
    solid, *_ = pixel_geometry(*lmap.shape[:2])
    return np.einsum("hw,hwc->c", solid, lmap)


# --- SH9 ------------------------------------------------------------------------------------------------

def _sh_basis(x, y, z):
    return np.stack([np.full_like(x, _Y00), _Y1 * y, _Y1 * z, _Y1 * x, _Y2 * x * y, _Y2 * y * z,
                     _Y20 * (3 * z * z - 1), _Y2 * x * z, _Y22 * (x * x - y * y)], axis=-1)


def sh9_coefficients(radiance, rotation=np.eye(3)):
    """The 9 SH coefficients L_lm (9, 3) of the piecewise-constant map, world frame (order SH9_NAMES).

    Each pixel's integral of Y_lm is exact: the basis is a polynomial of degree <= 2 in the world
    direction, whose zeroth, first and second moments over a lat-lon cell have closed forms.
    """
    lmap = _as_map(radiance)
    h, w, _ = lmap.shape
    rot = np.asarray(rotation, float)
    solid, m, *_ = pixel_geometry(h, w)
    m1 = m @ rot.T                                              # world first moments
    m2 = np.einsum("ia,hwab,jb->hwij", rot, _second_moments(h, w), rot)
    x, y, z = m1[..., 0], m1[..., 1], m1[..., 2]
    basis = np.stack([_Y00 * solid, _Y1 * y, _Y1 * z, _Y1 * x, _Y2 * m2[..., 0, 1], _Y2 * m2[..., 1, 2],
                      _Y20 * (3 * m2[..., 2, 2] - solid), _Y2 * m2[..., 0, 2],
                      _Y22 * (m2[..., 0, 0] - m2[..., 1, 1])], axis=-1)
    return np.einsum("hwk,hwc->kc", basis, lmap)


def sh9_irradiance(coefficients, normals):
    """E(n) (..., 3) from the 9 coefficients: sum_l A_l sum_m L_lm Y_lm(n) (R&H 2001 eq. 12/13)."""
    n, shape = _as_normals(normals)
    a = np.array([SH9_A[0]] + [SH9_A[1]] * 3 + [SH9_A[2]] * 5)
    y = _sh_basis(n[:, 0], n[:, 1], n[:, 2])
    coefficients = np.asarray(coefficients, float)
    return (y * a) @ coefficients.reshape(9, -1)


def sh9_error_bound(radiance):
    """Absolute bound (3,) on |E_9(n) - E(n)| for every n: (3/32) * integral of L over the sphere."""
    return SH9_KERNEL_ERROR * np.abs(total_radiance(radiance))


# --- irradiance environment maps ----------------------------------------------------------------------

def irradiance_map(radiance, rotation=np.eye(3), *, resolution=(64, 32), method="exact", out_rotation=None):
    """The lecture's irradiance environment map: E(n) for the centre direction n of every output pixel.

    ``resolution`` = (width, height); the output uses the same equirect convention with
    ``out_rotation`` (default: the input's), so it can be used where the input map is used.
    Returns a dict: ``map`` (h, w, 3) W/m^2, ``bound`` (absolute, (h, w, 3) or (3,) for SH9),
    ``coefficients`` (9, 3), ``sh9_error`` (max |E_9 - E_exact| over the output pixels, when both
    are computed) and ``sh9_bound``.
    """
    width, height = int(resolution[0]), int(resolution[1])
    if width < 1 or height < 1:
        raise ValueError(f"resolution must be positive, got {resolution}")
    radiance = check_finite_radiance(radiance)
    out_rotation = rotation if out_rotation is None else out_rotation
    dirs, _ = pixel_directions(height, width, out_rotation)
    coeffs = sh9_coefficients(radiance, rotation)
    sh = sh9_irradiance(coeffs, dirs.reshape(-1, 3)).reshape(height, width, -1)
    sh_bound = sh9_error_bound(radiance)
    out = {"coefficients": coeffs, "sh9_bound": sh_bound, "method": method}
    if method == "sh9":
        out.update(map=sh, bound=sh_bound)
        return out
    if method != "exact":
        raise ValueError(f"method must be 'exact' or 'sh9', got {method!r}")
    exact, bound = irradiance(radiance, dirs.reshape(-1, 3), rotation)
    exact, bound = exact.reshape(height, width, -1), bound.reshape(height, width, -1)
    out.update(map=exact, bound=bound, sh9_error=np.max(np.abs(sh - exact), axis=(0, 1)))
    return out


# --- images as Cycles samples them --------------------------------------------------------------------

def bilinear_supersample(radiance, factor=2):
    """The bilinear interpolant of the map (texel centres at pixel centres, periodic in longitude,
    clamped at the poles) sampled at the centres of ``factor`` x ``factor`` sub-pixels.

    Integrating the result as piecewise constant is the midpoint rule for the interpolated
    function on each sub-pixel; with an even ``factor`` no sub-pixel crosses a texel-centre line,
    so the interpolant is bilinear inside each and the rule's error is second order in the
    sub-pixel size (measured in tests/test_environment.py: factor 2 vs 8).
    """
    lmap = _as_map(radiance)
    h, w, _ = lmap.shape
    f = int(factor)
    rows = (np.arange(h * f) + 0.5) / f - 0.5
    cols = (np.arange(w * f) + 0.5) / f - 0.5
    r0 = np.floor(rows).astype(int)
    c0 = np.floor(cols).astype(int)
    tr, tc = rows - r0, cols - c0
    ra, rb = np.clip(r0, 0, h - 1), np.clip(r0 + 1, 0, h - 1)
    ca, cb = c0 % w, (c0 + 1) % w
    top = lmap[ra][:, ca] * (1 - tc)[None, :, None] + lmap[ra][:, cb] * tc[None, :, None]
    bottom = lmap[rb][:, ca] * (1 - tc)[None, :, None] + lmap[rb][:, cb] * tc[None, :, None]
    return top * (1 - tr)[:, None, None] + bottom * tr[:, None, None]


def brightest(radiance, rotation=np.eye(3), weights=(0.2126, 0.7152, 0.0722)):
    """(world direction (3,), RGB radiance (3,), (row, col)) of the pixel with the largest weighted radiance."""
    lmap = _as_map(radiance)
    y = lmap @ np.asarray(weights, float)[: lmap.shape[2]]
    row, col = np.unravel_index(int(np.nanargmax(y)), y.shape)
    dirs, _ = pixel_directions(*lmap.shape[:2], rotation)
    return dirs[row, col], lmap[row, col], (int(row), int(col))


# --- the mirror-sphere light probe -------------------------------------------------------------------

def probe_to_directions(size):
    """For a (size x size) mirror-ball image seen by an orthographic camera looking along -Z (image up
    = +Y, right = +X): per pixel the reflected direction (size, size, 3) in the camera frame and a
    mask of pixels on the ball. A ball point with normal N = (x, y, sqrt(1 - x^2 - y^2)) reflects
    the view ray d = (0, 0, -1) into r = d - 2 (d . N) N."""
    t = (np.arange(size) + 0.5) / size * 2 - 1
    x, y = np.meshgrid(t, -t)
    rr = x * x + y * y
    inside = rr < 1.0
    z = np.sqrt(np.clip(1 - rr, 0, None))
    normal = np.stack([x, y, z], axis=-1)
    d = np.array([0.0, 0.0, -1.0])
    refl = d - 2 * (normal @ d)[..., None] * normal
    return refl, inside


def probe_to_equirect(probe, shape, rotation=np.eye(3), camera_rotation=np.eye(3)):
    """Resample a mirror-ball image (S, S, 3) into an equirect map of ``shape`` (h, w): each map pixel
    centre looks up the ball pixel whose reflected direction it is (nearest pixel)."""
    probe = _as_map(probe)
    size = probe.shape[0]
    h, w = shape
    dirs, _ = pixel_directions(h, w, rotation)
    cam = dirs @ np.asarray(camera_rotation, float)   # world -> camera frame
    # Invert r = d - 2 (d.N) N for d = (0, 0, -1): N is along (r - d) normalised.
    nrm = cam - np.array([0.0, 0.0, -1.0])
    length = np.linalg.norm(nrm, axis=-1, keepdims=True)
    nrm = np.where(length > 1e-12, nrm / np.maximum(length, 1e-12), np.array([0.0, 1.0, 0.0]))
    col = np.clip(((nrm[..., 0] + 1) / 2 * size).astype(int), 0, size - 1)
    row = np.clip(((1 - nrm[..., 1]) / 2 * size).astype(int), 0, size - 1)
    return probe[row, col]


def equirect_to_probe(radiance, size, rotation=np.eye(3), camera_rotation=np.eye(3)):
    """Render the ideal mirror ball (S, S, 3) from an equirect map (nearest pixel); 0 off the ball."""
    lmap = _as_map(radiance)
    refl, inside = probe_to_directions(size)
    world = refl @ np.asarray(camera_rotation, float).T
    row, col = direction_to_pixel(world, lmap.shape, rotation)
    return np.where(inside[..., None], lmap[row, col], 0.0)


# --- the world as pure data -------------------------------------------------------------------------

class WorldLight(EnvironmentEmitter):
    """The scene's world as Cycles renders it, when a closed form covers it (``measure.authoring.world`` fills it).
    An emitter (:class:`.emitters.environment.EnvironmentEmitter`: ``irradiance_at``, flags INFINITE).

    ``kind``: "constant" (radiance (3,) in every direction), "equirect" (``radiance`` (H, W, 3) map
    with ``rotation`` local -> world, already multiplied by the Background colour x strength), "black"
    (no light reaches diffuse surfaces), or None with ``reason`` when it is not modelled (rendered).
    ``exact``: the value is exact to the image's pixels (constant, or 'Closest' interpolation); for
    'Linear' interpolation the integral of Cycles' bilinear interpolant is computed by
    ``bilinear_supersample`` (second-order quadrature, ``exact`` False, its error stated).
    ``strength``/``node``: the Background strength and node name (calibration scales it).
    """

    def __init__(self, kind=None, radiance=None, rotation=np.eye(3), *, exact=True, reason="", notes=(),
                 strength=1.0, node="", interpolation="", image="", supersample=1):
        self.kind = kind
        self.radiance = None if radiance is None else np.asarray(radiance, float)
        self.rotation = np.asarray(rotation, float)
        self.exact = bool(exact)
        self.reason = reason
        self.notes = list(notes)
        self.strength = float(strength)
        self.node = node
        self.interpolation = interpolation
        self.image = image
        self.supersample = int(supersample)
        self._sampled = None

    @property
    def modelled(self):
        return self.kind is not None

    def sampled_map(self):
        """The piecewise-constant map that is integrated (bilinear supersampled for 'Linear')."""
        if self._sampled is None and self.kind == "equirect":
            self._sampled = (bilinear_supersample(self.radiance, self.supersample) if self.supersample > 1
                             else self.radiance)
        return self._sampled

    def irradiance(self, normals):
        """(E (..., 3) W per scene-unit^2, error (..., 3)) from the world alone, nothing blocking it."""
        n, shape = _as_normals(normals)
        if self.kind == "constant":
            e = np.broadcast_to(np.pi * self.radiance[:3], (len(n), 3)).copy()
            e[~np.all(np.isfinite(n), axis=1)] = np.nan
            return e.reshape(shape + (3,)), np.zeros(shape + (3,))
        if self.kind == "black":
            return np.zeros(shape + (3,)), np.zeros(shape + (3,))
        if self.kind == "equirect":
            e, err = irradiance(self.sampled_map(), n, self.rotation)
            if self.supersample > 1:
                # The midpoint rule on f x f sub-pixels converges as f^-2 to the integral of the
                # bilinear interpolant (measured: E2 - E4 = 4.0 (E4 - E8) for a one-pixel hot spot),
                # so Richardson gives the error of E_f as |E_f - E_f/2| / 3; for f = 2 the pixel
                # sum is not on that curve and |E_2 - E_1| is used (about 3 x the actual error).
                half = self.supersample // 2
                coarse = bilinear_supersample(self.radiance, half) if half > 1 else self.radiance
                e1, err1 = irradiance(coarse, n, self.rotation)
                err = err + err1 + np.abs(e - e1) / (3.0 if half > 1 else 1.0)
            return e.reshape(shape + (3,)), err.reshape(shape + (3,))
        raise ValueError(f"the world is not modelled: {self.reason}")

    def as_map(self, height=16, width=32):
        """An equirect map (h, w, 3) and its rotation standing for the world (constant worlds: uniform)."""
        if self.kind == "equirect":
            return self.radiance, self.rotation
        value = self.radiance[:3] if self.kind == "constant" else np.zeros(3)
        return np.broadcast_to(value, (height, width, 3)).copy(), BLENDER_WORLD_ROTATION

    def brightest(self, weights=(0.2126, 0.7152, 0.0722)):
        """(world direction, RGB radiance) of the brightest pixel (constant worlds: +Z)."""
        if self.kind == "equirect":
            d, value, _ = brightest(self.radiance, self.rotation, weights)
            return d, value
        value = self.radiance[:3] if self.kind == "constant" else np.zeros(3)
        return np.array([0.0, 0.0, 1.0]), value

    def scaled(self, factor):
        """The same world with its Background strength times ``factor``."""
        out = WorldLight(self.kind, None if self.radiance is None else self.radiance * factor, self.rotation,
                         exact=self.exact, reason=self.reason, notes=self.notes, strength=self.strength * factor,
                         node=self.node, interpolation=self.interpolation, image=self.image,
                         supersample=self.supersample)
        return out
