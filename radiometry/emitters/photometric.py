"""Photometric (IES / EULUMDAT) point light: a goniometric intensity table read the way Cycles reads it.

A photometric point light (radius 0, node tree Emission <- IES Texture) has radiant intensity
I(d) = rgb_power x table(d) W/sr per channel (:class:`IntensityTable`: Cycles' IES lookup, Catmull-Rom
on table indices, 0 outside the table) and E = I cos / r^2 (a delta position).

Flux comes from ONE integration, :func:`table_flux`, which every caller uses (the light's power, the
photometric power dialog, a file's lumens in :class:`..photometric_files.Photometry`): 8 x 8
Gauss-Legendre nodes per table cell over the interpolated table (a bicubic polynomial inside each cell,
so exact up to the clamp at 0), times the Jacobian of the table's direction map when the light's matrix
or Mapping is not a similarity (d omega_world = |det B| / |B u|^3 d omega_table, B = (V M^T)^-1).
Checked against closed forms: an isotropic table (4 pi I) and a cosine table (pi I_0).
"""

from dataclasses import dataclass, field

import numpy as np

from ..geometry import unit
from ..units import as_finite_array, frozen_array
from .base import EmitterFlags
from .point import PointLight, delta_irradiance

__all__ = ["IntensityTable", "PhotometricLight", "catmull_rom_table", "integrate_cells", "table_flux"]

_frozen = frozen_array


def _cubic(a, b, c, d, x):
    # Catmull-Rom through b (x = 0) and c (x = 1), Cycles' cubic_interp.
    return 0.5 * (((d + 3.0 * (b - c) - a) * x + (2.0 * a - 5.0 * b + 4.0 * c - d)) * x + (c - a)) * x + b


def catmull_rom_table(h_deg, v_deg, table, h, v):
    """Cycles' IES interpolation of ``table`` (n_h, n_v) at C angles ``h`` and vertical angles
    ``v`` (deg, broadcast). ``h_deg`` must run from 0 to 360 for the C wrap (otherwise the ends
    repeat, and C outside the range gives 0)."""
    H = np.asarray(h_deg, dtype=np.float64)
    V = np.asarray(v_deg, dtype=np.float64)
    T = np.asarray(table, dtype=np.float64)
    h, v = np.broadcast_arrays(np.asarray(h, dtype=np.float64), np.asarray(v, dtype=np.float64))
    shape = h.shape
    h, v = h.ravel(), v.ravel()
    n_h, n_v = H.size, V.size
    out = np.zeros(h.shape)
    nan = np.isnan(h) | np.isnan(v)
    inside = ~nan & (v >= V[0]) & (v < V[-1]) & (h >= H[0]) & (h < H[-1])
    wrap_h = H[0] < 1e-5 and H[-1] > 360.0 - 1e-5
    wrap_vlow = V[0] < 1e-5
    wrap_vhigh = V[-1] > 180.0 - 1e-5
    hi, vi = h[inside], v[inside]
    ih = np.clip(np.searchsorted(H, hi, side="left") - 1, 0, n_h - 2)
    iv = np.clip(np.searchsorted(V, vi, side="left") - 1, 0, n_v - 2)
    fh = (hi - H[ih]) / (H[ih + 1] - H[ih])
    fv = (vi - V[iv]) / (V[iv + 1] - V[iv])

    def vertical(rows):
        b = T[rows, iv]
        c = T[rows, iv + 1]
        a = np.where(iv > 0, T[rows, np.maximum(iv - 1, 0)], T[rows, 1] if wrap_vlow else b)
        d_idx = np.minimum(iv + 2, n_v - 1)
        d = np.where(iv + 2 < n_v, T[rows, d_idx], T[rows, n_v - 2] if wrap_vhigh else c)
        return _cubic(a, b, c, d, fv)

    b = vertical(ih)
    c = vertical(ih + 1)
    if wrap_h:
        a = vertical(np.where(ih > 0, ih - 1, n_h - 2))
        d = vertical(np.where(ih + 2 < n_h, ih + 2, 1))
    else:  # Cycles falls back to the second point at both ends
        a = np.where(ih > 0, vertical(np.maximum(ih - 1, 0)), b)
        d = np.where(ih + 2 < n_h, vertical(np.minimum(ih + 2, n_h - 1)), b)
    out[inside] = np.maximum(_cubic(a, b, c, d, fh), 0.0)
    out[nan] = np.nan
    return out.reshape(shape)[()]


_GL8 = np.polynomial.legendre.leggauss(8)


