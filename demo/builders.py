"""Scene building blocks, the one home for them: a black world, a Diffuse BSDF material, a light, a
square plane, a mesh object, a closed box. The demo rooms are built of them, and so are the benchmark scenes
(``bench/scenes.py``) and the tests' ``build`` fixture (``tests/bpy/conftest.py``). Metres at unit
scale 1; every function returns what it made."""

import bpy

from ..compat import ensure_node_tree
from ..measure.blender.materials import shader_material


def metric_cycles_scene(scene):
    """Set ``scene`` up as every built scene is: Cycles, metric units, unit scale 1 (1 unit = 1 m)."""
    scene.render.engine = "CYCLES"
    scene.unit_settings.system = "METRIC"
    scene.unit_settings.scale_length = 1.0
    return scene


def black_world(scene, name="black"):
    """Give ``scene`` a new world whose Background emits nothing (strength 0, colour black)."""
    world = bpy.data.worlds.new(name)
    background = ensure_node_tree(world).nodes["Background"]
    background.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    background.inputs["Strength"].default_value = 0.0
    scene.world = world
    return world


def diffuse_material(name, albedo):
    """A Diffuse BSDF material of ``albedo``: one number (grey) or RGB; the viewport colour matches."""
    rgb = tuple(float(a) for a in albedo) if hasattr(albedo, "__len__") else (float(albedo),) * 3
    mat, _bsdf = shader_material(name, "ShaderNodeBsdfDiffuse", {"Color": (*rgb, 1.0)})
    mat.diffuse_color = (*rgb, 1.0)
    return mat


def add_light(scene, kind, location=(0.0, 0.0, 0.0), rotation=(0.0, 0.0, 0.0), *, name=None, collection=None,
              **props):
    """A light of ``kind`` (POINT, SPOT, AREA, SUN) at ``location`` with Euler ``rotation`` (rad), its
    data-block's ``props`` set (energy W, shadow_soft_size m, size m, ...), linked to ``collection``
    (default the scene's)."""
    data = bpy.data.lights.new(name or kind.lower(), kind)
    for key, value in props.items():
        setattr(data, key, value)
    obj = bpy.data.objects.new(data.name, data)
    obj.location, obj.rotation_euler = location, rotation
    (collection or scene.collection).objects.link(obj)
    return obj


def add_plane(scene, size=1.0, location=(0.0, 0.0, 0.0), rotation=(0.0, 0.0, 0.0), albedo=0.8, name="plane"):
    """A square one-sided quad of side ``size`` (normal local +Z) with a diffuse material of ``albedo``."""
    h = size / 2
    obj = mesh_object(name, [(-h, -h, 0), (h, -h, 0), (h, h, 0), (-h, h, 0)], [(0, 1, 2, 3)],
                      diffuse_material(name, albedo), scene.collection)
    obj.location, obj.rotation_euler = location, rotation
    return obj


def mesh_object(name, verts, faces, material, collection):
    """An object ``name`` in ``collection`` of a new mesh of ``verts`` (m) and ``faces`` (vertex indices;
    winding sets the normal) with ``material``."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    collection.objects.link(obj)
    return obj


def closed_box(name, centre, half, material, collection):
    """A closed box mesh (6 quads, outward normals) in world coordinates, as Add > Cube then scale
    would give: ``centre`` and ``half`` extents (m)."""
    cx, cy, cz = centre
    hx, hy, hz = half
    verts = [(cx + sx * hx, cy + sy * hy, cz + sz * hz) for sz in (-1, 1) for sy in (-1, 1) for sx in (-1, 1)]
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    return mesh_object(name, verts, faces, material, collection)
