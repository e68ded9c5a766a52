"""An independent reference for the throughput room (bench/scenes.py ``room``), in plain numpy.

Why: Radiometer read ~2.5 % above Radiance's path tracer in that room, all of it in reflected light.
This tracer knows nothing of Cycles, Radiance or Radiometer: a closed 4 x 4 x 3 m box of Lambertian
walls (albedo 0.7) lit by a 1 m square Lambertian panel 1 cm below the ceiling, facing down, of
radiance L = P / (pi A) (Blender's normalised area light). Indirect irradiance at a point is the
cosine-sampled path sum E_ind = sum_k rho^k E_dir(x_k) (each vertex's direct light from Lambert's
polygon formula, exact), 50 bounces (rho^50 = 2e-8). Two semantics for a path that reaches the
panel from below: ``transparent`` (it passes through to the ceiling, as Cycles treats lights) and
``opaque`` (it ends there: Radiance's ``light`` polygon reflects nothing). Bench only, never at run time.
"""

import math

import numpy as np

LO = np.array([-2.0, -2.0, 0.0])
HI = np.array([2.0, 2.0, 3.0])


def panel(z=2.99, half=0.5):
    return np.array([[-half, -half, z], [half, -half, z], [half, half, z], [-half, half, z]])


def panel_irradiance(x, n, radiance, quad):
    """Irradiance (W/m^2) at points ``x`` (M, 3) facing ``n`` (M, 3) from the downward-facing ``quad``
    of uniform ``radiance`` (Lambert's polygon formula; zero above the panel's plane)."""
    r = quad[None, :, :] - x[:, None, :]
    r /= np.linalg.norm(r, axis=2, keepdims=True)
    s = 0.0
    for i in range(4):
        a, b = r[:, i], r[:, (i + 1) % 4]
        c = np.cross(a, b)
        cn = np.linalg.norm(c, axis=1)
        angle = np.arctan2(cn, np.einsum("ij,ij->i", a, b))
        s = s + angle * np.einsum("ij,ij->i", c, n) / np.maximum(cn, 1e-300)
    return np.where(x[:, 2] < quad[0, 2], 0.5 * radiance * np.abs(s), 0.0)


def _cosine_directions(n, rng):
    u1, u2 = rng.random(len(n)), rng.random(len(n))
    r, phi = np.sqrt(u1), 2 * math.pi * u2
    helper = np.where(np.abs(n[:, 2:3]) < 0.9, [[0.0, 0.0, 1.0]], [[1.0, 0.0, 0.0]])
    t = np.cross(helper, n)
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    b = np.cross(n, t)
    return (r * np.cos(phi))[:, None] * t + (r * np.sin(phi))[:, None] * b + np.sqrt(1 - u1)[:, None] * n


def _exit(o, d):
    """Where rays from inside the box leave it: hit points, inward normals, distances."""
    with np.errstate(divide="ignore", invalid="ignore"):
        tb = np.where(d > 0, (HI - o) / d, np.where(d < 0, (LO - o) / d, np.inf))
    axis = np.argmin(tb, axis=1)
    rows = np.arange(len(o))
    t = tb[rows, axis]
    normal = np.zeros_like(o)
    normal[rows, axis] = -np.sign(d[rows, axis])
    return o + t[:, None] * d, normal, t


def irradiance(point, normal=(0.0, 0.0, 1.0), *, paths=100_000, opaque=False, albedo=0.7, power=400.0,
               bounces=50, seed=0):
    """(direct, indirect, indirect standard error) in W/m^2 at ``point`` facing ``normal``."""
    quad = panel()
    radiance = power / math.pi  # 1 m^2 panel
    rng = np.random.default_rng(seed)
    p = np.asarray(point, float)
    n0 = np.asarray(normal, float) / np.linalg.norm(normal)
    direct = float(panel_irradiance(p[None], n0[None], radiance, quad)[0])
    o, n = np.repeat(p[None], paths, 0), np.repeat(n0[None], paths, 0)
    total, alive = np.zeros(paths), np.ones(paths, bool)
    zp = quad[0, 2]
    for k in range(1, bounces + 1):
        d = _cosine_directions(n, rng)
        x, n2, t = _exit(o, d)
        if opaque:  # the ray crosses the panel's plane inside the panel before the wall: it ends
            with np.errstate(divide="ignore", invalid="ignore"):
                tp = (zp - o[:, 2]) / d[:, 2]
            q = o + tp[:, None] * d
            alive &= ~((d[:, 2] > 0) & (o[:, 2] < zp) & (tp < t) & (np.abs(q[:, 0]) <= 0.5) & (np.abs(q[:, 1]) <= 0.5))
        total += np.where(alive, albedo ** k * panel_irradiance(x, n2, radiance, quad), 0.0)
        o, n = x + 1e-9 * n2, n2
    return direct, float(total.mean()), float(total.std(ddof=1) / math.sqrt(paths))
