"""Area light (Cycles ``kernel/light/area.h``): rectangle, square, disk, ellipse, with spread.

A Lambertian emitter of radiance L = P/(pi A) on its -Z side (A = Cycles' area, object scale
included); ``spread`` < 180 deg multiplies the radiance by max((tan(s/2) - tan a) / (tan(s/2) - s/2), 0)
(soft-box slats, Blender differential D10594), which preserves the flux. Irradiance: Lambert's polygon
formula with horizon clipping (rectangles exact; disks and ellipses as an equal-area 2048-gon, bound
from the 1024-gon), spread 0 collimated, other spreads by Gauss-Legendre in polar coordinates about the
receiver's foot point (bound from a coarser rule); sheared transforms: Cycles' own light-sampling
estimate (see :func:`_sheared_area_nee`) plus :data:`SHEARED_MIS_BOUND`.

Power: P per channel (the spread is flux preserving), times |edge_u x edge_v| / (|edge_u| |edge_v|)
for a sheared light (Cycles takes A from the edge lengths, the surface is the parallelogram).

References
----------
See :mod:`..geometry` for the projected-solid-angle formulas (Lambert 1760, Arvo 1995, Baum 1989).
"""

import math
from dataclasses import dataclass

import numpy as np

from ..metrics import glare as glare_math
from ..scene.geometry import norm, polygon_projected_solid_angle, unit
from .base import EmitterFlags
from .cycles_light import CyclesLight

__all__ = ["AreaLight", "DISK_POLYGON_SIDES", "SHEARED_MIS_BOUND", "QUADRATURE_RADIAL", "QUADRATURE_ANGULAR"]

#: Sides of the equal-area polygon standing in for a disk/ellipse: relative irradiance error
#: below 1e-8 unless the receiver is within ~1 % of the radius of the rim (measured against a
#: 262144-gon: 2e-5 at 0.1 mm from a 0.5 m rim, 1 mm below it); irradiance_with_bound's per-point
#: bound (2048- vs 1024-gon) covers it conservatively (3e-4 there).
DISK_POLYGON_SIDES = 2048

#: Gauss-Legendre orders of the quadratures (spread < 180 deg; sheared area lights).
QUADRATURE_RADIAL = 48
QUADRATURE_ANGULAR = 96


def _outline_world(spec, sides):
    """World vertices of the emitter: position + a edge_u + b edge_v (a, b in [-1/2, 1/2])."""
    eu, ev = spec.edges
    if spec.shape in ("DISK", "ELLIPSE"):
        k = np.sqrt((2 * np.pi / sides) / np.sin(2 * np.pi / sides))  # equal-area polygon
        phi = np.arange(sides) * (2 * np.pi / sides)
        ab = 0.5 * k * np.stack([np.cos(phi), np.sin(phi)], axis=1)
    else:
        ab = np.array([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])
    return spec.position + ab[:, :1] * eu + ab[:, 1:] * ev


def _spread_normalisation(half_spread):
    # Cycles scene/light.cpp: 1 / (tan h - h), third-order Taylor 3 / h^3 below h = 0.05 rad.
    if half_spread > 0.05:
        return 1.0 / (np.tan(half_spread) - half_spread)
    return 3.0 / half_spread**3




