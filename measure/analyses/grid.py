"""Illuminance on a work-plane grid (host side): cell centres on a plane object's local XY, one
batch through ``meter.measure_illuminance`` (one scene sync; each point gets the samples its own
target error needs), statistics from ``radiometry.metrics.grid``, CSV and an isolux PNG, and a
viewport-only coloured copy of the plane. :func:`spectral_grid`: melanopic EDI (CIE S 026) on the same grid,
each point read as ``meter.spectral_reflected`` reads a meter (the band renders in one batch).

Units: lux, W/m^2, m; points in scene coordinates (Blender units).
"""

import csv
import dataclasses
import math
import time
import typing

import bpy
import numpy as np

from ... import plots as _plots
from ...errors import MeasurementCancelled, RadiometerError
from ...readings import batch_method
from ...radiometry.metrics import grid as grid_math
from . import analysis_common as common

#: Lift of the viewport-only isolux copy above its plane (scene units), so it is not hidden in it.
DISPLAY_OFFSET = 1e-4


@dataclasses.dataclass
class GridResult(common.ToDict):
    """Illuminance on a work-plane grid. lux (ny, nx); points (ny, nx, 3) scene coordinates."""

    target: str
    nx: int
    ny: int
    spacing: tuple             #: (dx, dy) cell size, m
    size: tuple                #: (width, depth) of the plane, m
    lux: np.ndarray            #: (ny, nx) illuminance, lx
    irradiance: np.ndarray     #: (ny, nx) W/m^2
    rel_std_error: np.ndarray  #: (ny, nx)
    points: np.ndarray         #: (ny, nx, 3) scene coordinates
    local_extent: tuple        #: (x0, x1, y0, y1) in the plane's local coordinates (scene units)
    normal: tuple
    stats: dict                #: avg, min, max, u0 (lux; u0 dimensionless), count
    method: str
    exact: bool
    seconds: float
    notes: list
    spacing_rule: str = ""
    image: str = ""
    csv: str = ""
    target_rel_error: float = None  #: the 1-sigma relative error asked of every point (None: fixed samples)
    max_rel_std_error: float = 0.0  #: the largest relative standard error reached over the grid
    matrix_world: list = None  #: the plane's 4 x 4 world matrix (scene units), for the plot's frame
    local_z: float = 0.0       #: the plane's local z of the grid (scene units)
    scale_length: float = 1.0  #: metres per scene unit

    def write_csv(self, path):
        """x, y, z (scene coordinates), lux, W/m^2 and relative s.e. per point, row by row."""
        from ...outputs import atomic_output

        with atomic_output(path) as tmp, open(tmp, "w", newline="", encoding="utf-8") as f:
            w = csv.writer(f)
            w.writerow(["row", "col", "x", "y", "z", "illuminance_lx", "irradiance_W_m2", "rel_std_error"])
            for j in range(self.ny):
                for i in range(self.nx):
                    x, y, z = self.points[j, i]
                    w.writerow([j, i, f"{x:.6g}", f"{y:.6g}", f"{z:.6g}", f"{self.lux[j, i]:.6g}",
                                f"{self.irradiance[j, i]:.6g}", f"{self.rel_std_error[j, i]:.3g}"])
        self.csv = path
        return path

    def plot_frame(self):
        """(origin, axis_u, axis_v, axis_labels) of the isolux plot, in metres.

        A horizontal plane (normal within 0.1 deg of +-Z) is drawn in scene X/Y (m), as the CSV's x, y
        columns times the unit scale: a rotated plane appears rotated in the room. Any other plane
        (a wall) is drawn in its own metric axes from its local corner (x0, y0).
        """
        mw = np.asarray(self.matrix_world, float)
        x0, x1, y0, y1 = self.local_extent
        zc = self.local_z
        corner = (mw @ np.array([x0, y0, zc, 1.0]))[:3]
        ex = mw[:3, 0] * (x1 - x0)
        ey = mw[:3, 1] * (y1 - y0)
        s = self.scale_length
        if abs(self.normal[2]) > math.cos(math.radians(0.1)):
            return corner[:2] * s, ex[:2] * s, ey[:2] * s, ("scene x (m)", "scene y (m)")
        return (np.zeros(2), np.array([np.linalg.norm(ex) * s, 0.0]), np.array([0.0, np.linalg.norm(ey) * s]),
                ("along the plane's local X (m)", "along the plane's local Y (m)"))

    def write_png(self, path, *, outline=None, mark_points=False):
        """The isolux PNG in metres (:meth:`plot_frame`); ``outline``: the room's (N, 2) polygon in
        the same coordinates, when known."""
        from ...plots.isolux import isolux_png

        origin, u, v, labels = self.plot_frame()
        isolux_png(path, self.lux, origin, u, v, title=f"Isolux: {self.target} ({self.nx} x {self.ny} points, "
                   f"{self.size[0]:.3g} m x {self.size[1]:.3g} m)", stats=self.stats, axis_labels=labels,
                   outline=outline, mark_points=mark_points)
        self.image = path
        return path


