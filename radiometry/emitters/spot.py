"""Spot light (Cycles ``kernel/light/spot.h``): a point light times its cone.

The cone factor is ``smoothstep((z - cos(size/2)) / ((1 - cos(size/2)) * blend))`` where z is the
cosine to -Z of the direction *in the object's scaled local frame* (``itfm``: non-uniform scale
stretches the cone, shear and mirror included); blend 0 is a hard edge. Radius 0: E = P cos att /
(4 pi r^2); radius R: the cone factor is applied per incoming direction over the sphere/disk
(piecewise Gauss-Legendre that follows the cone edge, the blend edge and the horizon, with a bound).

Power: P/(4 pi) x the integral of the cone factor over the sphere, by a change of variables to the
cone's own frame (u = unit(M^-1 d), d omega_d = |det M| / |M u|^3 d omega_u): Gauss-Legendre in z on
the hard edge, the blend ramp and the full part, and in azimuth (smooth and periodic).
"""

from dataclasses import dataclass

import numpy as np

from ..scene.geometry import unit
from .point import PointLight

__all__ = ["SpotLight", "spot_attenuation", "QUADRATURE_SPOT_PHI", "QUADRATURE_SPOT_T"]

#: Spot with radius: azimuth nodes, and nodes per smooth polar piece (between cone edge,
#: blend edge and horizon crossings).
QUADRATURE_SPOT_PHI = 256
QUADRATURE_SPOT_T = 8


def _smoothstep(x):
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)


def spot_attenuation(spec, directions):
    """Cycles' spot cone factor for world directions leaving the light, (..., 3) -> (...).

    z = cosine to the local -Z axis of the direction mapped by the inverse object matrix
    (``itfm``: scale, shear and mirror included), factor = smoothstep((z - cos(spot_size/2)) / ((1 - cos(spot_size/2)) * blend)).
    """
    d = np.asarray(directions, dtype=np.float64)
    local = unit(d @ np.linalg.inv(spec.matrix).T)       # Cycles: itfm, any affine map
    z = -local[..., 2]
    cos_half = np.cos(0.5 * spec.spot_size)
    width = (1.0 - cos_half) * spec.spot_blend
    if width <= 0.0:
        return (z > cos_half).astype(np.float64)
    return _smoothstep((z - cos_half) / width)