def _area_factor(spec, p, n):
    area = spec.area_m2
    out = np.zeros(p.shape[0])
    bound = np.zeros(p.shape[0])
    if area <= 0.0:
        return out, bound
    normal = spec.emission_direction
    in_front = (p - spec.position) @ normal > 0.0
    radiance = 1.0 / (np.pi * area)
    if not np.any(in_front):
        return out, bound
    pf, nf = p[in_front], n[in_front]
    if spec.is_sheared:
        if spec.spread < np.pi:
            out[in_front] = radiance * _spread_quadrature(spec, pf, nf)
            bound[in_front] = np.nan  # not modelled: see exactness()
        else:
            out[in_front], bound[in_front] = _sheared_area_factor(spec, pf, nf)
    elif spec.spread >= np.pi:
        if spec.shape in ("DISK", "ELLIPSE"):
            # Equal-area 2048-gon; bound: its difference from the 1024-gon, which is larger than
            # the 2048-gon's own error (see DISK_POLYGON_SIDES).
            fine = polygon_projected_solid_angle(_outline_world(spec, DISK_POLYGON_SIDES), pf, nf)
            coarse = polygon_projected_solid_angle(_outline_world(spec, DISK_POLYGON_SIDES // 2), pf, nf)
            out[in_front] = radiance * fine
            bound[in_front] = np.abs(fine - coarse) / np.where(fine > 0.0, fine, 1.0) * (fine > 0.0)
        else:
            out[in_front] = radiance * polygon_projected_solid_angle(_outline_world(spec, 4), pf, nf)
    elif spec.spread == 0.0:
        out[in_front] = _collimated_area_factor(spec, pf, nf)
    else:
        fine = _spread_quadrature(spec, pf, nf)
        coarse = _spread_quadrature(spec, pf, nf, QUADRATURE_RADIAL // 2, QUADRATURE_ANGULAR // 2)
        out[in_front] = radiance * fine
        bound[in_front] = np.abs(fine - coarse) / np.where(fine > 0.0, fine, 1.0) * (fine > 0.0)
    return out, bound


def _sheared_area_nee(spec, p, n, order):
    """Cycles' light-sampling estimate for a sheared area light, per unit rgb_power, (N,).

    Rectangle (``area_light_rect_sample``): Urena's spherical-rectangle sampler is run in the
    frame x = unit(edge_u), y = unit(edge_v), z = x cross y as if it were orthonormal; the sample
    (xu, yv) of the rectangle [xc +- len_u/2] x [yc +- len_v/2] at height z0 (xc = (c - P).x,
    ...) is placed at P + xu x + yv y + z0 z, and the estimate is L cos_r S with S that
    rectangle's solid angle. Its mean is L int_R0 max(n . unit(A w), 0) d omega(w), A = [x y z].
    Ellipse (``ellipse_sample``): uniform points on the true (sheared) ellipse with pdf
    1/(pi/4 len_u len_v) and area-to-solid-angle factor from Cycles' ``dir`` (not the plane's
    normal): mean = L (A_cycles/A_true) int max(cos_r, 0) |cos(dir, -D)| / t^2 dA.
    L = 1/(pi A_cycles), A_cycles = |edge_u| |edge_v| (pi/4).
    """
    eu, ev = spec.edges
    lu, lv = norm(eu), norm(ev)
    x, y = eu / lu, ev / lv
    g, wts = np.polynomial.legendre.leggauss(order)
    radiance = 1.0 / (np.pi * spec.area_m2)
    if spec.shape in ("DISK", "ELLIPSE"):
        # Polar coordinates on the unit disk: r in [0, 1], phi in [0, 2 pi].
        r = 0.5 * (g + 1.0)
        wr = 0.5 * wts * r
        pg, pw = np.polynomial.legendre.leggauss(2 * order)
        phi = np.pi * (pg + 1.0)
        wphi = np.pi * pw
        ab = 0.5 * r[:, None, None] * np.stack([np.cos(phi), np.sin(phi)], -1)[None]      # (R, A, 2)
        q = spec.position + ab[..., :1] * eu + ab[..., 1:] * ev                             # (R, A, 3)
        true_area = norm(np.cross(eu, ev)) * np.pi / 4
        dvec = q[None] - p[:, None, None, :]                                                # (N, R, A, 3)
        t2 = np.sum(dvec * dvec, axis=-1)
        dn = dvec / np.sqrt(t2)[..., None]
        f = (np.maximum(np.einsum("nrak,nk->nra", dn, n), 0.0)
             * np.abs(dn @ spec.emission_direction) / t2)
        # dA = |eu x ev| / 4 r dr dphi: the Jacobian of (r, phi) -> a eu + b ev.
        integral = np.einsum("nra,r,a->n", f, wr, wphi) * norm(np.cross(eu, ev)) / 4.0
        return radiance * (spec.area_m2 / true_area) * integral
    z = np.cross(x, y)
    rel = spec.position - p
    z0 = rel @ z
    zs = np.where(z0 > 0.0, -1.0, 1.0)
    z0 = z0 * zs
    xc, yc = rel @ x, rel @ y
    xs = xc[:, None] + 0.5 * lu * g[None, :]                                                 # (N, K)
    ys = yc[:, None] + 0.5 * lv * g[None, :]
    wv = np.stack([np.broadcast_to(xs[:, :, None], xs.shape + (order,)),
                   np.broadcast_to(ys[:, None, :], xs.shape + (order,)),
                   np.broadcast_to(z0[:, None, None], xs.shape + (order,))], -1)             # (N, K, K, 3)
    r2 = np.sum(wv * wv, axis=-1)
    domega = np.abs(z0)[:, None, None] / r2**1.5 * (0.25 * lu * lv) * wts[None, :, None] * wts[None, None, :]
    world = (wv[..., :1] * x + wv[..., 1:2] * y + wv[..., 2:] * (zs[:, None, None, None] * z))
    cos_r = np.maximum(np.einsum("nabk,nk->nab", unit(world), n), 0.0)
    return radiance * np.sum(cos_r * domega, axis=(1, 2))


#: Sheared area lights: Cycles' MIS mixes its light-sampling estimate (modelled exactly) with BSDF
#: hits on a differently shaped region; measured gap MIS - light sampling: +0.04 % to +0.21 %
#: (tests/bpy/test_cycles_lights_render.py, rectangles and disks, mirrored too). Empirical bound.
SHEARED_MIS_BOUND = 5e-3


def _sheared_area_factor(spec, p, n, chunk=128):
    """(value, relative bound) for a sheared area light: Cycles' light-sampling estimate; the
    bound is its quadrature error (48 vs 24 nodes) plus :data:`SHEARED_MIS_BOUND`."""
    out = np.empty(p.shape[0])
    bound = np.empty(p.shape[0])
    for start in range(0, p.shape[0], chunk):
        sl = slice(start, start + chunk)
        fine = _sheared_area_nee(spec, p[sl], n[sl], 48)
        coarse = _sheared_area_nee(spec, p[sl], n[sl], 24)
        denom = np.where(fine > 0.0, fine, 1.0)
        out[sl] = fine
        bound[sl] = (np.abs(fine - coarse) / denom + SHEARED_MIS_BOUND) * (fine > 0.0)
    return out, bound


def _inside_shape(spec, uv):
    u, v = spec.extents
    if spec.shape in ("DISK", "ELLIPSE"):
        return (2 * uv[:, 0] / u) ** 2 + (2 * uv[:, 1] / v) ** 2 <= 1.0
    return (np.abs(uv[:, 0]) <= u / 2) & (np.abs(uv[:, 1]) <= v / 2)


def _collimated_area_factor(spec, p, n):
    # Spread 0: Cycles emits only along the normal (attenuation pi for tan a < 1e-5), flux P.
    rel = p - spec.position
    uv = np.stack([rel @ spec.axes[:, 0], rel @ spec.axes[:, 1]], axis=1)
    cos_r = np.maximum(n @ (-spec.emission_direction), 0.0)
    return np.where(_inside_shape(spec, uv), cos_r / spec.area_m2, 0.0)


def _ray_interval(spec, foot, directions):
    """rho interval [lo, hi] where foot + rho * dir (2-D, light plane) lies inside the shape."""
    u, v = spec.extents
    fx, fy = foot[:, None, 0], foot[:, None, 1]
    dx, dy = directions[None, :, 0], directions[None, :, 1]
    if spec.shape in ("DISK", "ELLIPSE"):
        a, b = u / 2, v / 2
        qa = (dx / a) ** 2 + (dy / b) ** 2
        qb = 2 * (fx * dx / a**2 + fy * dy / b**2)
        qc = (fx / a) ** 2 + (fy / b) ** 2 - 1.0
        disc = qb * qb - 4 * qa * qc
        root = np.sqrt(np.maximum(disc, 0.0))
        lo = (-qb - root) / (2 * qa)
        hi = (-qb + root) / (2 * qa)
        hi = np.where(disc > 0.0, hi, lo)
        return lo, hi
    lo = np.full(np.broadcast(fx, dx).shape, -np.inf)
    hi = np.full(lo.shape, np.inf)
    for f, d, half in ((fx, dx, u / 2), (fy, dy, v / 2)):
        with np.errstate(divide="ignore", invalid="ignore"):
            t1 = (-half - f) / d
            t2 = (half - f) / d
        parallel = np.abs(d) < 1e-300
        outside = parallel & (np.abs(f) > half)
        t_lo = np.where(parallel, -np.inf, np.minimum(t1, t2))
        t_hi = np.where(parallel, np.inf, np.maximum(t1, t2))
        lo = np.maximum(lo, t_lo)
        hi = np.minimum(hi, np.where(outside, -np.inf, t_hi))
    return lo, hi


def _spread_quadrature(spec, p, n, order_r=QUADRATURE_RADIAL, order_phi=QUADRATURE_ANGULAR):
    """int over the emitter of att(a) cos_r cos_l / r^2 dA, polar around the receiver's foot point.

    att = max((tan h - tan a) * norm, 0) with tan a = rho / t only depends on the distance rho from
    the foot point, so in polar coordinates the integrand is smooth in rho on
    [0, min(t tan h, shape boundary)]: Gauss-Legendre in rho (exact support) and in azimuth.
    """
    half = 0.5 * spec.spread
    tan_h = np.tan(half)
    ns = _spread_normalisation(half)
    normal = spec.emission_direction
    rel = p - spec.position
    t = rel @ normal                                   # > 0: distance to the light plane
    foot = np.stack([rel @ spec.axes[:, 0], rel @ spec.axes[:, 1]], axis=1)
    rho_max = t * tan_h
    rg, rw = np.polynomial.legendre.leggauss(order_r)
    pg, pw = np.polynomial.legendre.leggauss(order_phi * 2)
    phi = np.pi * (pg + 1.0)
    wphi = np.pi * pw
    dirs2 = np.stack([np.cos(phi), np.sin(phi)], axis=1)
    lo, hi = _ray_interval(spec, foot, dirs2)          # (N, A)
    lo = np.maximum(lo, 0.0)
    hi = np.minimum(hi, rho_max[:, None])
    span = np.maximum(hi - lo, 0.0)
    rho = lo[..., None] + 0.5 * (rg + 1.0) * span[..., None]     # (N, A, R)
    w_r = 0.5 * rw * span[..., None]
    # Light point minus receiver = rho * (in-plane direction) - t * normal, world frame.
    x = rho * dirs2[None, :, None, 0]
    y = rho * dirs2[None, :, None, 1]
    vec = (x[..., None] * spec.axes[:, 0] + y[..., None] * spec.axes[:, 1]
           - t[:, None, None, None] * normal)            # receiver -> light point
    r2 = rho**2 + t[:, None, None] ** 2
    cos_l = t[:, None, None] / np.sqrt(r2)
    cos_r = np.maximum(np.einsum("nark,nk->nar", vec, n) / np.sqrt(r2), 0.0)
    att = np.maximum((tan_h - rho / t[:, None, None]) * ns, 0.0)
    integrand = att * cos_r * cos_l / r2 * rho          # rho: polar Jacobian
    return np.einsum("nar,nar,a->n", integrand, w_r, wphi)




@dataclass(frozen=True)
class AreaLight(CyclesLight, kind_key=("AREA", False)):
    """An area light (see the module docstring)."""

    @property
    def flags(self):
        # A sheared light with spread < 180 deg: Cycles' sampling of it is not modelled (bound None).
        unmodelled = self.is_sheared and self.spread < np.pi
        return EmitterFlags.AREA | (EmitterFlags.RENDERED_ONLY if unmodelled else EmitterFlags.NONE)

    def power_w(self):
        eu, ev = self.edges
        shear = norm(np.cross(eu, ev)) / (norm(eu) * norm(ev))
        return np.array(self.rgb_power, dtype=np.float64) * float(shear)

    def _unit_irradiance(self, p, n):
        return _area_factor(self, p, n)

    def _unit_intensity(self, d):
        cos_l = np.maximum(d @ self.emission_direction, 0.0)
        f = cos_l / np.pi
        if self.spread < np.pi:
            half = 0.5 * self.spread
            tan_a = np.sqrt(np.maximum(1.0 - cos_l**2, 0.0)) / np.maximum(cos_l, 1e-300)
            f = f * np.maximum((np.tan(half) - tan_a) * _spread_normalisation(half), 0.0) if half > 0 else f * 0.0
        return f

    # What callers ask (see CyclesLight) ----------------------------------------------------------
    @property
    def size_m(self):
        return float(max(self.extents))

    def describe(self):
        u, v = self.extents
        if self.shape in ("DISK", "ELLIPSE"):
            return f"area light, disk {u:.2g} m" if abs(u - v) < 1e-9 else f"area light, ellipse {u:.2g} x {v:.2g} m"
        return f"area light {u:.2g} x {v:.2g} m"

    @property
    def may_render_small(self):
        return False

    @property
    def render_reason(self):
        # Measured: with MIS on (the default) Cycles' light sampler and the emission its BSDF
        # rays hit disagree for a sheared area light (-3.3 % between the sum of single-light
        # renders and the joint render): the converged answer is Cycles' own, so render it.
        return "sheared area light: Cycles' MIS makes its answer its own; rendered" if self.is_sheared else ""

    def outline(self, sides=16):
        """World vertices (K, 3), metres, of a convex polygon holding the emitting shape: the
        parallelogram of its two edge vectors (Cycles' extentu/extentv) for squares and rectangles,
        a circumscribed ``sides``-gon (its affine image) for disks and ellipses. Under shear Cycles
        samples other shapes in the same plane, so a polygon circumscribing the circle of radius
        (|u| + |v|) / 2 stands in: it holds every one of them."""
        eu, ev = (np.asarray(e, float) for e in self.edges)
        centre = np.asarray(self.position, float)
        phi = 2 * np.pi * np.arange(sides) / sides
        r = 1.0 / np.cos(np.pi / sides)
        if self.is_sheared:
            radius = 0.5 * (np.linalg.norm(eu) + np.linalg.norm(ev)) * r
            uu = eu / np.linalg.norm(eu)
            vv = np.cross(np.cross(eu, ev), uu)
            vv /= np.linalg.norm(vv)
            return centre + radius * (np.cos(phi)[:, None] * uu + np.sin(phi)[:, None] * vv)
        if self.shape in ("DISK", "ELLIPSE"):
            return centre + 0.5 * r * (np.cos(phi)[:, None] * eu + np.sin(phi)[:, None] * ev)
        corners = np.array([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])
        return centre + corners[:, :1] * eu + corners[:, 1:] * ev

    def occlusion_bases(self, points, scene_reach, sides):
        n = len(points)
        outline = self.outline(sides=sides)
        return "polytope", np.broadcast_to(outline, (n,) + outline.shape), np.zeros(n, bool)

    def angular_radius(self, point_m, facing):
        u, v = self.extents
        ax = np.asarray(self.axes)
        phi = np.linspace(0, 2 * np.pi, 73)
        if self.shape in ("DISK", "ELLIPSE"):
            outline = np.c_[0.5 * u * np.cos(phi), 0.5 * v * np.sin(phi)]
        else:
            outline = np.array([[-u, -v], [u, -v], [u, v], [-u, v]]) / 2
        verts = self.position + outline[:, :1] * ax[:, 0] + outline[:, 1:] * ax[:, 1]
        dirs = verts - point_m
        dirs /= np.linalg.norm(dirs, axis=1, keepdims=True)
        return float(np.max(np.arccos(np.clip(dirs @ facing, -1, 1))))

    def _extreme_points(self):
        e1, e2 = self.edges
        return [self.position + a * e1 + b * e2 for a in (-0.5, 0.5) for b in (-0.5, 0.5)]

    def mirror_image_solid_angle(self, at, path_length):
        towards = np.asarray(at, float) - np.asarray(self.position, float)
        cos = abs(float(np.asarray(self.emission_direction, float) @ towards)) / max(float(np.linalg.norm(towards)), 1e-300)
        return float(self.area_m2) * cos / path_length ** 2

    def _seen_from(self, d, dist, eye, efficacy, weights, sides):
        if self.is_sheared:
            return None, "a sheared area light (Cycles samples another shape): not modelled"
        centre = np.asarray(self.position, float)
        eu, ev = (np.asarray(e, float) for e in self.edges)
        round_shape = self.shape in ("DISK", "ELLIPSE")
        area = float(self.area_m2)  # the emitter's area (its one home); not sheared here, so |eu x ev| (x pi/4)
        cos_l = float(d @ self.emission_direction)
        if cos_l <= 0:
            return None, "seen from behind: it emits nothing towards the eye"
        intensity = float(self.intensity_towards(d) @ weights) * efficacy  # cd
        luminance = intensity / (area * cos_l)
        if round_shape:
            poly = glare_math.disk_polygon(centre, eu, ev)
        else:
            poly = centre + np.array([[-.5, -.5], [.5, -.5], [.5, .5], [-.5, .5]]) @ np.array([eu, ev])
        outline = self.outline(sides=sides)  # holds the shape (the proofs' cells)
        return (luminance, glare_math.polygon_solid_angle(eye, poly), centre, outline), None

    def inverse_square_causes(self, d):
        if self.spread >= np.pi:
            u, v = self.extents
            return [f"light: the size of the area light ({u:.3g} x {v:.3g} m): an extended source follows I/d² "
                    f"only in the far field (five-times rule: {5 * self.size_m:.3g} m)"]
        return [f"light: the area light's spread ({math.degrees(self.spread):.3g} deg): close to the light "
                "only part of it shines on the meter, so E grows slower than 1/d² there"]

    def cosine_causes(self):
        if self.spread < np.pi:
            return [f"light: the area light's spread ({math.degrees(self.spread):.3g} deg) makes its radiance "
                    "depend on direction"]
        return []

    def exactness(self):
        sign = self._sign_note()
        if self.is_sheared:
            if self.spread < np.pi:
                return False, "unmodelled", ("sheared area light with spread < 180 deg: Cycles' sampling "
                                             "is not modelled (bound NaN); render it" + sign)
            return False, "sheared quadrature", (
                "sheared transform: Cycles' light sampling (modelled, Gauss-Legendre 48^2) and its BSDF-hit "
                "geometry disagree, and MIS mixes them; see irradiance_with_bound for the per-point bound" + sign)
        if self.spread >= np.pi:
            if self.shape in ("DISK", "ELLIPSE"):
                return True, "Lambert polygon", (f"equal-area {DISK_POLYGON_SIDES}-gon, rel. error < 1e-8 except within "
                                                 "~1 % of the radius from the rim (2e-5 there); per-point bound (vs the 1024-gon) from irradiance_with_bound"
                                                 + sign)
            return True, "Lambert polygon", "closed form with horizon clipping, exact" + sign
        if self.spread == 0.0:
            return True, "collimated", "spread 0: emission only along the normal" + sign
        return False, "quadrature", (f"Gauss-Legendre {QUADRATURE_RADIAL}x{2 * QUADRATURE_ANGULAR} in polar "
                                     "coordinates about the foot point; per-point bound from irradiance_with_bound"
                                     + sign)