def work_planes(scene):
    """The scene's work planes: mesh objects whose name contains "work plane" (any case) or that carry
    the custom property ``radiometer_work_plane`` (what the report, the client report and ``grid --all``
    measure)."""
    return [ob for ob in scene.objects if ob.type == "MESH"
            and ("work plane" in ob.name.lower() or bool(ob.get("radiometer_work_plane", False)))]


def plane_frame(obj, scene):
    """(local extent x0, x1, y0, y1, z) in scene units, matrix_world as numpy 4x4, normal."""
    if obj.type != "MESH":
        raise RadiometerError(f"{obj.name!r} is not a mesh plane (it is a {obj.type}): pick a plane object")
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        n = len(mesh.vertices)
        if n == 0:
            raise RadiometerError(f"plane {obj.name!r} has no vertices (empty mesh): give it a face")
        co = np.empty(n * 3)
        mesh.vertices.foreach_get("co", co)
        co = co.reshape(n, 3)
    finally:
        evaluated.to_mesh_clear()
    mw = np.array(evaluated.matrix_world, float)
    x0, y0, z0 = co.min(axis=0)
    x1, y1, z1 = co.max(axis=0)
    sx = (x1 - x0) * np.linalg.norm(mw[:3, 0])
    sy = (y1 - y0) * np.linalg.norm(mw[:3, 1])
    if not (sx > 0 and sy > 0):
        raise RadiometerError(f"plane {obj.name!r} has no area in its local XY (size {sx:.3g} x {sy:.3g}): "
                              "give it a face in its local XY plane")
    normal = np.linalg.inv(mw[:3, :3]).T @ np.array([0.0, 0.0, 1.0])
    normal /= np.linalg.norm(normal)
    return (x0, x1, y0, y1, 0.5 * (z0 + z1)), mw, normal


class GridLayout(typing.NamedTuple):
    """Where a plane's grid points lie: ``points`` (ny, nx, 3) scene coordinates at the cell centres."""

    obj: object
    nx: int
    ny: int
    points: np.ndarray
    normal: np.ndarray
    local_extent: tuple
    local_z: float
    matrix_world: np.ndarray
    size_x: float  # m
    size_y: float  # m
    scale_length: float
    spacing_rule: str


def grid_layout(request, target, resolution=None, spacing=None):
    """The cell centres of ``target``'s grid (a mesh object or its name) for a ``resolution`` (nx, ny),
    a ``spacing`` (m) or, with neither, the EN 12464-1 spacing: the one layout every grid uses. The request
    (``measure.blender.request``) gives the scene and its unit scale."""
    scene = request.scene
    obj = scene.objects.get(target) if isinstance(target, str) else target
    if obj is None:
        raise RadiometerError(f"no object named {target!r} in scene {scene.name!r}")
    (x0, x1, y0, y1, zc), mw, normal = plane_frame(obj, scene)
    scale = request.scale_length
    size_x = (x1 - x0) * np.linalg.norm(mw[:3, 0]) * scale
    size_y = (y1 - y0) * np.linalg.norm(mw[:3, 1]) * scale
    if resolution is not None and spacing is not None:
        raise RadiometerError("give a resolution or a spacing, not both")
    rule = ""
    if resolution is not None:
        try:
            nx, ny = (int(v) for v in resolution)
        except (TypeError, ValueError):
            raise RadiometerError(f"resolution must be two integers (nx, ny), got {resolution!r}") from None
        if nx < 1 or ny < 1:
            raise RadiometerError(f"resolution must be at least 1 x 1 points, got {nx} x {ny}")
    else:
        if spacing is not None and not (float(spacing) > 0 and math.isfinite(float(spacing))):
            raise RadiometerError(f"spacing must be > 0 m, got {spacing}")
        if spacing is None:
            p = float(grid_math.en12464_spacing(max(size_x, size_y)))
            rule = f"EN 12464-1: p = 0.2 x 5^log10({max(size_x, size_y):.3g} m) = {p:.3g} m"
        else:
            p = float(spacing)
        nx, ny = grid_math.grid_counts(size_x, size_y, p)
    if nx * ny > 250_000:
        raise RadiometerError(f"{nx} x {ny} points is too many for one measurement: use a coarser grid")
    local = grid_math.cell_centres((x0, x1), (y0, y1), nx, ny)
    local3 = np.concatenate([local, np.full(local.shape[:2] + (1,), zc), np.ones(local.shape[:2] + (1,))], axis=-1)
    return GridLayout(obj, nx, ny, (local3 @ mw.T)[..., :3], normal, (x0, x1, y0, y1), zc, mw, size_x, size_y,
                      scale, rule)


