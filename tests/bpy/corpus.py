"""A corpus of realistic scenes for testing the meter, built the way users build them (pure bpy).

Every builder starts from an empty factory scene (``bpy.ops.wm.read_factory_settings(use_empty=True)``)
unless ``reset=False``, builds into ``bpy.context.scene`` and returns a dict with at least
``scene``, ``objects`` (name -> object) and ``cases``: a list of ``Case(label, point, normal, note,
on_surface, scene_name)``. ``point`` and ``normal`` are in scene coordinates. ``on_surface=True``
means the point lies exactly ON a surface (a meter lying on a desk or hanging on a wall); the
reference sensor must then be lifted into free space with ``reference.lift_off_surface`` (1e-5 m).
``scene_name`` is set when the case measures a scene other than the returned one.

Units: every length below is written in METRES and divided by ``scene.unit_settings.scale_length``
when a builder takes ``scale_length`` (``closed_room``), so the room is 4 x 3 x 2.7 m in SI whatever
the unit scale. Powers of point, spot and area lights (W) need no conversion (Cycles: radiant
intensity P / (4 pi) W/sr, E = I / r^2 per scene unit^2, and E_SI = E_scene / scale^2 follows). A
sun's strength and a world's radiance ARE per scene unit^2, so they are multiplied by scale^2 to keep
the SI scene identical (the corpus only uses suns and worlds at scale 1).

Black world unless stated. Materials: walls use a Diffuse BSDF (albedo given); desks use the
Principled BSDF users get by default (so there is a specular layer, i.e. glossy paths).
"""

import collections
import math

import bpy
from mathutils import Vector

from radiometer.compat import ensure_node_tree  # Blender 4.5: new worlds/materials have no tree yet

Case = collections.namedtuple("Case", "label point normal note on_surface scene_name", defaults=(False, None))


# ---------------------------------------------------------------- helpers

def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return bpy.context.scene


def black_world(scene):
    world = bpy.data.worlds.new("black")
    ensure_node_tree(world).nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.world = world
    return world


def colour_world(scene, colour=(0.4, 0.6, 1.0), strength=1.0):
    world = bpy.data.worlds.new("sky")
    bg = ensure_node_tree(world).nodes["Background"]
    bg.inputs["Color"].default_value = (*colour, 1.0)
    bg.inputs["Strength"].default_value = strength
    scene.world = world
    return world


def diffuse(name, albedo):
    mat = bpy.data.materials.new(name)
    tree = ensure_node_tree(mat)
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    bsdf = tree.nodes.new("ShaderNodeBsdfDiffuse")
    a = albedo if isinstance(albedo, (tuple, list)) else (albedo,) * 3
    bsdf.inputs["Color"].default_value = (*a, 1.0)
    tree.links.new(bsdf.outputs["BSDF"], out.inputs["Surface"])
    return mat