def integrate_cells(func, h_deg, v_deg, weight):
    """int int func(h, v) weight(v) dh dv over the table's cells, both in radians, 8 x 8 GL nodes
    per cell (the integrand is a polynomial inside each cell except for the clamp at 0)."""
    x, w = _GL8
    hs = 0.5 * (h_deg[:-1, None] + h_deg[1:, None]) + 0.5 * np.diff(h_deg)[:, None] * x[None, :]
    whs = 0.5 * np.radians(np.diff(h_deg))[:, None] * w[None, :]
    vs = 0.5 * (v_deg[:-1, None] + v_deg[1:, None]) + 0.5 * np.diff(v_deg)[:, None] * x[None, :]
    wvs = 0.5 * np.radians(np.diff(v_deg))[:, None] * w[None, :]
    hh, vv = hs.ravel(), vs.ravel()
    values = func(hh[:, None], vv[None, :])
    return float(np.einsum("ij,i,j->", values, whs.ravel(), wvs.ravel() * weight(vv)))




def table_flux(h_deg, v_deg, table, direction_map=None):
    """Integral over the sphere of the interpolated table (``table`` in cd gives lm; in W/sr per W
    gives W per W), type C angles (v = 0 along -Z of the table frame, h the C angle).

    ``direction_map``: the 3 x 3 map A taking a world direction d to the table's frame (u = unit(A d));
    None for a rotation (no Jacobian). The integral is over world directions, so for a general A the
    integrand carries |det A^-1| / |A^-1 u|^3.
    """
    h_deg = np.asarray(h_deg, float)
    v_deg = np.asarray(v_deg, float)

    def func(hh, vv):
        values = catmull_rom_table(h_deg, v_deg, table, hh, vv)
        if direction_map is None:
            return values
        b = np.linalg.inv(np.asarray(direction_map, float))
        hr, vr = np.radians(hh), np.radians(vv)
        hr, vr = np.broadcast_arrays(hr, vr)
        # u from (h, v): v = acos(-u_z), h = atan2(u_x, u_y) + pi.
        u = np.stack([-np.sin(vr) * np.sin(hr), -np.sin(vr) * np.cos(hr), -np.cos(vr)], axis=-1)
        return values * abs(np.linalg.det(b)) / np.linalg.norm(u @ b.T, axis=-1) ** 3

    cells_h, cells_v = h_deg, v_deg
    if direction_map is not None:
        # The Jacobian is smooth but not a polynomial: cut every table cell into pieces of at most
        # JACOBIAN_CELL_DEG (the interpolant stays a polynomial on each piece).
        cells_h, cells_v = _subdivide(h_deg, JACOBIAN_CELL_DEG), _subdivide(v_deg, JACOBIAN_CELL_DEG)
    return integrate_cells(func, cells_h, cells_v, lambda v: np.sin(np.radians(v)))


#: Largest integration cell (deg) when the direction map is not a similarity (8 x 8 Gauss-Legendre per
#: cell: relative error < 1e-12 for a 3:1 non-uniform scale, 1e-7 at 25:1; 3e-5 at 3:1 with 90 deg cells).
JACOBIAN_CELL_DEG = 5.0


def _subdivide(angles, step):
    pieces = [np.linspace(a, b, int(np.ceil((b - a) / step)) + 1)[:-1] for a, b in zip(angles[:-1], angles[1:])]
    return np.concatenate(pieces + [angles[-1:]])


