"""Benchmark scenes built with plain bpy (metres, unit scale 1): delta-lit, area-lit, an
interreflecting closed room, a heavy triangle mesh, and the white card + camera of the manual way.

Reference values: point light E = P cos / (4 pi r^2) (FACTS.md, measured to 1e-6); square area light
by the radiometer's closed form (Lambert's polygon formula, checked against Cycles in tests/bpy).
"""

import math

import bpy
import numpy as np

from radiometer.compat import ensure_node_tree


def fresh():
    """Empty factory scene with a black world; returns the scene."""
    import radiometer

    radiometer.unregister()  # no-op when not registered; registering twice would fail
    bpy.ops.wm.read_factory_settings(use_empty=True)
    radiometer.register()
    scene = bpy.context.scene
    world = bpy.data.worlds.new("bench black")
    ensure_node_tree(world).nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world
    return scene


def diffuse_material(name, albedo):
    mat = bpy.data.materials.new(name)
    tree = ensure_node_tree(mat)
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    bsdf = tree.nodes.new("ShaderNodeBsdfDiffuse")
    bsdf.inputs["Color"].default_value = (albedo, albedo, albedo, 1.0)
    tree.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    return mat


def light(scene, kind, location, rotation=(0.0, 0.0, 0.0), **props):
    data = bpy.data.lights.new(f"bench {kind.lower()}", kind)
    for key, value in props.items():
        setattr(data, key, value)
    obj = bpy.data.objects.new(data.name, data)
    obj.location, obj.rotation_euler = location, rotation
    scene.collection.objects.link(obj)
    return obj


def quad_mesh(scene, name, quads, material):
    """One object from a list of quads (4 corner tuples each; winding sets the normal)."""
    verts = [v for q in quads for v in q]
    faces = [tuple(range(4 * i, 4 * i + 4)) for i in range(len(quads))]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    scene.collection.objects.link(obj)
    return obj


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


def room(size=(4.0, 4.0, 3.0), albedo=0.7, energy=400.0):
    """Closed diffuse room (floor at z=0, normals inward) lit by a 1 m square ceiling area light."""
    scene = fresh()
    hx, hy, h = size[0] / 2, size[1] / 2, size[2]
    mat = diffuse_material("bench wall", albedo)
    quads = [
        [(-hx, -hy, 0), (hx, -hy, 0), (hx, hy, 0), (-hx, hy, 0)],          # floor, +Z
        [(-hx, -hy, h), (-hx, hy, h), (hx, hy, h), (hx, -hy, h)],          # ceiling, -Z
        [(-hx, -hy, 0), (-hx, hy, 0), (-hx, hy, h), (-hx, -hy, h)],        # x = -hx, +X
        [(hx, -hy, 0), (hx, -hy, h), (hx, hy, h), (hx, hy, 0)],            # x = +hx, -X
        [(-hx, -hy, 0), (-hx, -hy, h), (hx, -hy, h), (hx, -hy, 0)],        # y = -hy, +Y
        [(-hx, hy, 0), (hx, hy, 0), (hx, hy, h), (-hx, hy, h)],            # y = +hy, -Y
    ]
    quad_mesh(scene, "bench room", quads, mat)
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
    mesh = bpy.data.meshes.new("bench triangles")
    mesh.vertices.add(len(verts))
    mesh.vertices.foreach_set("co", verts.ravel())
    mesh.loops.add(tris.size)
    mesh.loops.foreach_set("vertex_index", tris.ravel())
    mesh.polygons.add(len(tris))
    mesh.polygons.foreach_set("loop_start", np.arange(0, tris.size, 3, dtype=np.int32))
    mesh.polygons.foreach_set("loop_total", np.full(len(tris), 3, np.int32))
    mesh.update()
    mesh.materials.append(diffuse_material("bench grid", 0.5))
    obj = bpy.data.objects.new("bench triangles", mesh)
    scene.collection.objects.link(obj)
    return obj, len(tris)


def meter_points(n, half_width=0.8, z=0.0, seed=0):
    """`n` meter positions on a horizontal square (m) facing +Z, deterministic."""
    rng = np.random.default_rng(seed)
    pts = np.c_[rng.uniform(-half_width, half_width, (n, 2)), np.full(n, z)]
    return pts, np.tile([0.0, 0.0, 1.0], (n, 1))