def principled(name, base, roughness=0.5):
    mat = bpy.data.materials.new(name)
    bsdf = ensure_node_tree(mat).nodes.get("Principled BSDF")
    if bsdf is None:  # pragma: no cover - a new node tree has a Principled BSDF (4.5 and 5)
        raise RuntimeError("no Principled BSDF in a new material")
    b = base if isinstance(base, (tuple, list)) else (base,) * 3
    bsdf.inputs["Base Color"].default_value = (*b, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    return mat


def add_light(scene, kind, location=(0.0, 0.0, 0.0), rotation=(0.0, 0.0, 0.0), name=None, collection=None,
              **props):
    data = bpy.data.lights.new(name or kind.lower(), kind)
    if kind in ("POINT", "SPOT", "AREA"):
        data.shadow_soft_size = 0.0 if kind != "AREA" else data.shadow_soft_size
    for key, value in props.items():
        setattr(data, key, value)
    obj = bpy.data.objects.new(name or kind.lower(), data)
    obj.location, obj.rotation_euler = location, rotation
    (collection or scene.collection).objects.link(obj)
    return obj


def add_box(scene, name, lo, hi, material, collection=None):
    """Closed box mesh with outward normals; object at the box centre, mesh in local coordinates."""
    lo, hi = Vector(lo), Vector(hi)
    c, h = (lo + hi) / 2, (hi - lo) / 2
    v = [(sx * h.x, sy * h.y, sz * h.z) for sz in (-1, 1) for sy in (-1, 1) for sx in (-1, 1)]
    # vertex index = ix + 2 iy + 4 iz; faces counter-clockwise seen from outside
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(v, [], faces)
    mesh.update()
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    obj.location = c
    (collection or scene.collection).objects.link(obj)
    return obj


def add_quad(scene, name, corners, material, collection=None):
    """One planar quad from 4 world-space corners (a wall piece; single sided, Cycles shades both)."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([tuple(c) for c in corners], [], [(0, 1, 2, 3)])
    mesh.update()
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    (collection or scene.collection).objects.link(obj)
    return obj


def _look(forward):
    """Euler rotation whose local -Z points along ``forward`` (lights emit along local -Z)."""
    return Vector(forward).normalized().to_track_quat("-Z", "Y").to_euler()


def _result(scene, cases, **extra):
    return {"scene": scene, "objects": {o.name: o for o in scene.objects}, "cases": cases, **extra}


# ---------------------------------------------------------------- scenes

def closed_room(scale_length=1.0, do_reset=True):
    """4 x 3 x 2.7 m room made as Add > Cube, scaled (outward normals, NOT flipped), walls albedo 0.7;
    a 0.6 x 0.6 m, 40 W ceiling panel 1 cm below the ceiling facing down; a desk (closed slab, top at
    0.75 m, on four legs) with a 5 W spot lamp (radius 0.02 m) 0.4 m above it."""
    scene = reset() if do_reset else bpy.context.scene
    scene.unit_settings.scale_length = scale_length
    u = 1.0 / scale_length  # metres -> scene units
    black_world(scene)
    bpy.ops.mesh.primitive_cube_add(size=2.0, location=(0.0, 0.0, 1.35 * u))
    room = bpy.context.active_object
    room.name = "Room"
    room.scale = (2.0 * u, 1.5 * u, 1.35 * u)
    room.data.materials.append(diffuse("wall", 0.7))
    wood = principled("desk", (0.45, 0.3, 0.2), roughness=0.5)
    top = add_box(scene, "DeskTop", (0.4 * u, 0.2 * u, 0.72 * u), (1.6 * u, 0.8 * u, 0.75 * u), wood)
    for i, (x, y) in enumerate([(0.45, 0.25), (1.55, 0.25), (0.45, 0.75), (1.55, 0.75)]):
        add_box(scene, f"DeskLeg{i}", ((x - 0.025) * u, (y - 0.025) * u, 0.0), ((x + 0.025) * u, (y + 0.025) * u,
                                                                               0.72 * u), wood)
    add_light(scene, "AREA", (0.0, 0.0, 2.69 * u), name="CeilingPanel", energy=40.0, size=0.6 * u, shape="SQUARE")
    add_light(scene, "SPOT", (1.0 * u, 0.5 * u, 1.15 * u), name="DeskLamp", energy=5.0, shadow_soft_size=0.02 * u,
              spot_size=math.radians(100.0), spot_blend=0.3)
    z = (0.0, 0.0, 1.0)
    cases = [
        Case("floor centre", (0.0, 0.0, 0.0), z, "on the floor, panel overhead", True),
        Case("desk top", (1.1 * u, 0.5 * u, 0.75 * u), z, "exactly on the desk top, 0.1 m off the lamp axis", True),
        Case("wall", (-2.0 * u, 0.0, 1.2 * u), (1.0, 0.0, 0.0), "on the -X wall facing the room", True),
        Case("under desk", (1.0 * u, 0.5 * u, 0.0), z, "floor under the desk top (shadowed)", True),
    ]
    return _result(scene, cases, scale_length=scale_length)


def integrating_sphere(rho=0.8, power=100.0, radius=0.5, segments=128, rings=64, do_reset=True):
    """Closed UV sphere (Add > UV Sphere, outward normals) of albedo ``rho`` with a radius-0 point light
    at the centre. Closed form for a true sphere: E = P / (A (1 - rho)), A = 4 pi R^2. The result also
    gives ``area_poly`` (sum of facet areas) for the polygon-corrected form. Meters sit exactly on
    facet centres facing inward."""
    scene = reset() if do_reset else bpy.context.scene
    black_world(scene)
    bpy.ops.mesh.primitive_uv_sphere_add(segments=segments, ring_count=rings, radius=radius, location=(0, 0, 0))
    sphere = bpy.context.active_object
    sphere.name = "Sphere"
    sphere.data.materials.append(diffuse("sphere", rho))
    add_light(scene, "POINT", (0.0, 0.0, 0.0), name="Centre", energy=power, shadow_soft_size=0.0)
    polys = sphere.data.polygons
    area = sum(p.area for p in polys)
    cases = []
    # facets at three latitudes (quads only; the pole fans are triangles): equator, 45 deg, near pole
    for label, ring in (("equator", rings // 2), ("mid latitude", rings // 4), ("near pole", 2)):
        target_z = radius * math.cos(math.pi * (ring + 0.5) / rings)
        p = min((p for p in polys if p.loop_total == 4), key=lambda p: abs(p.center.z - target_z) +
                1e-3 * abs(math.atan2(p.center.y, p.center.x) - 0.3))
        cases.append(Case(label, tuple(p.center), tuple(-p.normal), "inner wall, facet centre", True))
    return _result(scene, cases, rho=rho, power=power, radius=radius, area_poly=area,
                   closed_form_true_sphere=power / (4 * math.pi * radius ** 2 * (1 - rho)))


def desk_only(do_reset=True):
    """A desk top (closed box slab, top at 0.75 m) lit by one 5 W spot lamp, nothing else."""
    scene = reset() if do_reset else bpy.context.scene
    black_world(scene)
    add_box(scene, "DeskTop", (-0.6, -0.3, 0.72), (0.6, 0.3, 0.75), principled("desk", (0.45, 0.3, 0.2)))
    add_light(scene, "SPOT", (0.0, 0.0, 1.15), name="DeskLamp", energy=5.0, shadow_soft_size=0.02,
              spot_size=math.radians(100.0), spot_blend=0.3)
    z = (0.0, 0.0, 1.0)
    cases = [Case("desk top under lamp", (0.0, 0.0, 0.75), z, "exactly on the desk top", True),
             Case("desk top off axis", (0.3, 0.15, 0.75), z, "exactly on the desk top, 40 deg off the lamp axis (in the blend)", True)]
    return _result(scene, cases)


def _luminaire_collection():
    coll = bpy.data.collections.new("Luminaire")  # not linked to the scene: only instances render
    add_light(None, "AREA", (0.0, 0.0, 0.0), name="LumPanel", collection=coll, energy=20.0, size=0.5,
              shape="SQUARE")
    add_box(None, "LumHousing", (-0.3, -0.3, 0.005), (0.3, 0.3, 0.06), diffuse("housing", 0.2), collection=coll)
    return coll


def _occluder_collection():
    coll = bpy.data.collections.new("Occluder")
    add_box(None, "OccluderBox", (-0.2, -0.2, -0.01), (0.2, 0.2, 0.01), diffuse("occluder", 0.5), collection=coll)
    return coll


LUMINAIRE_XY = [(x, y) for y in (-0.75, 0.75) for x in (-1.5, 0.0, 1.5)]
LUMINAIRE_Z = 2.5


def instanced_luminaires(mode="empties", do_reset=True):
    """3 x 2 luminaires (20 W, 0.5 m area panel + a dark housing above it) at 2.5 m over a floor of
    albedo 0.5, plus an occluder (0.4 m box) at 1.0 m under the luminaire at (1.5, 0.75).
    ``mode``: "empties" (collection-instance empties), "geonodes" (Instance on Points of the
    collection in a Geometry Nodes modifier) or "real" (real objects: the reference for the other two).
    The occluder is a collection instance (an empty) in the first two modes."""
    scene = reset() if do_reset else bpy.context.scene
    black_world(scene)
    add_quad(scene, "Floor", [(-4, -3, 0), (4, -3, 0), (4, 3, 0), (-4, 3, 0)], diffuse("floor", 0.5))
    lum = _luminaire_collection()
    occ = _occluder_collection()
    if mode == "empties":
        for i, (x, y) in enumerate(LUMINAIRE_XY):
            e = bpy.data.objects.new(f"LumInstance{i}", None)
            e.instance_type, e.instance_collection = "COLLECTION", lum
            e.location = (x, y, LUMINAIRE_Z)
            scene.collection.objects.link(e)
    elif mode == "geonodes":
        mesh = bpy.data.meshes.new("LumPoints")
        mesh.from_pydata([(x, y, LUMINAIRE_Z) for x, y in LUMINAIRE_XY], [], [])
        obj = bpy.data.objects.new("LumArray", mesh)
        scene.collection.objects.link(obj)
        tree = bpy.data.node_groups.new("LumArray", "GeometryNodeTree")
        tree.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
        tree.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
        gin, gout = tree.nodes.new("NodeGroupInput"), tree.nodes.new("NodeGroupOutput")
        info = tree.nodes.new("GeometryNodeCollectionInfo")
        info.inputs["Collection"].default_value = lum
        info.transform_space = "ORIGINAL"
        iop = tree.nodes.new("GeometryNodeInstanceOnPoints")
        tree.links.new(gin.outputs[0], iop.inputs["Points"])
        tree.links.new(info.outputs[0], iop.inputs["Instance"])
        tree.links.new(iop.outputs["Instances"], gout.inputs[0])
        mod = obj.modifiers.new("LumArray", "NODES")
        mod.node_group = tree
    elif mode == "real":
        for i, (x, y) in enumerate(LUMINAIRE_XY):
            for src in lum.objects:
                dup = src.copy()
                dup.location = Vector(src.location) + Vector((x, y, LUMINAIRE_Z))
                dup.name = f"{src.name}{i}"
                scene.collection.objects.link(dup)
    else:
        raise ValueError(mode)
    if mode == "real":
        for src in occ.objects:
            dup = src.copy()
            dup.location = Vector(src.location) + Vector((1.5, 0.75, 1.0))
            scene.collection.objects.link(dup)
    else:
        e = bpy.data.objects.new("OccluderInstance", None)
        e.instance_type, e.instance_collection = "COLLECTION", occ
        e.location = (1.5, 0.75, 1.0)
        scene.collection.objects.link(e)
    z = (0.0, 0.0, 1.0)
    cases = [Case("under luminaire", (0.0, -0.75, 0.0), z, "floor under the middle front luminaire", True),
             Case("between luminaires", (-0.75, 0.0, 0.0), z, "floor between four luminaires", True),
             Case("behind occluder", (1.5, 0.75, 0.0), z, "floor under the instanced occluder", True),
             Case("facing up at 1 m", (0.0, 0.75, 1.0), z, "free space 1.5 m under a luminaire", False)]
    return _result(scene, cases, mode=mode)


def window_room(do_reset=True):
    """A 4 x 3 x 2.7 m room of separate wall planes with a 1.2 x 1.0 m window hole in the +Y wall
    (four wall pieces around the hole), a sun (strength 100 W/m^2, 35 deg elevation, default angle)
    shining in through it, and a constant-colour sky world (colour (0.4, 0.6, 1.0), strength 1)."""
    scene = reset() if do_reset else bpy.context.scene
    colour_world(scene, (0.4, 0.6, 1.0), 1.0)
    wall, floor = diffuse("wall", 0.7), diffuse("floor", 0.3)
    X, Y, H = 2.0, 1.5, 2.7
    add_quad(scene, "Floor", [(-X, -Y, 0), (X, -Y, 0), (X, Y, 0), (-X, Y, 0)], floor)
    add_quad(scene, "Ceiling", [(-X, -Y, H), (-X, Y, H), (X, Y, H), (X, -Y, H)], wall)
    add_quad(scene, "WallS", [(-X, -Y, 0), (-X, -Y, H), (X, -Y, H), (X, -Y, 0)], wall)
    add_quad(scene, "WallW", [(-X, -Y, 0), (-X, Y, 0), (-X, Y, H), (-X, -Y, H)], wall)
    add_quad(scene, "WallE", [(X, -Y, 0), (X, -Y, H), (X, Y, H), (X, Y, 0)], wall)
    wx0, wx1, wz0, wz1 = -0.6, 0.6, 0.9, 1.9  # window hole in the +Y wall
    add_quad(scene, "WallN_below", [(-X, Y, 0), (X, Y, 0), (X, Y, wz0), (-X, Y, wz0)], wall)
    add_quad(scene, "WallN_above", [(-X, Y, wz1), (X, Y, wz1), (X, Y, H), (-X, Y, H)], wall)
    add_quad(scene, "WallN_left", [(-X, Y, wz0), (wx0, Y, wz0), (wx0, Y, wz1), (-X, Y, wz1)], wall)
    add_quad(scene, "WallN_right", [(wx1, Y, wz0), (X, Y, wz0), (X, Y, wz1), (wx1, Y, wz1)], wall)
    elev = math.radians(35.0)
    to_sun = Vector((0.0, math.cos(elev), math.sin(elev)))  # the sun is outside, beyond +Y
    add_light(scene, "SUN", (0, 0, 5), _look(-to_sun), name="Sun", energy=100.0)
    # Sun patch on the floor: rays through the window centre (0, 1.5, 1.4) reach z=0 at y = 1.5 - 1.4/tan(35)
    y_patch = Y - 1.4 / math.tan(elev)
    z = (0.0, 0.0, 1.0)
    cases = [Case("floor in sun patch", (0.0, y_patch, 0.0), z, "sunlit floor", True),
             Case("floor in shade", (-1.5, -1.0, 0.0), z, "floor, sky and walls only", True),
             Case("back wall", (0.0, -Y, 1.2), (0.0, 1.0, 0.0), "south wall facing the window", True),
             Case("window facing out", (0.0, Y - 0.05, 1.4), (0.0, 1.0, 0.0), "in the window, facing the sun", False)]
    return _result(scene, cases, to_sun=tuple(to_sun))


def hidden_lights(do_reset=True):
    """Lights that do or do not render, over a floor (albedo 0.5) with one wall, black world.

    Renders: ``ViewportHidden`` (hide_viewport=True), ``NoShadow`` (use_shadow=False, behind the wall,
    shines through it), ``Negative`` (energy -5 W: Cycles subtracts light).
    Does not render: ``HiddenColl`` (in a collection with hide_render), the light instanced by the
    hidden instancer ``HiddenInstancer``, ``Portal`` (an area light with is_portal: emits nothing).
    ``NoDiffuse`` (visible_diffuse=False) does not light diffuse surfaces (the meter is one)."""
    scene = reset() if do_reset else bpy.context.scene
    black_world(scene)
    add_quad(scene, "Floor", [(-3, -3, 0), (3, -3, 0), (3, 3, 0), (-3, 3, 0)], diffuse("floor", 0.5))
    add_quad(scene, "Wall", [(-3, 1.0, 0), (3, 1.0, 0), (3, 1.0, 2.5), (-3, 1.0, 2.5)], diffuse("wall", 0.5))
    lv = add_light(scene, "POINT", (0.0, 0.0, 2.0), name="ViewportHidden", energy=50.0)
    lv.hide_viewport = True
    hidden = bpy.data.collections.new("HiddenColl")
    scene.collection.children.link(hidden)
    hidden.hide_render = True
    add_light(scene, "POINT", (0.5, 0.0, 2.0), name="InHiddenColl", collection=hidden, energy=500.0)
    inst = bpy.data.collections.new("InstancedLight")
    add_light(None, "POINT", (0.0, 0.0, 0.0), name="InstancedPoint", collection=inst, energy=500.0)
    e = bpy.data.objects.new("HiddenInstancer", None)
    e.instance_type, e.instance_collection = "COLLECTION", inst
    e.location = (-0.5, 0.0, 2.0)
    e.hide_render = True
    scene.collection.objects.link(e)
    nd = add_light(scene, "AREA", (1.5, -1.0, 1.5), name="NoDiffuse", energy=200.0, size=0.5)
    nd.visible_diffuse = False
    portal = add_light(scene, "AREA", (0.0, -1.5, 2.4), name="Portal", energy=1000.0, size=1.0)
    portal.data.cycles.is_portal = True
    add_light(scene, "POINT", (0.0, 2.0, 1.0), name="NoShadow", energy=100.0, use_shadow=False)
    add_light(scene, "POINT", (-1.5, -1.0, 1.0), name="Negative", energy=-5.0)
    z = (0.0, 0.0, 1.0)
    cases = [Case("floor centre", (0.0, 0.0, 0.0), z, "hidden-viewport light overhead; hidden ones at 0.5 m", True),
             Case("facing wall", (0.0, 0.5, 1.0), (0.0, 1.0, 0.0), "faces the wall; the no-shadow light shines through it", False),
             Case("near negative", (-1.5, -1.0, 0.0), z, "floor under the negative light", True),
             Case("under no-diffuse", (1.5, -1.0, 0.0), z, "floor under the visible_diffuse=False light", True)]
    return _result(scene, cases)


def transformed_lights(do_reset=True, sheared_mis=True):
    """Area and spot lights under parent transforms, black world, no geometry.
    ``ScaledChild``: 0.5 m square area light (10 W) under a parent scaled (2, 2, 2) -> a 1 m square.
    ``ShearedChild``: 0.5 m square area (10 W), rotated 45 deg about Z, under a parent scaled (2, 0.5, 1):
      its world matrix is sheared (a rhombus).
    ``Mirrored``: 0.5 x 0.5 m area (10 W) with scale (-1, 1, 1).
    ``SquashedSpot``: 10 W spot (45 deg cone) with scale (1, 2, 1), 50 m away from the others so that
      its cases are not mixed with the sheared light's (measured: a radius-0 spot's on-axis intensity
      is P / (4 pi) whatever its scale).

    Measured Cycles behaviour (bpy 5.0.1), important when using this scene as a reference: with MIS
    on (the default) the SHEARED area light's converged contribution depends on the other lights in
    the scene. Under it: 2.745 W/m^2 rendered with all four lights, 2.840 as the sum of the four
    rendered one at a time (-3.3 %); with ``light.cycles.use_multiple_importance_sampling = False``
    on the sheared light both give 2.860 (additive). Light sampling and the emission seen by BSDF
    rays disagree for a sheared light, so the MIS-weighted answer is not well defined; compare a
    meter against the MIS-off render for that light.
    Also measured: at "squashed spot, 0.9 m along x" (outside the spot's cone; only the three far area
    lights reach it, 4.62e-5 W/m^2 rendered with the spot hidden or unscaled, = the sum of the lights
    rendered one at a time) the render with the (1, 2, 1)-scaled spot present converges to
    6.35e-5 +- 2 % (sheared light's MIS off): the non-uniformly scaled spot biases Cycles' light-tree
    sampling of the other lights. Cycles is not a trustworthy reference at that point."""
    scene = reset() if do_reset else bpy.context.scene
    black_world(scene)

    def parent(name, location, scale):
        e = bpy.data.objects.new(name, None)
        e.location, e.scale = location, scale
        scene.collection.objects.link(e)
        return e

    p1 = parent("ScaleParent", (-3.0, 0.0, 2.0), (2.0, 2.0, 2.0))
    a = add_light(scene, "AREA", (0, 0, 0), name="ScaledChild", energy=10.0, size=0.5)
    a.parent = p1
    p2 = parent("ShearParent", (0.0, 0.0, 2.0), (2.0, 0.5, 1.0))
    b = add_light(scene, "AREA", (0, 0, 0), (0.0, 0.0, math.radians(45.0)), name="ShearedChild", energy=10.0, size=0.5)
    b.parent = p2
    b.data.cycles.use_multiple_importance_sampling = sheared_mis
    add_light(scene, "AREA", (3.0, 0.0, 2.0), name="Mirrored", energy=10.0, size=0.5).scale = (-1.0, 1.0, 1.0)
    add_light(scene, "SPOT", (0.0, 50.0, 2.0), name="SquashedSpot", energy=10.0, spot_size=math.radians(45.0),
              spot_blend=0.0).scale = (1.0, 2.0, 1.0)
    z = (0.0, 0.0, 1.0)
    cases = [Case("under scaled parent", (-3.0, 0.0, 0.0), z, "1 m effective square at 2 m"),
             Case("under sheared", (0.0, 0.0, 0.0), z, "rhombus at 2 m"),
             Case("under sheared, tilted", (0.3, 0.0, 0.0), (0.5, 0.0, 0.8660254), "rhombus, tilted meter"),
             Case("under mirrored", (3.0, 0.0, 0.0), z, "negative-scale area light"),
             Case("squashed spot, on axis", (0.0, 50.0, 0.0), z, "spot with scale (1, 2, 1)"),
             Case("squashed spot, 0.9 m along y", (0.0, 50.9, 0.0), z, "inside the stretched cone only"),
             Case("squashed spot, 0.9 m along x", (0.9, 50.0, 0.0), z, "inside the round cone, outside the squashed")]
    return _result(scene, cases)


def two_scenes():
    """Two scenes in one file: "Scene" (active) with a 100 W point light at 2 m, and "Other" with a
    1 m square 100 W area light at 1 m. The cases measure "Other" while "Scene" stays active."""
    scene = reset()
    black_world(scene)
    add_light(scene, "POINT", (0.0, 0.0, 2.0), name="ActivePoint", energy=100.0)
    other = bpy.data.scenes.new("Other")
    other.render.engine = "CYCLES"
    black_world(other)
    add_light(other, "AREA", (0.0, 0.0, 1.0), name="OtherArea", energy=100.0, size=1.0)
    z = (0.0, 0.0, 1.0)
    cases = [Case("active scene", (0.0, 0.0, 0.0), z, "point light only: 100/(4 pi 4)", False, scene.name),
             Case("other scene", (0.0, 0.0, 0.0), z, "area light only: 23.946 W/m^2", False, "Other")]
    return _result(scene, cases, other=other)


def stacked_lights(do_reset=True):
    """Two 1 m square 50 W area lights facing down on the meter's axis, 1 m and 2 m above it. Lights are
    transparent to rays (FACTS.md), so the upper one shines through the lower one."""
    scene = reset() if do_reset else bpy.context.scene
    black_world(scene)
    add_light(scene, "AREA", (0.0, 0.0, 1.0), name="Lower", energy=50.0, size=1.0)
    add_light(scene, "AREA", (0.0, 0.0, 2.0), name="Upper", energy=50.0, size=1.0)
    cases = [Case("on axis", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), "both lights overhead")]
    return _result(scene, cases)


def on_surface_cases(built):
    return [c for c in built["cases"] if c.on_surface]


# name -> builder (no arguments) for the baseline and for parametrised tests
BUILDERS = {
    "closed_room": closed_room,
    "integrating_sphere": integrating_sphere,
    "desk_only": desk_only,
    "instanced_empties": lambda: instanced_luminaires("empties"),
    "instanced_geonodes": lambda: instanced_luminaires("geonodes"),
    "instanced_real": lambda: instanced_luminaires("real"),
    "window_room": window_room,
    "hidden_lights": hidden_lights,
    "transformed_lights": transformed_lights,
    "transformed_lights_sheared_mis_off": lambda: transformed_lights(sheared_mis=False),
    "room_scale_0.001": lambda: closed_room(0.001),
    "room_scale_1000": lambda: closed_room(1000.0),
    "two_scenes": two_scenes,
    "stacked_lights": stacked_lights,
}