def illuminance_grid(target, *, request, resolution=None, spacing=None, method="auto", png=None, csv_path=None):
    """Illuminance at the cell centres of a grid on a plane object's local XY (its +Z side).

    ``target``: a mesh object or its name. ``resolution``: (nx, ny); ``spacing``: cell size in m;
    neither: the EN 12464-1 spacing p = 0.2 x 5^log10(d). The request (``measure.blender.request``): the
    scene, ``quality`` / ``target_rel_error`` (fraction, every point) / ``samples`` (per point) /
    ``time_budget_s`` (s, the whole grid) as in ``meter.measure_illuminance``, ``target_abs_error`` (the
    absolute error floor, lux; None: the preset's), the seed, progress and cancel. Returns :class:`GridResult`.
    """
    layout = grid_layout(request, target, resolution, spacing)
    obj, nx, ny, points, normal = layout.obj, layout.nx, layout.ny, layout.points, layout.normal
    (x0, x1, y0, y1), zc, mw = layout.local_extent, layout.local_z, layout.matrix_world
    size_x, size_y, scale, rule = layout.size_x, layout.size_y, layout.scale_length, layout.spacing_rule
    started = time.perf_counter()
    readings = common.measure(request, points.reshape(-1, 3), normal, method=method)
    seconds = time.perf_counter() - started
    irr = np.array([r.irradiance for r in readings]).reshape(ny, nx)
    lux = np.array([r.illuminance for r in readings]).reshape(ny, nx)
    se = np.array([r.rel_std_error for r in readings]).reshape(ny, nx)
    notes = [f"{nx} x {ny} points at cell centres on the plane (each sensor raised by a scale-aware epsilon "
             "along the normal when a surface is there: see the readings' notes)"]
    if obj.hide_render:
        notes.append("the plane is hidden in renders: an imaginary work plane that neither blocks nor reflects")
    notes += readings[0].notes
    result = GridResult(
        target=obj.name, nx=nx, ny=ny, spacing=(size_x / nx, size_y / ny), size=(size_x, size_y), lux=lux,
        irradiance=irr, rel_std_error=se, points=points, local_extent=(x0, x1, y0, y1),
        normal=tuple(normal.tolist()), stats=grid_math.grid_stats(lux), method=batch_method(readings),
        exact=all(r.exact for r in readings), seconds=seconds, notes=notes, spacing_rule=rule,
        target_rel_error=readings[0].target_rel_error, max_rel_std_error=float(np.max(se)),
        matrix_world=mw.tolist(), local_z=float(zc), scale_length=float(scale))
    if png and common.can_plot(result.notes):
        result.write_png(png)
    if csv_path:
        result.write_csv(csv_path)
    return result