def _cap_frame(w):
    helper = np.where(np.abs(w[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    e1 = unit(np.cross(w, helper))
    return e1, np.cross(w, e1)


def _cap_dirs(w, e1, e2, t, cphi, sphi):
    """Directions at t = 1 - cos(gamma) and azimuth (cos, sin) about w; t (M, A, ...)."""
    sin_g = np.sqrt(np.maximum(t * (2.0 - t), 0.0))[..., None]
    shape = (w.shape[0],) + (1,) * (t.ndim - 1) + (3,)
    ca = cphi.reshape((1, -1) + (1,) * (t.ndim - 2) + (1,))
    sa = sphi.reshape((1, -1) + (1,) * (t.ndim - 2) + (1,))
    return ((1.0 - t)[..., None] * w.reshape(shape)
            + sin_g * (ca * e1.reshape(shape) + sa * e2.reshape(shape)))


def _spot_cap_quadrature(spec, w, s2, normals, order_phi, order_t, grid=24):
    """int over the cap {angle to w < sigma} of spot_att(-omega) max(n.omega, 0) d omega, (M,).

    Piecewise Gauss-Legendre that follows the discontinuities: per azimuth, the polar variable
    t = 1 - cos(gamma) in [0, 1 - cos sigma] is cut where the direction crosses the cone edge
    (z = cos(size/2)), the blend's inner edge (z = cos(size/2) + width) and the receiver's
    horizon (n . omega = 0); each smooth piece gets ``order_t`` nodes. The crossings are found
    numerically (a ``grid``-point scan, then bisection), so an elliptical (non-uniformly scaled or
    sheared) cone needs no closed form. Azimuth: ``order_phi`` Gauss-Legendre nodes on [0, 2 pi].
    """
    inv_t = np.linalg.inv(spec.matrix).T
    cos_half = np.cos(0.5 * spec.spot_size)
    width = (1.0 - cos_half) * spec.spot_blend
    levels = [cos_half] + ([cos_half + width] if 0.0 < width and cos_half + width < 1.0 else [])
    e1, e2 = _cap_frame(w)
    tmax = s2 / (1.0 + np.sqrt(np.maximum(1.0 - s2, 0.0)))                     # 1 - cos sigma
    pg, pw = np.polynomial.legendre.leggauss(order_phi)
    phi = np.pi * (pg + 1.0)
    cphi, sphi = np.cos(phi), np.sin(phi)
    tg, tw = np.polynomial.legendre.leggauss(order_t)

    def funcs(t):  # (M, A, ...) -> (M, A, ..., F): zero at each discontinuity
        d = _cap_dirs(w, e1, e2, t, cphi, sphi)
        z = -unit(-d @ inv_t)[..., 2]
        nn = normals.reshape((normals.shape[0],) + (1,) * (t.ndim - 1) + (3,))
        return np.stack([z - c for c in levels] + [np.sum(d * nn, axis=-1)], axis=-1)

    m, a = w.shape[0], order_phi
    tt = tmax[:, None, None] * np.linspace(0.0, 1.0, grid)[None, None, :] * np.ones((1, a, 1))
    f = funcs(tt)                                                           # (M, A, G, F)
    change = np.signbit(f[:, :, :-1]) != np.signbit(f[:, :, 1:])            # (M, A, G-1, F)
    idx = np.arange(grid - 1)[None, None, :, None]
    first = np.where(change, idx, grid).min(axis=2)                         # (M, A, F)
    last = np.where(change, idx, -1).max(axis=2)
    cuts = []
    for k_idx, valid in ((first, first < grid), (last, last >= 0)):
        k = np.clip(k_idx, 0, grid - 2)
        lo = np.take_along_axis(tt, k, axis=2)                              # (M, A, F)
        hi = np.take_along_axis(tt, k + 1, axis=2)
        f_lo = np.take_along_axis(f, k[:, :, :, None], axis=2)              # (M, A, F, F)
        f_lo = np.diagonal(f_lo, axis1=2, axis2=3)                          # (M, A, F)
        for _ in range(48):
            mid = 0.5 * (lo + hi)
            fm = np.diagonal(funcs(mid), axis1=2, axis2=3)
            same = np.signbit(fm) == np.signbit(f_lo)
            lo, hi = np.where(same, mid, lo), np.where(same, hi, mid)
            f_lo = np.where(same, fm, f_lo)
        cuts.append(np.where(valid, 0.5 * (lo + hi), tmax[:, None, None]))
    bounds = np.sort(np.concatenate([np.zeros((m, a, 1)), *cuts, tmax[:, None, None] * np.ones((1, a, 1))],
                                    axis=2), axis=2)                         # (M, A, P+1)
    lo, span = bounds[:, :, :-1], np.diff(bounds, axis=2)                    # (M, A, P)
    t = lo[..., None] + 0.5 * (tg + 1.0) * span[..., None]                   # (M, A, P, K)
    d = _cap_dirs(w, e1, e2, t, cphi, sphi)
    att = spot_attenuation(spec, -d)
    cosr = np.maximum(np.einsum("mapkx,mx->mapk", d, normals), 0.0)
    return np.einsum("mapk,mapk,k,a->m", att * cosr, 0.5 * span[..., None] * np.ones_like(t), tw, np.pi * pw)


def _spot_cap_with_bound(spec, w, s2, normals, chunk=64):
    """(value, relative bound): 256 azimuths against 128 (8 nodes per smooth piece in both)."""
    out = np.empty(w.shape[0])
    rel = np.empty(w.shape[0])
    for start in range(0, w.shape[0], chunk):
        sl = slice(start, start + chunk)
        fine = _spot_cap_quadrature(spec, w[sl], s2[sl], normals[sl], QUADRATURE_SPOT_PHI, QUADRATURE_SPOT_T)
        coarse = _spot_cap_quadrature(spec, w[sl], s2[sl], normals[sl], QUADRATURE_SPOT_PHI // 2,
                                      QUADRATURE_SPOT_T)
        out[sl] = fine
        rel[sl] = np.abs(fine - coarse) / np.where(fine != 0.0, np.abs(fine), 1.0) * (fine != 0.0)
    return out, rel



def cone_solid_angle(spec, order_z=32, order_phi=128):
    """Integral of the cone factor over the sphere of world directions, sr (see the module docstring).

    Exact for a circular cone up to float64 (the smoothstep is a cubic in z: Gauss-Legendre of order
    >= 2 per piece integrates it exactly; the azimuth weight is constant); an elliptical cone adds
    the azimuthal quadrature error of a smooth periodic function (spectral)."""
    matrix = np.asarray(spec.matrix, float)
    cos_half = np.cos(0.5 * spec.spot_size)
    width = (1.0 - cos_half) * spec.spot_blend
    cuts = [cos_half] + ([min(cos_half + width, 1.0)] if width > 0.0 else []) + [1.0]
    g, gw = np.polynomial.legendre.leggauss(order_z)
    phi = 2.0 * np.pi * np.arange(order_phi) / order_phi
    det = abs(np.linalg.det(matrix))
    total = 0.0
    for lo, hi in zip(cuts[:-1], cuts[1:]):
        if hi <= lo:
            continue
        z = 0.5 * (lo + hi) + 0.5 * (hi - lo) * g                                 # cosine to local -Z
        s = np.sqrt(np.maximum(1.0 - z * z, 0.0))
        u = np.stack([s[:, None] * np.cos(phi)[None, :], s[:, None] * np.sin(phi)[None, :],
                      -z[:, None] * np.ones_like(phi)[None, :]], axis=-1)           # local unit directions
        weight = det / np.linalg.norm(u @ matrix.T, axis=-1) ** 3                   # d omega_world / d omega_u
        att = _smoothstep((z - cos_half) / width) if width > 0.0 else np.ones_like(z)
        total += float(np.einsum("z,zp,z->", att, weight, 0.5 * (hi - lo) * gw)) * (2.0 * np.pi / order_phi)
    return total


@dataclass(frozen=True)
class SpotLight(PointLight, kind_key=("SPOT", False)):
    """A spot light (see the module docstring)."""

    def power_w(self):
        return np.array(self.rgb_power, dtype=np.float64) * (cone_solid_angle(self) / (4.0 * np.pi))

    def _cone(self, directions):
        return spot_attenuation(self, directions)

    def _cap(self, w, sin_sq, n):
        return _spot_cap_with_bound(self, w, sin_sq, n)

    def exactness(self):
        if self.radius == 0.0:
            return True, "spot", "inverse square law, exact" + self._sign_note()
        model = "disk facing receiver" if self.soft_falloff else "Lambertian sphere"
        return False, "quadrature", (f"{model} with per-direction spot attenuation, piecewise Gauss-Legendre "
                                     f"{QUADRATURE_SPOT_PHI} azimuths x {QUADRATURE_SPOT_T} per smooth piece (cut at the "
                                     "cone edge, blend edge and horizon); per-point bound from irradiance_with_bound"
                                     + self._sign_note())
