"""Closed-form projected solid angles (form factors times pi) used by the light models.

All functions are vectorised over leading axes, float64, and return the projected solid angle
Omega_perp = int cos(theta) d omega over the visible part of an emitter seen from a receiver, in sr;
the irradiance from a uniform (Lambertian) emitter of radiance L is E = L * Omega_perp.

References
----------
- J. H. Lambert, *Photometria* (1760); J. Arvo, "Applications of Irradiance Tensors to the
  Simulation of Non-Lambertian Phenomena", SIGGRAPH 1995; D. R. Baum et al., "Improving Radiosity
  Solutions Through the Use of Analytically Determined Form-Factors", SIGGRAPH 1989: polygon formula
  Omega_perp = 1/2 sum_i Gamma_i . n.
- J. M. Snyder, "Area light sources for real-time graphics", Microsoft Research MSR-TR-96-11 (1996);
  S. Lagarde, C. de Rousiers, "Moving Frostbite to Physically Based Rendering 3.0", SIGGRAPH 2014
  course notes, eq. 17-19: spherical cap partly below the horizon.
"""

import numpy as np

__all__ = ["cap_projected_solid_angle", "polygon_projected_solid_angle", "unit", "norm"]


def norm(v):
    """Euclidean norm over the last axis, computed without overflow/underflow for huge/tiny values."""
    v = np.asarray(v, dtype=np.float64)
    scale = np.max(np.abs(v), axis=-1, keepdims=True)
    safe = np.where(scale > 0.0, scale, 1.0)
    return (scale * np.sqrt(np.sum((v / safe) ** 2, axis=-1, keepdims=True)))[..., 0]


def unit(v):
    """Unit vectors over the last axis; zero vectors stay zero."""
    v = np.asarray(v, dtype=np.float64)
    n = norm(v)[..., np.newaxis]
    return np.divide(v, n, out=np.zeros_like(v), where=n > 0.0)


def cap_projected_solid_angle(cos_theta, sin_sq_sigma):
    """Projected solid angle of a spherical cap (uniform cone), clipped by the receiver's horizon.

    Parameters
    ----------
    cos_theta : array_like
        Cosine of the angle between the receiver normal and the cap's axis.
    sin_sq_sigma : array_like
        sin^2 of the cap's half-angle sigma, in (0, 1]; 1 means a hemisphere (receiver inside).

    Returns
    -------
    numpy.ndarray
        pi sin^2(sigma) cos(theta) when the cap is fully above the horizon, 0 when fully below,
        and Snyder's exact expression (cos t acos y - x sin t sqrt(1 - y^2)) sin^2 s +
        atan(sin t sqrt(1 - y^2) / x), x = cot(sigma), y = -x cot(theta) in between.
    """
    c = np.clip(np.asarray(cos_theta, dtype=np.float64), -1.0, 1.0)
    s2 = np.clip(np.asarray(sin_sq_sigma, dtype=np.float64), 0.0, 1.0)
    c, s2 = np.broadcast_arrays(c, s2)
    full = np.pi * s2 * np.maximum(c, 0.0)
    partial = (c * c < s2)
    out = np.array(full, dtype=np.float64)
    if np.any(partial):
        cp, sp = c[partial], s2[partial]
        sin_t = np.sqrt(np.maximum(1.0 - cp * cp, 0.0))
        x = np.sqrt(np.maximum(1.0 - sp, 0.0) / sp)  # cot(sigma)
        y = np.clip(-x * cp / np.maximum(sin_t, 1e-300), -1.0, 1.0)
        root = sin_t * np.sqrt(np.maximum(1.0 - y * y, 0.0))
        value = (cp * np.arccos(y) - x * root) * sp + np.arctan2(root, x)
        out[partial] = np.maximum(value, 0.0)
    return out


def polygon_projected_solid_angle(vertices, points, normals):
    """Projected solid angle of convex planar polygons, clipped to each receiver's upper hemisphere.

    Parameters
    ----------
    vertices : array_like, shape (V, 3)
        Polygon vertices in order (either winding), metres, shared by all receivers.
    points, normals : array_like, shape (N, 3)
        Receiver positions (m) and unit normals.

    Returns
    -------
    numpy.ndarray, shape (N,)
        Omega_perp in sr (0 for a polygon entirely below the horizon).

    Notes
    -----
    The horizon clip (Sutherland-Hodgman against the plane n . (x - p) = 0) keeps a fixed number of
    slots per receiver: each edge yields its start vertex if above and the crossing point if it
    crosses; empty slots repeat the first kept vertex, giving zero-length edges that add nothing.
    Edge terms use atan2(|a x b|, a . b) for accuracy at small angles (far receivers).
    """
    verts = np.asarray(vertices, dtype=np.float64)
    p = np.asarray(points, dtype=np.float64)
    n = np.asarray(normals, dtype=np.float64)
    rel = verts[np.newaxis, :, :] - p[:, np.newaxis, :]          # (N, V, 3)
    h = np.einsum("nvk,nk->nv", rel, n)                            # height above the horizon
    rel_next = np.roll(rel, -1, axis=1)
    h_next = np.roll(h, -1, axis=1)
    keep_start = h >= 0.0
    crosses = (h >= 0.0) != (h_next >= 0.0)
    denom = np.where(crosses, h - h_next, 1.0)
    t = np.where(crosses, h / denom, 0.0)
    crossing = rel + t[..., np.newaxis] * (rel_next - rel)
    # Put the crossing point exactly on the horizon plane (removes round-off below it).
    crossing = crossing - np.einsum("nv,nk->nvk", np.einsum("nvk,nk->nv", crossing, n) * crosses, n)
    slots = np.stack([rel, crossing], axis=2).reshape(p.shape[0], -1, 3)   # (N, 2V, 3)
    valid = np.stack([keep_start, crosses], axis=2).reshape(p.shape[0], -1)
    order = np.argsort(~valid, axis=1, kind="stable")
    slots = np.take_along_axis(slots, order[..., np.newaxis], axis=1)
    valid = np.take_along_axis(valid, order, axis=1)
    first = slots[:, :1, :]
    slots = np.where(valid[..., np.newaxis], slots, first)
    u = unit(slots)
    u_next = np.roll(u, -1, axis=1)
    cross = np.cross(u, u_next)
    sin_edge = norm(cross)
    cos_edge = np.einsum("nvk,nvk->nv", u, u_next)
    angle = np.arctan2(sin_edge, cos_edge)
    ratio = np.divide(angle, sin_edge, out=np.ones_like(angle), where=sin_edge > 0.0)
    total = 0.5 * np.sum(np.einsum("nvk,nk->nv", cross, n) * ratio, axis=1)
    total = np.where(np.any(valid, axis=1), np.abs(total), 0.0)
    return total
