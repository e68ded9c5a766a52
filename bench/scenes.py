"""Benchmark scenes built with plain bpy (metres, unit scale 1): delta-lit, area-lit, an
interreflecting closed room, a heavy triangle mesh, and the white card + camera of the manual way.

Reference values: point light E = P cos / (4 pi r^2) (FACTS.md, measured to 1e-6); square area light
by the radiometer's closed form (Lambert's polygon formula, checked against Cycles in tests/bpy).
"""

import importlib.util
import math
import pathlib

import bpy
import numpy as np

from radiometer.demo import builders
from radiometer.demo.builders import diffuse_material


def fresh():
    """Empty factory scene with a black world; returns the scene."""
    import radiometer

    radiometer.unregister()  # no-op when not registered; registering twice would fail
    bpy.ops.wm.read_factory_settings(use_empty=True)
    radiometer.register()
    scene = bpy.context.scene
    builders.black_world(scene, "bench black")
    return scene


def light(scene, kind, location, rotation=(0.0, 0.0, 0.0), **props):
    return builders.add_light(scene, kind, location, rotation, name=f"bench {kind.lower()}", **props)


def quad_mesh(scene, name, quads, material):
    """One object from a list of quads (4 corner tuples each; winding sets the normal)."""
    verts = [v for q in quads for v in q]
    faces = [tuple(range(4 * i, 4 * i + 4)) for i in range(len(quads))]
    return builders.mesh_object(name, verts, faces, material, scene.collection)


def delta_lit(energy=100.0, height=2.0):
    """A point light of radius 0, `height` m above the origin; nothing else."""
    scene = fresh()
    light(scene, "POINT", (0.0, 0.0, height), energy=energy, shadow_soft_size=0.0)
    return scene


def area_lit(energy=40.0, size=1.0, height=1.0):
    """A square area light (side `size` m) facing down, `height` m above the origin; nothing else."""
    scene = fresh()
    light(scene, "AREA", (0.0, 0.0, height), energy=energy, shape="SQUARE", size=size)
    return scene


def room_quads(size=(4.0, 4.0, 3.0)):
    """The six walls of the closed room (floor at z=0), each quad's normal pointing into the room (m)."""
    hx, hy, h = size[0] / 2, size[1] / 2, size[2]
    return [
        [(-hx, -hy, 0), (hx, -hy, 0), (hx, hy, 0), (-hx, hy, 0)],          # floor, +Z
        [(-hx, -hy, h), (-hx, hy, h), (hx, hy, h), (hx, -hy, h)],          # ceiling, -Z
        [(-hx, -hy, 0), (-hx, hy, 0), (-hx, hy, h), (-hx, -hy, h)],        # x = -hx, +X
        [(hx, -hy, 0), (hx, -hy, h), (hx, hy, h), (hx, hy, 0)],            # x = +hx, -X
        [(-hx, -hy, 0), (-hx, -hy, h), (hx, -hy, h), (hx, -hy, 0)],        # y = -hy, +Y
        [(-hx, hy, 0), (hx, hy, 0), (hx, hy, h), (-hx, hy, h)],            # y = +hy, -Y
    ]


def room(size=(4.0, 4.0, 3.0), albedo=0.7, energy=400.0):
    """Closed diffuse room (floor at z=0, normals inward) lit by a 1 m square ceiling area light."""
    scene = fresh()
    h = size[2]
    mat = diffuse_material("bench wall", albedo)
    quad_mesh(scene, "bench room", room_quads(size), mat)
    light(scene, "AREA", (0.0, 0.0, h - 0.01), energy=energy, shape="SQUARE", size=1.0)
    return scene


def add_triangles(scene, count, z=-0.5, extent=20.0):
    """A flat grid of about `count` triangles at height `z` (m), facing up; returns the object."""
    n = max(1, int(round(math.sqrt(count / 2))))  # n x n quads = 2 n^2 triangles
    xs = np.linspace(-extent / 2, extent / 2, n + 1)
    gx, gy = np.meshgrid(xs, xs)
    verts = np.c_[gx.ravel(), gy.ravel(), np.full(gx.size, z)].astype(np.float32)
    i, j = np.meshgrid(np.arange(n), np.arange(n))
    a = (j * (n + 1) + i).ravel()
    tris = np.concatenate([np.c_[a, a + 1, a + n + 2], np.c_[a, a + n + 2, a + n + 1]]).astype(np.int32)
    return _mesh_from_arrays(scene, "bench triangles", verts, tris, diffuse_material("bench grid", 0.5)), len(tris)


def meter_points(n, half_width=0.8, z=0.0, seed=0):
    """`n` meter positions on a horizontal square (m) facing +Z, deterministic."""
    rng = np.random.default_rng(seed)
    pts = np.c_[rng.uniform(-half_width, half_width, (n, 2)), np.full(n, z)]
    return pts, np.tile([0.0, 0.0, 1.0], (n, 1))


# --- scenes for issue 10's benchmarks -------------------------------------------------------------