def colour_plane(result, scene=None, name=None):
    """A viewport-only copy of the grid as coloured quads (colour attribute 'lux_colour').

    Creates (or replaces) an object named ``Isolux <plane>`` hidden in renders; set the viewport's
    Solid shading colour to Attribute to see it. Returns the object.
    """
    from mathutils import Vector

    matplotlib = _plots.require_matplotlib()  # RadiometerError in Blender's own Python

    scene = common.scene_or_context(scene)
    name = name or f"Isolux {result.target}"
    old = bpy.data.objects.get(name)
    if old is not None:
        mesh_old = old.data
        bpy.data.objects.remove(old, do_unlink=True)
        if mesh_old is not None and mesh_old.users == 0:
            bpy.data.meshes.remove(mesh_old)
    obj_plane = scene.objects.get(result.target)
    (x0, x1, y0, y1, zc), mw, normal = plane_frame(obj_plane, scene)
    ny, nx = result.lux.shape
    xs, ys = np.linspace(x0, x1, nx + 1), np.linspace(y0, y1, ny + 1)
    verts, faces, colours = [], [], []
    lo, hi = float(result.lux.min()), float(result.lux.max())
    cmap = matplotlib.colormaps["inferno"]
    for j in range(ny):
        for i in range(nx):
            base = len(verts)
            verts += [(xs[i], ys[j], zc), (xs[i + 1], ys[j], zc), (xs[i + 1], ys[j + 1], zc), (xs[i], ys[j + 1], zc)]
            faces.append((base, base + 1, base + 2, base + 3))
            c = cmap((result.lux[j, i] - lo) / (hi - lo) if hi > lo else 0.5)
            colours += [c] * 4
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    attr = mesh.color_attributes.new("lux_colour", "FLOAT_COLOR", "CORNER")
    attr.data.foreach_set("color", np.array(colours, np.float32).ravel())
    obj = bpy.data.objects.new(name, mesh)
    obj.matrix_world = obj_plane.matrix_world.copy()
    obj.location = obj_plane.matrix_world.translation + DISPLAY_OFFSET * Vector(normal)
    obj.hide_render = True
    scene.collection.objects.link(obj)
    return obj


# -- False-colour overlay helpers (viewport legend and the toggle operator) ------------------------------

#: inferno at t = 0, 1/8, ..., 1 (matplotlib's values), for the legend when matplotlib is missing.
_INFERNO = np.array([(0.001462, 0.000466, 0.013866), (0.129285, 0.047293, 0.290788), (0.3415, 0.062325, 0.429425),
                     (0.54092, 0.134729, 0.415123), (0.735683, 0.215906, 0.330245), (0.894305, 0.353399, 0.193584),
                     (0.978422, 0.557937, 0.034931), (0.974638, 0.797692, 0.206332), (0.988362, 0.998364, 0.644924)])


def false_colour(t):
    """RGBA of the grid's colour map ('inferno', as :func:`colour_plane`) at t in [0, 1]."""
    t = min(1.0, max(0.0, float(t))) if math.isfinite(t) else 0.0
    try:
        import matplotlib

        return tuple(float(c) for c in matplotlib.colormaps["inferno"](t))
    except ImportError:
        pts = np.linspace(0.0, 1.0, len(_INFERNO))
        return tuple(float(np.interp(t, pts, _INFERNO[:, k])) for k in range(3)) + (1.0,)


def lux_from_csv(path):
    """The (ny, nx) illuminance array of a grid CSV written by :meth:`GridResult.write_csv`."""
    cells = {}
    with open(path, newline="", encoding="utf-8") as f:
        for row in csv.DictReader(f):
            cells[int(row["row"]), int(row["col"])] = float(row["illuminance_lx"])
    if not cells:
        raise RadiometerError(f"{path}: no grid points")
    ny, nx = max(j for j, _ in cells) + 1, max(i for _, i in cells) + 1
    lux = np.full((ny, nx), np.nan)
    for (j, i), v in cells.items():
        lux[j, i] = v
    return lux


# --- melanopic EDI on the same grid (issue 35) ---------------------------------------------------------

