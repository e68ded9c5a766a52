"""Add meter on surface: a ray from the view onto a desk places an illuminance meter ON the hit point,
its +Z along the face normal; the operator is one undo step (issue 13)."""

import math

import bpy
import pytest
from mathutils import Vector


def desk(build, rotation=(0.0, 0.0, 0.0)):
    scene = bpy.context.scene
    # A 1.2 m x 0.6 m desk top at 0.75 m (a quad), possibly tilted like a drafting table.
    obj = build.plane(scene, size=1.0, location=(0.2, -0.1, 0.75), rotation=rotation, name="Desk")
    obj.scale = (1.2, 0.6, 1.0)
    bpy.context.view_layer.update()
    return scene, obj


def face_normal(obj):
    return (obj.matrix_world.to_3x3() @ obj.data.polygons[0].normal).normalized()


def test_ray_onto_a_desk_puts_the_meter_on_the_surface_facing_up(clean_blender, build):
    from radiometer.operators.meter import meter_pose_on_surface

    scene, obj = desk(build)
    origin, direction = Vector((1.5, 0.4, 2.5)), Vector((0.3, -0.1, 0.75)) - Vector((1.5, 0.4, 2.5))
    location, normal, rotation, hit = meter_pose_on_surface(scene, origin, direction)
    assert hit.name == "Desk"
    assert location.z == pytest.approx(0.75, abs=1e-6)  # exactly on the surface
    assert (location - Vector((0.3, -0.1, 0.75))).length < 1e-5
    assert (normal - Vector((0, 0, 1))).length < 1e-6
    z = rotation.to_matrix().col[2]
    assert (z - face_normal(obj)).length < 1e-6


def test_tilted_desk_normal_and_back_face(clean_blender, build):
    from radiometer.operators.meter import meter_pose_on_surface

    scene, obj = desk(build, rotation=(math.radians(30.0), 0.0, math.radians(20.0)))
    n = face_normal(obj)
    centre = obj.matrix_world.translation
    location, normal, rotation, _hit = meter_pose_on_surface(scene, centre + 2.0 * n + Vector((0.1, 0, 0)),
                                                             -n)
    assert abs((location - centre).dot(n)) < 1e-6  # in the face's plane
    assert (normal - n).length < 1e-6
    assert (rotation.to_matrix().col[2] - n).length < 1e-6
    # From behind (under the desk) the meter faces the viewer: the side the ray came from.
    _loc, normal, _rot, _hit = meter_pose_on_surface(scene, centre - 2.0 * n, n)
    assert (normal + n).length < 1e-6
    # A ray that misses: None.
    assert meter_pose_on_surface(scene, Vector((10, 10, 10)), Vector((0, 0, 1))) is None


def test_operator_adds_meter_on_the_hit_point_and_undo_removes_it(clean_blender, build):
    scene, obj = desk(build)
    bpy.ops.ed.undo_push(message="desk")
    result = bpy.ops.radiometer.add_meter_on_surface("EXEC_DEFAULT", True, ray_origin=(0.3, -0.1, 3.0),
                                                     ray_direction=(0.0, 0.0, -1.0))
    assert result == {"FINISHED"}
    meter = bpy.context.active_object
    name = meter.name
    m = meter.radiometer_meter
    assert m.is_meter and m.kind == "ILLUMINANCE"
    assert (meter.location - Vector((0.3, -0.1, 0.75))).length < 1e-6
    assert (meter.matrix_world.to_3x3().col[2] - Vector((0, 0, 1))).length < 1e-6
    assert bpy.ops.ed.undo() == {"FINISHED"}
    assert name not in bpy.data.objects
    assert bpy.ops.ed.redo() == {"FINISHED"}
    assert name in bpy.data.objects


def test_operator_misses_adds_nothing(clean_blender, build):
    desk(build)
    n = len(bpy.data.objects)
    assert bpy.ops.radiometer.add_meter_on_surface(ray_origin=(5, 5, 5), ray_direction=(0, 0, 1)) == {"CANCELLED"}
    assert len(bpy.data.objects) == n


def test_meter_on_the_desk_reads_the_light_arriving_there(clean_blender, build):
    """Placed exactly on the surface, the meter still reads the light above it (its sensor is raised)."""
    scene, _obj = desk(build)
    build.black_world(scene)
    build.light(scene, "POINT", (0.3, -0.1, 2.75), energy=100.0, shadow_soft_size=0.0)
    bpy.ops.radiometer.add_meter_on_surface(ray_origin=(0.3, -0.1, 3.0), ray_direction=(0.0, 0.0, -1.0))
    bpy.ops.radiometer.measure()
    m = bpy.context.active_object.radiometer_meter
    assert m.photometric == pytest.approx(683 * 100 / (4 * math.pi * 4), rel=0.03)