def _mesh_from_arrays(scene, name, verts, tris, material):
    """One mesh object from (V, 3) vertices and (T, 3) triangle indices (fast foreach_set path)."""
    verts = np.asarray(verts, np.float32)
    tris = np.asarray(tris, np.int32)
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(len(verts))
    mesh.vertices.foreach_set("co", verts.ravel())
    mesh.loops.add(tris.size)
    mesh.loops.foreach_set("vertex_index", tris.ravel())
    mesh.polygons.add(len(tris))
    mesh.polygons.foreach_set("loop_start", np.arange(0, tris.size, 3, dtype=np.int32))
    mesh.polygons.foreach_set("loop_total", np.full(len(tris), 3, np.int32))
    mesh.update()
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    scene.collection.objects.link(obj)
    return obj


def _subdivided_cube(n):
    """Unit cube [-1, 1]^3 with every face an n x n grid of quads (2 triangles each), outward normals,
    as Add > Cube + Subdivide would give. Returns (verts, tris)."""
    s = np.linspace(-1.0, 1.0, n + 1)
    gu, gv = np.meshgrid(s, s, indexing="ij")
    gu, gv = gu.ravel(), gv.ravel()
    one = np.ones_like(gu)
    faces = [  # (x, y, z) of each face grid; the winding is fixed below from the face's outward axis
        (one, gu, gv, (1, 0, 0)), (-one, gu, gv, (-1, 0, 0)),
        (gu, one, gv, (0, 1, 0)), (gu, -one, gv, (0, -1, 0)),
        (gu, gv, one, (0, 0, 1)), (gu, gv, -one, (0, 0, -1)),
    ]
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    a = (i * (n + 1) + j).ravel()
    b, c, d = a + (n + 1), a + (n + 1) + 1, a + 1
    verts, tris = [], []
    for x, y, z, outward in faces:
        base = sum(len(v) for v in verts)
        v = np.c_[x, y, z]
        t = np.concatenate([np.c_[a, b, c], np.c_[a, c, d]]) + base
        p = v[t - base]
        nrm = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
        flip = nrm @ np.asarray(outward, float) < 0
        t[flip] = t[flip][:, ::-1]
        verts.append(v)
        tris.append(t)
    return np.concatenate(verts), np.concatenate(tris)


#: Furniture of the big room: (centre x, y), half extents (x, y, z); boxes stand on the floor.
BIG_ROOM_FURNITURE = (((1.2, 0.6), (0.8, 0.4, 0.375)),    # desk-sized box (top at 0.75 m)
                      ((-1.5, -1.0), (0.5, 0.5, 0.45)),   # low cabinet
                      ((-1.6, 1.4), (0.3, 0.9, 1.0)),     # tall shelf (2 m)
                      ((0.9, -1.6), (0.6, 0.3, 0.6)))     # sideboard
BIG_ROOM = {"size": (6.0, 5.0, 3.0), "area": ((0.0, 0.0), 1.2, 300.0), "point": ((1.5, -0.6, 2.0), 60.0)}


def big_room(triangles=130_000, albedo=0.6):
    """A ~130k-triangle CLOSED room: a subdivided cube scaled to 6 x 5 x 3 m (floor at z = 0), four
    furniture boxes standing on the floor, a 1.2 m square ceiling area light (300 W) and a radius-0
    point light (60 W) at 2 m. Returns (scene, triangle count)."""
    scene = fresh()
    n = max(2, int(round(math.sqrt(triangles / 12.0))))  # 6 faces x n^2 quads x 2 triangles
    verts, tris = _subdivided_cube(n)
    sx, sy, sz = BIG_ROOM["size"]
    verts = verts * np.array([sx / 2, sy / 2, sz / 2]) + np.array([0.0, 0.0, sz / 2])
    wall = diffuse_material("bench big room wall", albedo)
    _mesh_from_arrays(scene, "bench big room", verts, tris, wall)
    count = len(tris)
    box_v, box_t = _subdivided_cube(1)
    wood = diffuse_material("bench furniture", 0.35)
    for k, ((cx, cy), (hx, hy, hz)) in enumerate(BIG_ROOM_FURNITURE):
        v = box_v * np.array([hx, hy, hz]) + np.array([cx, cy, hz])
        _mesh_from_arrays(scene, f"bench furniture {k}", v, box_t, wood)
        count += len(box_t)
    (ax, ay), side, power = BIG_ROOM["area"]
    light(scene, "AREA", (ax, ay, sz - 0.01), energy=power, shape="SQUARE", size=side)
    loc, power = BIG_ROOM["point"]
    light(scene, "POINT", loc, energy=power, shadow_soft_size=0.0)
    return scene, count


def floor_meters(n, seed=0, z=0.0, margin=0.25):
    """`n` meters lying ON the floor of ``big_room`` (z = 0, facing up), outside the furniture's
    footprints; some of them lie in the furniture's shadows. Deterministic."""
    rng = np.random.default_rng(seed)
    sx, sy, _ = BIG_ROOM["size"]
    out = []
    while len(out) < n:
        p = rng.uniform([-sx / 2 + margin, -sy / 2 + margin], [sx / 2 - margin, sy / 2 - margin], (4 * n, 2))
        inside = np.zeros(len(p), bool)
        for (cx, cy), (hx, hy, _hz) in BIG_ROOM_FURNITURE:
            inside |= (np.abs(p[:, 0] - cx) < hx + 0.02) & (np.abs(p[:, 1] - cy) < hy + 0.02)
        out.extend(p[~inside].tolist())
    pts = np.c_[np.array(out[:n]), np.full(n, z)]
    return pts, np.tile([0.0, 0.0, 1.0], (n, 1))


