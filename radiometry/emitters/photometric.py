"""Photometric (IES / EULUMDAT) point light: a goniometric intensity table read the way Cycles reads it.

A photometric point light (radius 0, node tree Emission <- IES Texture) has radiant intensity
I(d) = rgb_power x table(d) W/sr per channel (:meth:`Photometry.lookup` of a light's table
(:meth:`Photometry.light_table`): Cycles' IES lookup, Catmull-Rom
on table indices, 0 outside the table) and E = I cos / r^2 (a delta position).

Flux comes from ONE integration, :func:`table_flux`, which every caller uses (the light's power, the
photometric power dialog, a file's lumens in :attr:`Photometry.lumens`): 8 x 8
Gauss-Legendre nodes per table cell over the interpolated table (a bicubic polynomial inside each cell,
so exact up to the clamp at 0), times the Jacobian of the table's direction map when the light's matrix
or Mapping is not a similarity (d omega_world = |det B| / |B u|^3 d omega_table, B = (V M^T)^-1).
Checked against closed forms: an isotropic table (4 pi I) and a cosine table (pi I_0).
"""

import math
from dataclasses import dataclass, field

import numpy as np

from ..metrics import glare as glare_math
from ..scene.geometry import unit as unit_vector
from ..scene.visibility import circumscribed_polygon
from ..units import as_finite_array, frozen_array
from .base import EmitterFlags
from .point import PointLight, delta_irradiance

__all__ = ["Photometry", "PhotometricLight", "catmull_rom_table", "integrate_cells", "table_flux", "opening_outline"]

