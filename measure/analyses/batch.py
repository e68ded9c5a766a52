"""``measure_batch``: many .blend files (design variants) x their meters, one task per file.

The task function :func:`measure_file` is importable by name, so Dask workers run it; without a
client the files are opened one after the other in this process.
"""

import dataclasses
import os

from ...cluster import engine, source
from ...errors import RadiometerError


@dataclasses.dataclass
class FileReadings:
    """The readings of one file: ``names`` (meter object names, or "point 1".. for given locations)
    and ``readings`` (IlluminanceReading / LuminanceReading / RadianceMap, SI units), in order."""

    file: str
    scene: str
    names: list
    readings: list

    def to_dict(self):
        return {"file": self.file, "scene": self.scene,
                "meters": [dict(name=n, **(r.to_dict() if hasattr(r, "to_dict") else {}))
                           for n, r in zip(self.names, self.readings)]}


def _as_points(meters):
    import numpy as np

    locations, normals = [], []
    for m in meters:
        if isinstance(m, dict):
            location, normal = m.get("location"), m.get("normal", (0.0, 0.0, 1.0))
        elif len(m) == 2 and hasattr(m[0], "__len__"):
            location, normal = m
        else:
            location, normal = m, (0.0, 0.0, 1.0)
        locations.append(location)
        normals.append(normal)
    try:
        points = np.asarray(locations, float).reshape(-1, 3)
        directions = np.asarray(normals, float).reshape(-1, 3)
    except (TypeError, ValueError):
        raise RadiometerError("meters: give meter object names, or locations (x, y, z) / "
                              "((x, y, z), (nx, ny, nz)) pairs / {'location':, 'normal':} dicts") from None
    return points, directions


def measure_file(scene, *, file="", meters=None, quality="standard", method=None, seed=0, read_meters=None):
    """Task: the readings of one opened file (worker side; ``scene`` is that file's scene).

    ``meters``: None (every light-meter object in the scene, with the scene's method), a list of
    meter object names, or illuminance meters as locations (scene coordinates) with optional
    normals (default +Z). ``seed``: first Cycles seed of located meters (deterministic readings). The
    request is built here, on the opened file's scene (its own efficacy setting, as the api reads it).
    """
    from ..blender import request as request_of
    from ..meter import meter_objects, point_meter as meter

    if meters is None or (meters and all(isinstance(m, str) for m in meters)):
        objects = None
        if meters is not None:
            missing = [name for name in meters if name not in scene.objects]
            if missing:
                raise RadiometerError(f"no object named {', '.join(repr(m) for m in missing)}")
            objects = [scene.objects[name] for name in meters]
        if read_meters is None:
            raise RadiometerError("measure_file: meter objects need read_meters (radiometer.api.scene_meters), "
                                  "which reads their settings")
        found, settings = read_meters(scene, objects)
        request = request_of.build(scene, quality=quality, target_rel_error=settings["target_rel_error"])
        pairs = meter_objects.measure_meters(found, request, method=method or settings["method"])
        return FileReadings(file, scene.name, [ob.name for ob, _ in pairs], [r for _, r in pairs])
    points, normals = _as_points(meters)
    readings = meter.measure_illuminance(points, normals, request_of.build(scene, quality=quality, seed=seed),
                                         method=method or "auto")
    return FileReadings(file, scene.name, [f"point {k + 1}" for k in range(len(points))], list(readings))


def measure_batch(files, meters=None, *, quality="standard", method=None, seed=0, client=None, progress=None,
                  cancelled=None, stats=None, shared=False, read_meters=None):
    """Readings per file, in the order of ``files``; see ``radiometer.api.measure_batch``. ``read_meters(scene,
    objects)``: (meters, settings) of the opened file's meter objects (``radiometer.api.scene_meters``, which
    reads their Radiometer properties); needed unless ``meters`` are points."""
    if isinstance(files, (str, bytes, os.PathLike)):
        files = [files]
    files = [os.fspath(f) for f in files]
    if not files:
        raise RadiometerError("measure_batch: no files given")
    for path in files:
        source.check_blend_file(path)
    from ... import quality as quality_presets

    quality_presets.preset(quality)  # an unknown preset is one line now, not one per task
    meters = None if meters is None else list(meters)
    kwargs = [dict(file=os.path.abspath(f), meters=meters, quality=quality, method=method, seed=seed,
                   read_meters=read_meters) for f in files]
    return engine.run_file_tasks([os.path.abspath(f) for f in files], measure_file, kwargs, client=client,
                                 progress=progress, cancelled=cancelled, label="batch", stats=stats, shared=shared)