def multi_light(count_points=6, albedo=0.15):
    """Light sampling is the noise: a dark closed 5 x 5 x 3 m room (albedo 0.15, so reflected light is
    small), six radius-0 point lights, a spot light and a small area light, and a table (box top at 0.7 m, 1.2 x 0.8 m) that puts
    meters near it in the partial shadow of some lights. Returns the scene."""
    scene = fresh()
    verts, tris = _subdivided_cube(4)
    verts = verts * np.array([2.5, 2.5, 1.5]) + np.array([0.0, 0.0, 1.5])
    _mesh_from_arrays(scene, "bench multi room", verts, tris, diffuse_material("bench multi wall", albedo))
    box_v, box_t = _subdivided_cube(1)
    v = box_v * np.array([0.6, 0.4, 0.35]) + np.array([0.0, 0.0, 0.35])
    _mesh_from_arrays(scene, "bench table", v, box_t, diffuse_material("bench table", 0.3))
    spots = ((-1.5, -1.2, 2.5), (1.4, -1.0, 2.2), (0.2, 1.6, 2.6), (-1.9, 1.8, 1.2), (1.9, 0.3, 1.6), (0.0, -1.9, 2.0))
    for k, loc in enumerate(spots[:count_points]):
        light(scene, "POINT", loc, energy=40.0 + 10 * k, shadow_soft_size=0.0)
    light(scene, "SPOT", (-1.0, 1.2, 2.8), rotation=(math.radians(15), 0.0, 0.0), energy=120.0,
          shadow_soft_size=0.0, spot_size=math.radians(70), spot_blend=0.2)
    light(scene, "AREA", (1.2, 1.2, 2.99), energy=60.0, shape="SQUARE", size=0.4)
    return scene


def multi_light_meters():
    """Meters on the floor around the table of ``multi_light``: in its shadow from some lights."""
    pts = np.array([[0.0, -0.6, 0.0], [0.75, 0.0, 0.0], [-0.8, 0.2, 0.0], [0.3, 0.6, 0.0],
                    [-1.8, -1.8, 0.0], [1.9, 1.5, 0.0]])
    return pts, np.tile([0.0, 0.0, 1.0], (len(pts), 1))


def load_test_module(name):
    """tests/bpy/<name>.py as a module (the test corpus's scene builders and reference helpers)."""
    path = pathlib.Path(__file__).resolve().parents[1] / "tests" / "bpy" / f"{name}.py"
    spec = importlib.util.spec_from_file_location(f"_bench_{name}", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def write_results(folder, stem, data, markdown_text):
    """``folder/stem.json`` (``data``, numpy numbers as floats) and ``folder/stem.md`` (``markdown_text``),
    each written whole or not at all; ``folder`` is made when missing."""
    import json
    import os

    from radiometer.outputs import write_text

    os.makedirs(folder, exist_ok=True)
    write_text(os.path.join(folder, f"{stem}.json"), json.dumps(data, indent=2, default=float) + "\n")
    write_text(os.path.join(folder, f"{stem}.md"), markdown_text + "\n")


def grid_arguments(args, n=10, target=0.01, whole=12):
    """(n, target, whole) from a bench script's command line ``args`` ([n] [target] [whole]: an n x n grid at
    ``target`` relative error, ``whole`` of its points also rendered whole), the defaults where missing."""
    return (int(args[0]) if args else n, float(args[1]) if len(args) > 1 else target,
            int(args[2]) if len(args) > 2 else whole)


def grid_pair(api, scene, plane, n, target):
    """After a warm-up (a 2 x 2 electric and daylight-factor grid on ``plane``: kernels, captures, the emitters'
    checks), (electric, auto): callables that run the n x n illuminance grid and the daylight-factor grid (``method``
    auto, seed 1) at ``target``, the pair the issue-31 benches time against each other."""
    api.illuminance_grid(plane, resolution=(2, 2), scene=scene, target_rel_error=0.05)
    api.daylight_factor_grid(plane, resolution=(2, 2), scene=scene, target_rel_error=0.05)

    def electric():
        return api.illuminance_grid(plane, resolution=(n, n), scene=scene, target_rel_error=target)

    def auto():
        return api.daylight_factor_grid(plane, resolution=(n, n), scene=scene, target_rel_error=target, seed=1)

    return electric, auto


def pop_option(args, flag, default, kind=str):
    """The value after ``flag`` in the list ``args`` (both removed from it) as ``kind``, else ``default``."""
    if flag not in args:
        return default
    k = args.index(flag)
    value = kind(args[k + 1])
    del args[k:k + 2]
    return value