_frozen = frozen_array
#: A photometric file's table is luminous intensity; a Blender light's is radiant intensity per watt.
LIGHT_UNIT = "W/sr per W"
UNITS = ("cd", LIGHT_UNIT)
ANGLE_TOL = 1e-4  # deg; Cycles' angle_close
_ANGLE_TOL = ANGLE_TOL


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
class Photometry:
    """An intensity table on type-C (or A/B) angles, read with Cycles' interpolation: ONE class for a
    photometric file's luminaire (``radiometry.photometry.photometric_files``: unit cd, the file's symmetry and
    metadata) and for the table a Blender IES light renders (:meth:`light_table`: Cycles' own reading
    of the light's IES text, already expanded to 0-360 deg, per watt of the light's ``rgb_power``,
    with the node tree's direction map and colour). Both share the interpolation
    (:func:`catmull_rom_table`) and the flux integration (:func:`table_flux`).

    Reading the table: :meth:`candela_at` (angles; a reader's convention at the last vertical angle:
    the table's value there) and :meth:`lookup` (directions in the light's frame, as Cycles' kernel:
    0 at the last vertical angle, the stored angles as they are). Flux: :attr:`lumens` (a file's
    distribution expanded by its symmetry, lm) and :meth:`flux_per_unit` (the stored table over world
    directions for a light's object matrix, in ``unit`` x sr).

    Attributes
    ----------
    vertical_angles_deg : (n_v,) ascending, deg (type C: 0 = nadir, along the table frame's -Z)
    horizontal_angles_deg : (n_h,) ascending, deg, as stored (C-planes; 0-360 for a light's table)
    candela : (n_h, n_v) the table, in ``unit``: a file's luminous intensity in cd (multiplier and
        ballast factor applied; EULUMDAT: cd/klm times lamp flux / 1000), or a light's radiant
        intensity per watt of rgb_power (W/sr per W: Cycles' IES texture value / (4 pi))
    symmetry : {'axial', 'quadrilateral', 'bilateral', 'bilateral-90-270', 'none'}
    photometric_type : {'C', 'B', 'A'}
    rated_lumens : float or None
        Rated lamp flux from the header (number of lamps x lumens per lamp), None for absolute
        photometry.
    file_format : str, e.g. 'LM-63-2002', 'EULUMDAT'
    metadata : dict of str (manufacturer, catalogue number, luminaire, lamp, ... as in the file)
    tilt : Tilt or None
    input_watts : float or None
    source : str, the file path (or '<text>')
    unit : {'cd', 'W/sr per W'}
    vector_map : (3, 3) a light's Mapping node (identity without one): the table frame is
        ``vector_map @ matrix.T @ d`` for a world direction d (Cycles: Geometry Incoming, the
        world-to-object normal transform, then the Mapping)
    rgb_scale : (3,) a light's Emission colour x Emission strength x IES strength, folded into
        rgb_power by :func:`.cycles_light.from_blender_values`
    label : str, where a light's table came from (shown in notes)
    luminous_opening : (width, length, height) m or None
        A light's luminous opening as its photometric file gives it (LM-63 / EULUMDAT, read by the
        capture layer with ``radiometry.metrics.glare.luminous_opening_m``; width < 0: a circle), None
        when the file gives none or was not read.
    opening_read : bool, whether the capture read the light's photometric file for its opening
    """

    vertical_angles_deg: np.ndarray
    horizontal_angles_deg: np.ndarray
    candela: np.ndarray
    symmetry: str
    photometric_type: str = "C"
    rated_lumens: float = None
    file_format: str = ""
    metadata: dict = field(default_factory=dict)
    tilt: object = None  # photometric_files.Tilt
    input_watts: float = None
    source: str = "<text>"
    unit: str = "cd"
    vector_map: np.ndarray = field(default_factory=lambda: np.eye(3))
    rgb_scale: np.ndarray = field(default_factory=lambda: np.ones(3))
    label: str = "IES"
    luminous_opening: tuple = None
    opening_read: bool = False

    def __post_init__(self):
        object.__setattr__(self, "vertical_angles_deg", _frozen(self.vertical_angles_deg))
        object.__setattr__(self, "horizontal_angles_deg", _frozen(self.horizontal_angles_deg))
        cd = _frozen(self.candela)
        if cd.shape != (self.horizontal_angles_deg.size, self.vertical_angles_deg.size):
            raise ValueError(f"candela must have shape (n_h, n_v) = ({self.horizontal_angles_deg.size}, "
                             f"{self.vertical_angles_deg.size}), got {cd.shape}")
        if self.unit not in UNITS:
            raise ValueError(f"unit must be one of {', '.join(UNITS)}, got {self.unit!r}")
        vmap = as_finite_array(self.vector_map, "vector_map", (3, 3))
        if abs(np.linalg.det(vmap)) < 1e-12:
            raise ValueError("the table's vector_map is singular")
        object.__setattr__(self, "candela", cd)
        object.__setattr__(self, "metadata", dict(self.metadata))
        object.__setattr__(self, "vector_map", _frozen(vmap))
        object.__setattr__(self, "rgb_scale", _frozen(as_finite_array(self.rgb_scale, "rgb_scale", (3,))))

    @classmethod
    def light_table(cls, h_deg, v_deg, values, vector_map=None, rgb_scale=(1.0, 1.0, 1.0), label="IES", *,
                    luminous_opening=None, opening_read=False):
        """The table a Blender IES light renders: ``values`` (n_h, n_v) W/sr per W of rgb_power at C angles
        ``h_deg`` (0-360 for a wrapping table) and vertical angles ``v_deg``, used as stored (Cycles'
        expansion already done, e.g. by ``photometric_files.cycles_ies_table``); ``luminous_opening`` and
        ``opening_read`` as the class's attributes."""
        h = as_finite_array(h_deg, "h_deg")
        v = as_finite_array(v_deg, "v_deg")
        values = as_finite_array(values, "values")
        if h.ndim != 1 or v.ndim != 1 or h.size < 2 or v.size < 2 or values.shape != (h.size, v.size):
            raise ValueError("a light's table needs h_deg (n_h >= 2), v_deg (n_v >= 2) and values (n_h, n_v)")
        if np.any(np.diff(h) <= 0.0) or np.any(np.diff(v) <= 0.0):
            raise ValueError("a light's table angles must increase")
        if np.any(values < 0.0):
            raise ValueError("a light's table values must be >= 0")
        return cls(vertical_angles_deg=v, horizontal_angles_deg=h, candela=values, symmetry="none",
                   unit=LIGHT_UNIT, vector_map=np.eye(3) if vector_map is None else vector_map,
                   rgb_scale=rgb_scale, label=label, source=label,
                   luminous_opening=None if luminous_opening is None else tuple(map(float, luminous_opening)),
                   opening_read=bool(opening_read))

    # --- as a light renders it: directions in the light's frame, the stored table ----------------------
    def lookup(self, local):
        """Table value (``unit``) for directions ``local`` = matrix.T @ d (..., 3), before the Mapping,
        with Cycles' IES lookup on the stored angles (0 outside them and at the last vertical angle)."""
        u = unit_vector(np.asarray(local, dtype=np.float64) @ self.vector_map.T)
        v = np.degrees(np.arccos(np.clip(-u[..., 2], -1.0, 1.0)))
        h = np.degrees(np.arctan2(u[..., 0], u[..., 1]) + np.pi)
        H = self.horizontal_angles_deg
        if H[0] == 0.0 and abs(H[-1] - 360.0) < 1e-4:
            # Cycles returns 0 at exactly h = 360 deg (h >= last angle), a single direction where
            # its rendered patch still sees the neighbouring values: read it as 0 deg instead.
            h = np.where(h >= H[-1], 0.0, h)
        return catmull_rom_table(H, self.vertical_angles_deg, self.candela, h, v)

    def flux_per_unit(self, matrix=np.eye(3)):
        """Integral of the stored table over world directions for a light whose object matrix is
        ``matrix`` (:func:`table_flux`): W per W of rgb_power for a light's table, lm for cd."""
        a = self.vector_map @ np.asarray(matrix, float).T
        q = a / np.cbrt(abs(np.linalg.det(a)))
        similarity = np.allclose(q @ q.T, np.eye(3), atol=1e-9)
        return table_flux(self.horizontal_angles_deg, self.vertical_angles_deg, self.candela,
                          None if similarity else a)

    # --- the full type-C table ----------------------------------------------------------------
    def full_table(self):
        """(h_deg, v_deg, cd) with h from 0 to 360 deg inclusive, expanded by the file's symmetry."""
        if self.photometric_type != "C":
            raise ValueError(f"type {self.photometric_type} photometry has no type-C table "
                             "(its polar axis is horizontal); only type C can be expanded")
        h, cd = self.horizontal_angles_deg, self.candela
        if self.symmetry == "axial":
            return np.array([0.0, 360.0]), self.vertical_angles_deg.copy(), np.vstack([cd[0], cd[0]])
        if self.symmetry == "quadrilateral":
            h = np.concatenate([h, 180.0 - h[-2::-1]])
            cd = np.vstack([cd, cd[-2::-1]])
        if self.symmetry in ("quadrilateral", "bilateral"):
            h = np.concatenate([h, 360.0 - h[-2::-1]])
            cd = np.vstack([cd, cd[-2::-1]])
        elif self.symmetry == "bilateral-90-270":
            # stored 90..270; I(C) = I(180 - C): 0..90 from 180..90, 270..360 from 270..180.
            low = h <= 180.0 + _ANGLE_TOL
            high = h >= 180.0 - _ANGLE_TOL
            h0 = 180.0 - h[low][::-1]
            cd0 = cd[low][::-1]
            h2 = 540.0 - h[high][::-1]
            cd2 = cd[high][::-1]
            h = np.concatenate([h0[:-1], h, h2[1:]])
            cd = np.vstack([cd0[:-1], cd, cd2[1:]])
        if abs(h[-1] - 360.0) > _ANGLE_TOL:  # 'none' without the closing plane
            h = np.concatenate([h, [360.0]])
            cd = np.vstack([cd, cd[:1]])
        return h, self.vertical_angles_deg.copy(), cd

    def candela_at(self, vertical_deg, horizontal_deg):
        """Luminous intensity (cd) in a direction, vectorised (broadcasting) over both angles.

        ``vertical_deg`` 0 = nadir, 180 = zenith; ``horizontal_deg`` is the C angle (any value,
        wrapped to [0, 360)). Interpolation: Cycles' (see the module docstring). NaN gives NaN.
        """
        h_full, v_full, table = self.full_table()
        v = np.asarray(vertical_deg, dtype=np.float64)
        h = np.mod(np.asarray(horizontal_deg, dtype=np.float64), 360.0)
        out = catmull_rom_table(h_full, v_full, table, h, v)
        # At the table's last vertical angle (usually 180 deg) Cycles' lookup gives 0 (its cells are
        # half-open: the meter's light model keeps that, it is what renders); the READER answers
        # the table's own value there, interpolated along C only (a column repeated past the end).
        at_end = np.broadcast_to(v == v_full[-1], np.broadcast_shapes(v.shape, h.shape))
        if np.any(at_end):
            v_ext = np.append(v_full, v_full[-1] + 1.0)
            t_ext = np.hstack([table, table[:, -1:]])
            end = catmull_rom_table(h_full, v_ext, t_ext, h, np.full(np.shape(v), v_full[-1]))
            out = np.where(at_end, end, out)
        return out[()] if np.ndim(out) == 0 else out

    # --- derived quantities ----------------------------------------------------------------------
    @property
    def max_candela(self):
        return float(np.max(self.candela))

    @property
    def lumens(self):
        """Luminous flux (lm) of the interpolated distribution over the whole sphere (a table in cd)."""
        if self.unit != "cd":
            raise ValueError(f"a table in {self.unit} has no lumens: use flux_per_unit")
        if self.photometric_type == "C":
            h_full, v_full, table = self.full_table()
            return table_flux(h_full, v_full, table)
        return _lumens_type_ab(self)

    @property
    def candela_per_klm(self):
        """(n_h, n_v) cd per 1000 lm of rated lamp flux; None for absolute photometry."""
        if not self.rated_lumens:
            return None
        return self.candela * (1000.0 / self.rated_lumens)

    def _spread_angle(self, fraction):
        """Full angle (deg) of the cone about the nadir in which the intensity stays above
        ``fraction`` of the maximum, per C-plane pair C0-C180 and C90-C270, averaged (type C);
        found on the interpolated distribution at 0.01 deg."""
        if self.photometric_type != "C":
            return None
        peak = self.max_candela
        if peak <= 0.0:
            return 0.0
        v = np.arange(0.0, 180.0 + 1e-9, 0.01)
        widths = []
        for c in (0.0, 90.0):
            halves = []
            for side in (c, c + 180.0):
                values = self.candela_at(v, side)
                # first angle where it drops below, going out from the nadir (linear in between)
                below = np.nonzero(values < fraction * peak)[0]
                if not below.size:
                    halves.append(180.0)
                elif below[0] == 0:
                    halves.append(0.0)
                else:
                    k = below[0]
                    f0, f1 = values[k - 1], values[k]
                    halves.append(v[k - 1] + 0.01 * (f0 - fraction * peak) / (f0 - f1))
            widths.append(sum(halves))
        return float(np.mean(widths))

    @property
    def beam_angle_deg(self):
        """Full angle where the intensity is >= 50 % of the maximum (IES beam angle), deg;
        mean of the C0-C180 and C90-C270 planes, each measured outward from the nadir."""
        return self._spread_angle(0.5)

    @property
    def field_angle_deg(self):
        """As :attr:`beam_angle_deg` at 10 % of the maximum (field angle), deg."""
        return self._spread_angle(0.1)

    def summary(self):
        """JSON-serialisable dict of the numbers a catalogue prints."""
        md = self.metadata
        return {
            "source": self.source, "format": self.file_format, "photometric_type": self.photometric_type,
            "symmetry": self.symmetry,
            "manufacturer": md.get("MANUFAC") or md.get("company"),
            "luminaire": md.get("LUMINAIRE") or md.get("luminaire_name"),
            "catalogue_number": md.get("LUMCAT") or md.get("luminaire_number"),
            "lumens": self.lumens, "rated_lumens": self.rated_lumens,
            "light_output_ratio": (self.lumens / self.rated_lumens) if self.rated_lumens else None,
            "max_candela": self.max_candela, "beam_angle_deg": self.beam_angle_deg,
            "field_angle_deg": self.field_angle_deg,
            "n_vertical": int(self.vertical_angles_deg.size), "n_horizontal": int(self.horizontal_angles_deg.size),
            "input_watts": self.input_watts,
            "tilt": None if self.tilt is None else self.tilt.source,
        }