def spectral_grid(target, *, request, resolution=None, spacing=None, reflected=False):
    """A dict: ``mel_edi_lx`` and ``illuminance_lx`` (ny, nx), ``low_95_lx`` / ``high_95_lx`` of mel-EDI with
    ``reflected``, ``mel_der`` (ny, nx), ``points`` (N, 3) scene coordinates, ``normal``, ``stats`` (avg, min,
    max, u0 = min/avg, count of each: ``grid_math.grid_stats``), ``exact`` (every point's every part proven), ``lower_bound`` (some light is
    left out somewhere: the values are then lower bounds), ``not_included``, ``notes``, ``units``, ``seconds``.
    The request gives the scene, the band renders' quality and seed, progress and cancel."""
    from ..meter import spectra, spectral_reflected

    start = time.perf_counter()
    progress, cancelled = request.progress, request.cancelled
    layout = grid_layout(request, target, resolution=resolution, spacing=spacing)
    points = layout.points.reshape(-1, 3)
    shape = layout.points.shape[:2]
    normals = np.broadcast_to(np.asarray(layout.normal, float), points.shape)
    if reflected:
        readings = spectral_reflected.spectral_readings(points, normals, request=request)
    else:
        readings = []
        for k, (p, n) in enumerate(zip(points, normals)):
            if cancelled is not None and cancelled():
                raise MeasurementCancelled("cancelled: the melanopic grid stopped; nothing was changed")
            readings.append(spectra.spectral_reading(tuple(p), tuple(n), request=request))
            if progress is not None and (k + 1) % 16 == 0:
                spent = time.perf_counter() - start
                progress(k + 1, len(points), spent / (k + 1) * (len(points) - k - 1))
    mel = np.array([r["mel_edi_lx"] for r in readings], float)
    ev = np.array([r["illuminance_lx"] for r in readings], float)
    with np.errstate(divide="ignore", invalid="ignore"):
        der = np.where(ev > 0, mel / np.where(ev > 0, ev, 1.0), np.nan)
    out = {
        "quantity": "melanopic EDI (CIE S 026/E:2018) on a plane, lx", "target": getattr(target, "name", target),
        "part": readings[0]["part"], "nx": int(shape[1]), "ny": int(shape[0]),
        "points": points.tolist(), "normal": tuple(map(float, layout.normal)),
        "mel_edi_lx": mel.reshape(shape).tolist(), "illuminance_lx": ev.reshape(shape).tolist(),
        "mel_der": [[None if not np.isfinite(x) else float(x) for x in row] for row in der.reshape(shape)],
        "stats": {"mel_edi_lx": grid_math.grid_stats(mel), "illuminance_lx": grid_math.grid_stats(ev)},
        "exact": all(bool(r["exact"]) and not r["not_included"] for r in readings),
        "lower_bound": any(r["not_included"] or not r["complete"] for r in readings),
        "not_included": sorted({x for r in readings for x in r["not_included"]}),
        "notes": list(dict.fromkeys(n for r in readings for n in r["notes"])),
        "units": {"mel_edi_lx": "lx", "illuminance_lx": "lx", "low_95_lx": "lx", "high_95_lx": "lx", "mel_der": "1",
                  "points": "scene units", "seconds": "s"},
    }
    if readings[0]["part"] == "direct+reflected":
        lo = np.array([r["interval_95"]["mel_edi_lx"]["low_95"] for r in readings], float)
        hi = np.array([r["interval_95"]["mel_edi_lx"]["high_95"] for r in readings], float)
        out["low_95_lx"], out["high_95_lx"] = lo.reshape(shape).tolist(), hi.reshape(shape).tolist()
        # the plane's mean: the mean of the points' interval ends (errors added linearly: conservative)
        out["stats"]["mel_edi_lx"]["avg_interval_95"] = (float(lo.mean()), float(hi.mean()))
    out["alpha_opic_edi_avg_lx"] = {a: float(np.mean([r["alpha_opic_edi_lx"][a] for r in readings]))
                                    for a in readings[0]["alpha_opic_edi_lx"]}
    out["seconds"] = time.perf_counter() - start
    return out


def write_spectral_csv(result, path):
    """A melanopic grid (:func:`spectral_grid`'s dict) as CSV, row by row: x, y, z (scene coordinates), E_v and
    mel-EDI (lx), mel-DER, and the 95 % interval of mel-EDI where the reflected part was read; whole or not at all."""
    from ...outputs import atomic_output

    nx = result["nx"]
    cols = ["row", "col", "x", "y", "z", "illuminance_lx", "mel_edi_lx", "mel_der"]
    interval = "low_95_lx" in result
    with atomic_output(path) as tmp, open(tmp, "w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(cols + (["mel_edi_low_95_lx", "mel_edi_high_95_lx"] if interval else []))
        for k, (x, y, z) in enumerate(result["points"]):
            j, i = divmod(k, nx)
            der = result["mel_der"][j][i]
            row = [j, i, f"{x:.6g}", f"{y:.6g}", f"{z:.6g}", f"{result['illuminance_lx'][j][i]:.6g}",
                   f"{result['mel_edi_lx'][j][i]:.6g}", "" if der is None else f"{der:.6g}"]
            if interval:
                row += [f"{result['low_95_lx'][j][i]:.6g}", f"{result['high_95_lx'][j][i]:.6g}"]
            w.writerow(row)
    return path
