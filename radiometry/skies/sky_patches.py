"""Sky patches for daylight coefficients (pure numpy): Tregenza (145) and Reinhart MF:m subdivisions
plus one ground patch, in the order and geometry of Radiance's ``reinhartb.cal`` / ``gendaymtx``.

Patch 0 is the ground (the whole lower hemisphere, 2 pi sr). Sky rows r = 0 .. 7m-1 span altitudes
[r alpha, (r+1) alpha] with alpha = 90 deg / (7 m + 0.5); row r holds m x (30, 30, 24, 24, 18, 12, 6)
[r // m] patches, patch j of a row centred on azimuth 360 j / n (clockwise from north, +Y, towards
east, +X), spanning +- 180 / n deg; the last patch is the zenith cap above 7 m alpha. m = 1 gives the
145 Tregenza patches (Tregenza 1987; Reinhart & Walkenhorst 2001 for the subdivisions).
Directions: (cos alt sin az, cos alt cos az, sin alt) with +X east, +Y north, +Z up.
"""

import numpy as np

__all__ = ["SkyPatches", "reinhart_patches", "patch_of", "dome_mesh"]

_ROW_COUNTS = (30, 30, 24, 24, 18, 12, 6)


class SkyPatches:
    """Arrays over P patches (index 0 = ground): ``alt_lo``, ``alt_hi``, ``az_lo``, ``az_hi`` (rad;
    azimuths may start below 0 for the patch centred on north), ``altitude``/``azimuth`` of the
    centre, ``solid_angle`` (sr), ``cos_solid_angle`` (sr: the integral of cos(zenith) over the patch,
    0 for the ground), ``direction`` (P, 3); ``m`` the subdivision."""

    def __init__(self, m):
        self.m = int(m)
        alpha = (np.pi / 2) / (7 * self.m + 0.5)
        lo, hi, az_lo, az_hi, alt_c, az_c, dom = [-np.pi / 2], [0.0], [0.0], [2 * np.pi], [-np.pi / 2], [0.0], [2 * np.pi]
        for r in range(7 * self.m):
            n = self.m * _ROW_COUNTS[r // self.m]
            a0, a1 = r * alpha, (r + 1) * alpha
            for j in range(n):
                c = 2 * np.pi * j / n
                lo.append(a0)
                hi.append(a1)
                az_lo.append(c - np.pi / n)
                az_hi.append(c + np.pi / n)
                alt_c.append((r + 0.5) * alpha)
                az_c.append(c)
                dom.append(2 * np.pi * (np.sin(a1) - np.sin(a0)) / n)
        top = 7 * self.m * alpha
        lo.append(top)
        hi.append(np.pi / 2)
        az_lo.append(0.0)
        az_hi.append(2 * np.pi)
        alt_c.append(np.pi / 2)
        az_c.append(0.0)
        dom.append(2 * np.pi * (1 - np.sin(top)))
        self.alt_lo, self.alt_hi = np.array(lo), np.array(hi)
        self.az_lo, self.az_hi = np.array(az_lo), np.array(az_hi)
        self.altitude, self.azimuth = np.array(alt_c), np.array(az_c)
        self.solid_angle = np.array(dom)
        # integral of cos(zenith) over each patch, exact: (d az / 2)(sin^2 a1 - sin^2 a0); 0 for the ground
        # (the sky's normalisation to the diffuse horizontal uses it, not cos at the centre x solid angle)
        self.cos_solid_angle = np.where(self.alt_hi > 0, 0.5 * (self.az_hi - self.az_lo)
                                        * (np.sin(self.alt_hi) ** 2 - np.sin(np.maximum(self.alt_lo, 0)) ** 2), 0.0)
        ca = np.cos(self.altitude)
        self.direction = np.stack([ca * np.sin(self.azimuth), ca * np.cos(self.azimuth), np.sin(self.altitude)], axis=-1)

    @property
    def count(self):
        return len(self.solid_angle)

    def cos_zenith(self):
        """cos of the zenith angle at each sky patch's centre (0 for the ground)."""
        return np.where(np.arange(self.count) == 0, 0.0, np.sin(self.altitude))


def reinhart_patches(m=1):
    """``SkyPatches`` for Reinhart MF:m (m = 1: Tregenza, 146 patches with the ground)."""
    if int(m) != m or m < 1 or m > 8:
        raise ValueError(f"the Reinhart subdivision must be an integer 1..8, got {m!r}")
    return SkyPatches(int(m))


def _row_edges(patches, row):
    """Azimuths (deg, in [0, 360)) of the patch edges of sky row ``row`` (0 .. 7m-1)."""
    n = patches.m * _ROW_COUNTS[row // patches.m]
    return np.mod((np.arange(n) + 0.5) * 360.0 / n, 360.0)


def dome_mesh(patches, step_deg=1.0):
    """Triangles on the unit sphere whose radial projections are the patches (patch 0: the ground).

    Returns a list over patches of (vertices (V, 3), faces (F, 3) int). Every vertex lies on the
    sphere; an edge along a meridian projects onto that meridian exactly, an edge along an altitude
    circle is a chord of at most ``step_deg`` (its projection strays at most ~2e-5 rad from the
    circle for 1 deg). The vertices of each altitude circle are shared by the patches above and
    below it (the same floats), so the triangles close the sphere without cracks: no direction
    escapes between two patches (T-junction-free, zipper triangulation between circles).
    """
    m, rows = patches.m, 7 * patches.m
    alpha = 90.0 / (7 * m + 0.5)
    grid = np.arange(0.0, 360.0, float(step_deg))
    circles = []  # per circle r (altitude r alpha, r = 0 .. rows): sorted azimuths (deg) and unit vectors
    for r in range(rows + 1):
        az = [grid]
        if r > 0:
            az.append(_row_edges(patches, r - 1))
        if r < rows:
            az.append(_row_edges(patches, r))
        az = np.unique(np.round(np.concatenate(az), 9))
        alt, azr = np.radians(r * alpha), np.radians(az)
        vec = np.stack([np.cos(alt) * np.sin(azr), np.cos(alt) * np.cos(azr), np.full(az.shape, np.sin(alt))], -1)
        circles.append((az, vec))

    def arc(circle, lo, width):
        az, vec = circles[circle]
        rel = np.mod(az - lo, 360.0)
        rel = np.where(rel > 360.0 - 1e-7, 0.0, rel)
        keep = np.flatnonzero(rel <= width + 1e-7)
        order = keep[np.argsort(rel[keep])]
        return rel[order], vec[order]

    out = []
    az0, v0 = circles[0]
    ring = np.concatenate([v0, v0[:1]])
    verts = np.concatenate([[[0.0, 0.0, -1.0]], ring[:-1]])
    k = len(v0)
    out.append((verts, np.array([[0, 1 + i, 1 + (i + 1) % k] for i in range(k)])))  # the ground: a fan to the nadir
    for r in range(rows):
        n = m * _ROW_COUNTS[r // m]
        width = 360.0 / n
        for j in range(n):
            lo = 360.0 * j / n - width / 2
            rb, vb = arc(r, lo, width)
            rt, vt = arc(r + 1, lo, width)
            faces, i, t = [], 0, 0
            nb = len(rb)
            while i < nb - 1 or t < len(rt) - 1:
                if t == len(rt) - 1 or (i < nb - 1 and rb[i + 1] <= rt[t + 1]):
                    faces.append((i, i + 1, nb + t))
                    i += 1
                else:
                    faces.append((i, nb + t + 1, nb + t))
                    t += 1
            out.append((np.concatenate([vb, vt]), np.array(faces)))
    az, vec = circles[rows]
    k = len(az)
    verts = np.concatenate([[[0.0, 0.0, 1.0]], vec])
    out.append((verts, np.array([[0, 1 + i, 1 + (i + 1) % k] for i in range(k)])))  # the zenith cap
    return out


def patch_of(directions, patches):
    """Patch index (...,) of unit world ``directions`` (..., 3); the ground (0) for z < 0."""
    d = np.asarray(directions, float)
    alt = np.arcsin(np.clip(d[..., 2], -1, 1))
    az = np.mod(np.arctan2(d[..., 0], d[..., 1]), 2 * np.pi)
    out = np.zeros(alt.shape, int)
    for p in range(1, patches.count):
        a0, a1 = patches.alt_lo[p], patches.alt_hi[p]
        z0, z1 = patches.az_lo[p], patches.az_hi[p]
        in_alt = (alt >= a0) & ((alt < a1) | (p == patches.count - 1))
        rel = np.mod(az - z0, 2 * np.pi)
        out = np.where(in_alt & (rel < (z1 - z0)) & (d[..., 2] >= 0), p, out)
    return out