# --- flux of type A/B tables ----------------------------------------------------------------------

def _lumens_type_ab(p):
    """Flux of a type A/B table: angles (H lateral, V elevation) about a horizontal polar axis,
    d omega = cos V dV dH; a 0-90 range stands for its mirror image too."""
    H, V, T = p.horizontal_angles_deg, p.vertical_angles_deg, p.candela
    factor = 1.0
    if abs(H[0]) < _ANGLE_TOL and H.size > 1:
        factor *= 2.0
    if abs(V[0]) < _ANGLE_TOL and V.size > 1:
        factor *= 2.0
    if H.size == 1:
        raise ValueError("a type A/B table needs at least two horizontal angles")
    return factor * integrate_cells(lambda hh, vv: catmull_rom_table(H, V, T, hh, vv),
                                     H, V, lambda v: np.cos(np.radians(v)))


@dataclass(frozen=True)
class PhotometricLight(PointLight, kind_key=("POINT", True)):
    """A photometric point light of radius 0 (see the module docstring)."""

    def _check_kind(self):
        if self.kind != "POINT" or self.radius != 0.0:
            raise ValueError("an intensity table is modelled for a point light of radius 0 only "
                             f"(got {self.kind.lower()} of radius {self.radius:g} m)")
        if not isinstance(self.intensity_table, Photometry) or self.intensity_table.unit != LIGHT_UNIT:
            raise ValueError("intensity_table must be a light's Photometry (Photometry.light_table)")

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

    def _seen_from(self, d, dist, eye, efficacy, weights, sides):
        # CIE 117: luminance = I / projected area of the file's flat luminous opening, solid angle = that
        # area / d².
        table = self.intensity_table
        if not table.opening_read:
            return None, "photometric light whose file is not at hand: no luminous area to rate"
        opening = table.luminous_opening
        if opening is None:
            return None, "its photometric file gives no luminous opening (a point source): no luminance to rate"
        gamma = math.degrees(math.acos(float(np.clip(d @ self.emission_direction, -1.0, 1.0))))
        projected = glare_math.projected_opening_area(*opening, gamma)
        if projected is None:
            return None, "a luminous opening with height or of another shape: not modelled (flat ones only)"
        if projected <= 0:
            return None, "seen from above its luminous opening"
        intensity = float(self.intensity_towards(d) @ weights) * efficacy
        return (intensity / projected, projected / dist**2, np.asarray(self.position, float),
                opening_outline(self.axes, self.position, opening, sides)), None

    def exactness(self):
        return True, "photometric point", (f"{self.intensity_table.label}: I(theta, C) cos / r^2 with Cycles' IES "
                                           "interpolation, exact" + self._sign_note())


def opening_outline(axes, position, opening, sides):
    """World vertices (K, 3) m of a flat luminous opening (width, length, height) m at a light's photometric
    centre ``position`` (3,) m, facing its emission direction (``axes`` (3, 3), columns local x, y, z):
    LM-63 / EULUMDAT give the length along the C0-C180 axis (local +X) and the width along C90-C270 (local
    +Y); a circle (negative width) as a circumscribed ``sides``-gon."""
    width, length, _height = opening
    x, y = (np.asarray(axes, float)[:, k] for k in (0, 1))
    centre = np.asarray(position, float)
    if width < 0:
        return circumscribed_polygon(centre, np.cross(x, y), abs(width) / 2, sides)
    corners = np.array([[-.5, -.5], [.5, -.5], [.5, .5], [-.5, .5]])
    return centre + corners[:, :1] * length * x + corners[:, 1:] * width * y
