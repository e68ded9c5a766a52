"""Local shading-frame geometry (pbrt-v4 style building blocks).

All directions are arrays of shape ``(..., 3)`` in the LOCAL shading frame: x = tangent,
y = bitangent, z = surface normal. Directions point AWAY from the surface (both the light
direction ``wi`` and the view direction ``wo``). Angles are in radians.

References
----------
M. Pharr, W. Jakob, G. Humphreys, *Physically Based Rendering*, 4th ed. (2023), ch. 3.8
("Spherical geometry") and 9.1 ("BSDF representation", the local shading coordinate system).
"""

import numpy as np

__all__ = [
    "cos_theta", "cos2_theta", "sin2_theta", "tan2_theta", "normalize", "same_hemisphere",
    "spherical_to_cartesian", "cartesian_to_spherical", "reflect", "reflect_about",
    "half_vector", "to_local", "dot", "orthonormal_basis", "sample_cosine_hemisphere",
]


def dot(a, b):
    """Dot product over the last axis (broadcasting)."""
    return np.sum(np.asarray(a, dtype=float) * np.asarray(b, dtype=float), axis=-1)


def cos_theta(w):
    """cos θ of a unit local direction: its z component."""
    return np.asarray(w)[..., 2]


def cos2_theta(w):
    return np.asarray(w)[..., 2] ** 2


def sin2_theta(w):
    # max(0, .) guards against 1 - cos² < 0 from rounding when |z| is 1 + ulp.
    return np.maximum(0.0, 1.0 - cos2_theta(w))


def tan2_theta(w):
    """tan² θ; inf at the horizon (cos θ = 0) without a warning."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return sin2_theta(w) / cos2_theta(w)


def normalize(v):
    """Unit vectors along ``v`` (shape (..., 3)).

    Robust definitions (documented behaviour, no warnings):

    * a NaN component gives NaN in every component of that vector;
    * vectors with infinite components are replaced by their limit direction (the signs of the
      infinite components, finite components -> 0), e.g. ``[inf, 0, 1] -> [1, 0, 0]``;
    * the zero vector stays zero (it is then "below the horizon" everywhere: cos θ = 0);
    * huge or tiny finite vectors (1e300, 1e-300) are scaled by their largest component first
      so the squared norm neither overflows nor underflows.
    """
    v = np.asarray(v, dtype=float)
    with np.errstate(all="ignore"):
        has_nan = np.isnan(v).any(axis=-1, keepdims=True)  # before the inf substitution below
        is_inf = np.isinf(v)
        any_inf = is_inf.any(axis=-1, keepdims=True)
        v = np.where(any_inf, np.where(is_inf, np.sign(v), 0.0), v)
        scale = np.max(np.abs(v), axis=-1, keepdims=True)
        # scale == 0 only for the zero vector; dividing by 1 keeps it zero.
        v = v / np.where(scale > 0, scale, 1.0)
        norm = np.sqrt(np.sum(v * v, axis=-1, keepdims=True))
        out = v / np.where(norm > 0, norm, 1.0)
        # NaN in any component poisons the whole vector (np.max already propagates NaN).
        return np.where(has_nan, np.nan, out)


def same_hemisphere(a, b):
    """True where two local directions lie on the same side of the surface (z·z > 0)."""
    return np.asarray(a)[..., 2] * np.asarray(b)[..., 2] > 0


def spherical_to_cartesian(theta, phi):
    """Unit local direction from polar angle ``theta`` (from +z) and azimuth ``phi`` [rad]."""
    theta = np.asarray(theta, dtype=float)
    phi = np.asarray(phi, dtype=float)
    s = np.sin(theta)
    return np.stack(np.broadcast_arrays(s * np.cos(phi), s * np.sin(phi), np.cos(theta)), axis=-1)


def cartesian_to_spherical(w):
    """(theta, phi) [rad] of a local direction; phi in (-π, π]. ``w`` need not be unit."""
    w = normalize(w)
    theta = np.arccos(np.clip(w[..., 2], -1.0, 1.0))
    phi = np.arctan2(w[..., 1], w[..., 0])
    return theta, phi


def reflect(w):
    """Mirror reflection of a local direction about the normal z: (-x, -y, z)."""
    w = np.asarray(w, dtype=float)
    return w * np.array([-1.0, -1.0, 1.0])


def reflect_about(w, n):
    """Mirror reflection of ``w`` about the axis ``n`` (unit): 2 (w·n) n - w."""
    w = np.asarray(w, dtype=float)
    n = np.asarray(n, dtype=float)
    return 2.0 * dot(w, n)[..., None] * n - w


def half_vector(wi, wo):
    """Unit half vector normalize(wi + wo), flipped into the upper hemisphere (z >= 0).

    For wi = -wo the sum is zero and the result is the zero vector (callers treat such
    configurations as below the horizon: one of the two cosines is <= 0 there anyway).
    """
    h = normalize(np.asarray(wi, dtype=float) + np.asarray(wo, dtype=float))
    return np.where(h[..., 2:3] < 0, -h, h)


def to_local(w, n, t):
    """Express world directions ``w`` in the local frame of normal ``n`` and tangent ``t``.

    ``t`` is Gram-Schmidt orthogonalised against ``n``; the bitangent is b = n × t, so the frame
    (t, b, n) is right-handed. All arrays broadcast over leading axes. This is THE one conversion
    from world/Blender space into the shading frame used by every model.
    """
    n = normalize(n)
    t = np.asarray(t, dtype=float)
    t = normalize(t - dot(t, n)[..., None] * n)
    b = np.cross(n, t)
    w = np.asarray(w, dtype=float)
    return np.stack(np.broadcast_arrays(dot(w, t), dot(w, b), dot(w, n)), axis=-1)


def orthonormal_basis(n):
    """Two unit vectors (b1, b2) completing unit ``n`` to a right-handed frame (b1, b2, n).

    Branchless construction of Duff et al., "Building an Orthonormal Basis, Revisited",
    JCGT 6(1), 2017 (Listing 3); valid for every unit n including n = -z.
    """
    n = np.asarray(n, dtype=float)
    x, y, z = n[..., 0], n[..., 1], n[..., 2]
    sign = np.where(z >= 0, 1.0, -1.0)
    a = -1.0 / (sign + z)
    b = x * y * a
    b1 = np.stack([1.0 + sign * x * x * a, sign * b, -sign * x], axis=-1)
    b2 = np.stack([b, sign + y * y * a, -y], axis=-1)
    return b1, b2


def sample_cosine_hemisphere(u1, u2):
    """Cosine-weighted upper-hemisphere direction, density cos θ / π [1/sr] (Malley's method)."""
    u1 = np.asarray(u1, dtype=float)
    u2 = np.asarray(u2, dtype=float)
    r = np.sqrt(u1)
    phi = 2.0 * np.pi * u2
    return np.stack(np.broadcast_arrays(r * np.cos(phi), r * np.sin(phi),
                                        np.sqrt(np.maximum(0.0, 1.0 - u1))), axis=-1)