@dataclass(frozen=True)
class IntensityTable:
    """A photometric (IES) light's intensity per unit ``rgb_power``, as Cycles looks it up.

    I(d) = rgb_power * interp(h(d), v(d)) W/sr for a world direction d leaving the light, with
    u = vector_map @ matrix.T @ d (Cycles: Geometry Incoming, world-to-object NORMAL transform =
    the transposed object matrix, then the node tree's Mapping), v = acos(-u_z / |u|) and
    h = atan2(u_x, u_y) + 180 deg, and ``interp`` Cycles' IES kernel
    (:func:`catmull_rom_table`: Catmull-Rom on indices, 0 outside the table).

    Attributes
    ----------
    h_deg : (n_h,) ascending C angles of Cycles' table, deg (0..360 for a wrapping table)
    v_deg : (n_v,) ascending vertical angles, deg (0 = along the IES vector's -Z)
    values : (n_h, n_v) W/sr per W of rgb_power (Cycles' IES texture value / (4 pi))
    vector_map : (3, 3) the Mapping node's linear map (identity without one)
    rgb_scale : (3,) Emission colour x Emission strength x IES strength, folded into rgb_power
        by :func:`.cycles_light.from_blender_values`
    label : str, where the table came from (shown in notes)
    """

    h_deg: np.ndarray
    v_deg: np.ndarray
    values: np.ndarray
    vector_map: np.ndarray = field(default_factory=lambda: np.eye(3))
    rgb_scale: np.ndarray = field(default_factory=lambda: np.ones(3))
    label: str = "IES"

    def __post_init__(self):
        h = _frozen(as_finite_array(self.h_deg, "h_deg"))
        v = _frozen(as_finite_array(self.v_deg, "v_deg"))
        values = _frozen(as_finite_array(self.values, "values"))
        if h.ndim != 1 or v.ndim != 1 or h.size < 2 or v.size < 2 or values.shape != (h.size, v.size):
            raise ValueError("IntensityTable needs h_deg (n_h >= 2), v_deg (n_v >= 2) and values (n_h, n_v)")
        if np.any(np.diff(h) <= 0.0) or np.any(np.diff(v) <= 0.0):
            raise ValueError("IntensityTable angles must increase")
        if np.any(values < 0.0):
            raise ValueError("IntensityTable values must be >= 0")
        vmap = as_finite_array(self.vector_map, "vector_map", (3, 3))
        if abs(np.linalg.det(vmap)) < 1e-12:
            raise ValueError("IntensityTable vector_map is singular")
        for name, value in (("h_deg", h), ("v_deg", v), ("values", values), ("vector_map", _frozen(vmap)),
                            ("rgb_scale", _frozen(as_finite_array(self.rgb_scale, "rgb_scale", (3,))))):
            object.__setattr__(self, name, value)

    def lookup(self, local):
        """Table value for directions ``local`` = matrix.T @ d (..., 3), before the Mapping."""
        u = unit(np.asarray(local, dtype=np.float64) @ self.vector_map.T)
        v = np.degrees(np.arccos(np.clip(-u[..., 2], -1.0, 1.0)))
        h = np.degrees(np.arctan2(u[..., 0], u[..., 1]) + np.pi)
        if self.h_deg[0] == 0.0 and abs(self.h_deg[-1] - 360.0) < 1e-4:
            # Cycles returns 0 at exactly h = 360 deg (h >= last angle), a single direction where
            # its rendered patch still sees the neighbouring values: read it as 0 deg instead.
            h = np.where(h >= self.h_deg[-1], 0.0, h)
        return catmull_rom_table(self.h_deg, self.v_deg, self.values, h, v)

    def flux_per_unit(self, matrix=np.eye(3)):
        """Integral of the table over world directions (W per W of rgb_power) for a light whose
        object matrix is ``matrix`` (:func:`table_flux`)."""
        a = self.vector_map @ np.asarray(matrix, float).T
        q = a / np.cbrt(abs(np.linalg.det(a)))
        similarity = np.allclose(q @ q.T, np.eye(3), atol=1e-9)
        return table_flux(self.h_deg, self.v_deg, self.values, None if similarity else a)


@dataclass(frozen=True)
class PhotometricLight(PointLight, kind_key=("POINT", True)):
    """A photometric point light of radius 0 (see the module docstring)."""

    def _check_kind(self):
        if self.kind != "POINT" or self.radius != 0.0:
            raise ValueError("an intensity table is modelled for a point light of radius 0 only "
                             f"(got {self.kind.lower()} of radius {self.radius:g} m)")
        if not isinstance(self.intensity_table, IntensityTable):
            raise ValueError("intensity_table must be an IntensityTable")

    @property
    def flags(self):
        return EmitterFlags.DELTA_POSITION

    def power_w(self):
        return np.array(self.rgb_power, dtype=np.float64) * self.intensity_table.flux_per_unit(self.matrix)

    def _unit_intensity(self, d):
        return self.intensity_table.lookup(np.asarray(d, dtype=np.float64) @ self.matrix)

    def _unit_irradiance(self, p, n):
        # Delta source: E = I(-w) cos / r^2, w = unit vector from the receiver to the light.
        g, w, _r = delta_irradiance(self.position, p, n, "a photometric point light")
        g = self._unit_intensity(-w) * g
        return g, np.zeros_like(g)

    def exactness(self):
        return True, "photometric point", (f"{self.intensity_table.label}: I(theta, C) cos / r^2 with Cycles' IES "
                                           "interpolation, exact" + self._sign_note())
