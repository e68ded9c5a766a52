"""A side-lit room for daylight tests and the bench: the same quads built in Blender and written for
Radiance (rtrace as a path tracer under the sharp-horizon CIE overcast sky, tests only)."""

import os
import subprocess

import numpy as np

W, D, H = 4.0, 3.0, 2.7            # x width, y depth, z height (m); the window wall is y = 0
WINDOW = (1.0, 3.0, 0.9, 2.1)      # x0, x1, z0, z1 of the opening (m)
RHO = {"floor": 0.2, "ceiling": 0.7, "walls": 0.5}
# surfaces only some scenes have (an obstruction outside): a material is made only where a quad names it, so
# the scenes without them are built and written for Radiance byte for byte as before (the cache keys hold)
RHO_EXTRA = {"obstruction": 0.2, "ground": 0.2}
POINTS = [(2.0, 0.75, 0.85), (2.0, 1.5, 0.85), (2.0, 2.5, 0.85)]


def quads(W=W, D=D, H=H, WINDOW=WINDOW):  # noqa: N803 - the module's names for the room's size
    """The room as named quads: a W x D x H box, the window an opening (x0, x1, z0, z1) in the wall y = 0."""
    x0, x1, z0, z1 = WINDOW
    return [("floor", [(0, 0, 0), (W, 0, 0), (W, D, 0), (0, D, 0)]),
            ("ceiling", [(0, 0, H), (0, D, H), (W, D, H), (W, 0, H)]),
            ("walls", [(0, D, 0), (W, D, 0), (W, D, H), (0, D, H)]),
            ("walls", [(0, 0, 0), (0, D, 0), (0, D, H), (0, 0, H)]),
            ("walls", [(W, 0, 0), (W, 0, H), (W, D, H), (W, D, 0)]),
            ("walls", [(0, 0, 0), (x0, 0, 0), (x0, 0, H), (0, 0, H)]),
            ("walls", [(x1, 0, 0), (W, 0, 0), (W, 0, H), (x1, 0, H)]),
            ("walls", [(x0, 0, 0), (x1, 0, 0), (x1, 0, z0), (x0, 0, z0)]),
            ("walls", [(x0, 0, z1), (x1, 0, z1), (x1, 0, H), (x0, 0, H)])]


def skylight_quads(W=4.0, D=4.0, H=3.0, SKYLIGHT=(1.5, 2.5, 1.5, 2.5)):  # noqa: N803 - as quads()
    """A closed W x D x H room (no window) with a convex opening x0..x1, y0..y1 (m) in its ceiling: the
    ceiling as 4 quads around the hole, thin like ``quads()``; inward normals."""
    x0, x1, y0, y1 = SKYLIGHT
    return [("floor", [(0, 0, 0), (W, 0, 0), (W, D, 0), (0, D, 0)]),
            ("ceiling", [(0, 0, H), (0, y0, H), (W, y0, H), (W, 0, H)]),
            ("ceiling", [(0, y1, H), (0, D, H), (W, D, H), (W, y1, H)]),
            ("ceiling", [(0, y0, H), (0, y1, H), (x0, y1, H), (x0, y0, H)]),
            ("ceiling", [(x1, y0, H), (x1, y1, H), (W, y1, H), (W, y0, H)]),
            ("walls", [(0, 0, 0), (0, 0, H), (W, 0, H), (W, 0, 0)]),
            ("walls", [(0, D, 0), (W, D, 0), (W, D, H), (0, D, H)]),
            ("walls", [(0, 0, 0), (0, D, 0), (0, D, H), (0, 0, H)]),
            ("walls", [(W, 0, 0), (W, 0, H), (W, D, H), (W, D, 0)])]


def ground_quads(z=-0.01, reach=30.0):
    """A square ground plane ``reach`` m round the room, just below its floor (named "ground": RHO_EXTRA)."""
    return [("ground", [(-reach, -reach, z), (W + reach, -reach, z), (W + reach, D + reach, z),
                        (-reach, D + reach, z)])]


def box_triangles(lo, hi):
    """12 outward-facing triangles (12, 3, 3) of an axis-aligned box from corner ``lo`` to ``hi`` (m)."""
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    v = np.array([[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0],
                  [x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]], float)
    quads = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]
    return np.array([[v[a], v[b], v[c]] for a, b, c, d in quads] + [[v[a], v[c], v[d]] for a, b, c, d in quads])


def window_frame_boxes(width=0.05, depth=0.06, mullion=True, window=WINDOW):
    """A window frame inside the opening of ``quads()`` (the wall y = 0): four bars ``width`` m wide round its rim
    and, with ``mullion``, one up its middle, each ``depth`` m deep, half in front of the wall's plane and half
    behind it. A list of (lo, hi) corners of boxes (``box_triangles``)."""
    x0, x1, z0, z1 = window
    y0, y1 = -0.5 * depth, 0.5 * depth
    boxes = [((x0, y0, z0), (x1, y1, z0 + width)), ((x0, y0, z1 - width), (x1, y1, z1)),
             ((x0, y0, z0 + width), (x0 + width, y1, z1 - width)), ((x1 - width, y0, z0 + width), (x1, y1, z1 - width))]
    if mullion:
        xm = 0.5 * (x0 + x1)
        boxes.append(((xm - 0.5 * width, y0, z0 + width), (xm + 0.5 * width, y1, z1 - width)))
    return boxes


def build_boxes_objects(scene, boxes, name="frame", rho=0.5):
    """One mesh object per box of ``boxes`` ((lo, hi) corners), a Diffuse BSDF of reflectance ``rho``."""
    import bpy

    material = diffuse_material(name, rho)
    for k, (lo, hi) in enumerate(boxes):
        me = bpy.data.meshes.new(f"{name} {k}")
        me.from_pydata([tuple(v) for v in box_triangles(lo, hi).reshape(-1, 3)], [],
                       [(3 * j, 3 * j + 1, 3 * j + 2) for j in range(12)])
        me.materials.append(material)
        scene.collection.objects.link(bpy.data.objects.new(f"{name} {k}", me))


def box_room_boxes(t=0.1, hx=2.0, hy=2.0, h=3.0, w=1.0, sill=0.9, head=2.1):
    """The demo's daylit room (demo/daylight.py) as its boxes [(lo, hi)]: floor, roof and walls ``t`` m thick
    round a 2 hx x 2 hy x h m inside, a 2 w wide window from ``sill`` to ``head`` in the wall y = -hy."""
    y0, y1 = -hy - t, -hy
    return [((-hx - t, -hy - t, -t), (hx + t, hy + t, 0.0)), ((-hx - t, -hy - t, h), (hx + t, hy + t, h + t)),
            ((-hx - t, hy, 0.0), (hx + t, hy + t, h)), ((hx, -hy, 0.0), (hx + t, hy, h)),
            ((-hx - t, -hy, 0.0), (-hx, hy, h)), ((-hx - t, y0, 0.0), (hx + t, y1, sill)),
            ((-hx - t, y0, head), (hx + t, y1, h)), ((-hx - t, y0, sill), (-w, y1, head)),
            ((w, y0, sill), (hx + t, y1, head))]


def obstruction_quads(gap=4.0, width=10.0, height=6.0, thick=1.0, x_mid=W / 2):
    """An opaque block outside facing the window wall y = 0: its near face (parallel to the wall) ``gap`` m in
    front of it, ``width`` x ``height`` x ``thick`` m, centred on x_mid, standing on the ground (z = 0); its 5
    visible faces (the bottom lies on the ground), outward normals, named ``obstruction``."""
    x0, x1 = x_mid - width / 2, x_mid + width / 2
    y1, y0 = -gap, -gap - thick
    h = height
    return [("obstruction", [(x0, y1, 0), (x0, y1, h), (x1, y1, h), (x1, y1, 0)]),   # +y, facing the window
            ("obstruction", [(x0, y0, 0), (x1, y0, 0), (x1, y0, h), (x0, y0, h)]),   # -y
            ("obstruction", [(x0, y0, h), (x1, y0, h), (x1, y1, h), (x0, y1, h)]),   # +z, the top
            ("obstruction", [(x0, y0, 0), (x0, y0, h), (x0, y1, h), (x0, y1, 0)]),   # -x
            ("obstruction", [(x1, y0, 0), (x1, y1, 0), (x1, y1, h), (x1, y0, h)])]   # +x


ROOF_TILT = 30.0  # degrees: the roof's slope, rising from the wall y = 0 towards y = D


def roof_frame(W=4.0, D=4.0, H=3.0, tilt=ROOF_TILT):  # noqa: N803 - as quads()
    """The sloped ceiling's plane: origin (0, 0, H), u along x, s up the slope (m), outward normal n."""
    t = np.radians(tilt)
    s = np.array([0.0, np.cos(t), np.sin(t)])
    return np.array([0.0, 0.0, H]), np.array([1.0, 0.0, 0.0]), s, np.array([0.0, -np.sin(t), np.cos(t)])


def roof_opening(W=4.0, D=4.0, H=3.0, tilt=ROOF_TILT, size=1.0):  # noqa: N803 - as quads()
    """The 1 x 1 m opening in the sloped ceiling, centred on the roof: 4 corners counter-clockwise seen from
    outside (x0 s0, x1 s0, x1 s1, x0 s1) and its outward normal."""
    o, u, s, n = roof_frame(W, D, H, tilt)
    L = D / np.cos(np.radians(tilt))
    x0, x1, s0, s1 = (W - size) / 2, (W + size) / 2, (L - size) / 2, (L + size) / 2
    return [tuple(map(float, o + a * u + b * s)) for a, b in ((x0, s0), (x1, s0), (x1, s1), (x0, s1))], n


def roof_quads(W=4.0, D=4.0, H=3.0, tilt=ROOF_TILT, size=1.0):  # noqa: N803 - as quads()
    """A closed room W x D, its ceiling a mono-pitch roof tilted ``tilt`` degrees (H m high at y = 0, rising to
    y = D), holding a ``size`` x ``size`` m opening (``roof_opening``): the sloped ceiling as 4 quads around the
    hole, thin like ``quads()``; the side walls trapezoids."""
    o, u, s, n = roof_frame(W, D, H, tilt)
    L = D / np.cos(np.radians(tilt))
    x0, x1, s0, s1 = (W - size) / 2, (W + size) / 2, (L - size) / 2, (L + size) / 2
    Ht = H + D * np.tan(np.radians(tilt))

    def r(a, b):
        return tuple(float(c) for c in o + a * u + b * s)

    return [("floor", [(0, 0, 0), (W, 0, 0), (W, D, 0), (0, D, 0)]),
            ("ceiling", [r(0, 0), r(0, s0), r(W, s0), r(W, 0)]),
            ("ceiling", [r(0, s1), r(0, L), r(W, L), r(W, s1)]),
            ("ceiling", [r(0, s0), r(0, s1), r(x0, s1), r(x0, s0)]),
            ("ceiling", [r(x1, s0), r(x1, s1), r(W, s1), r(W, s0)]),
            ("walls", [(0, 0, 0), (0, 0, H), (W, 0, H), (W, 0, 0)]),
            ("walls", [(0, D, 0), (W, D, 0), (W, D, Ht), (0, D, Ht)]),
            ("walls", [(0, 0, 0), (0, D, 0), (0, D, Ht), (0, 0, H)]),
            ("walls", [(W, 0, 0), (W, 0, H), (W, D, Ht), (W, D, 0)])]


def slab_quads(rect, normal, thick):
    """A slab over a planar rectangle (corners counter-clockwise seen from outside, ``normal`` outward): from
    the rectangle to ``thick`` m outside it; its 6 faces, outward normals."""
    a = [np.asarray(p, float) for p in rect]
    b = [p + thick * np.asarray(normal, float) for p in a]
    t = lambda v: tuple(float(c) for c in v)  # noqa: E731
    return [[t(p) for p in b],                                    # outside face
            [t(p) for p in a[::-1]],                              # room side
            *[[t(a[i]), t(a[(i + 1) % 4]), t(b[(i + 1) % 4]), t(b[i])] for i in range(4)]]


def roof_pane():
    """The roof opening's 6 mm pane (outside the roof plane, tilted with it): its 6 faces for the solid and its
    mid-plane polygon for Radiance's thin ``glass``."""
    rect, n = roof_opening()
    mid = [tuple(float(c) for c in np.asarray(p) + 0.5 * PANE * n) for p in rect]
    return slab_quads(rect, n, PANE), mid


PANE = 0.006  # m: a 6 mm clear pane filling the opening, outside the wall plane (y from -PANE to 0)
IOR = 1.52


def pane_quads():
    """The pane's 6 faces, outward normals (counter-clockwise seen from outside)."""
    x0, x1, z0, z1 = WINDOW
    y0, y1 = -PANE, 0.0
    return [[(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)],   # -y (outside face)
            [(x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0)],   # +y (room side)
            [(x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)],   # -x
            [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)],   # +x
            [(x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0)],   # -z
            [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]]   # +z


def add_pane_blender(scene, pane=None):
    """A solid 6 mm pane of Glass BSDF (roughness 0, IOR 1.52, white) in the opening (``pane``: its faces,
    default ``pane_quads()``)."""
    import bpy

    from radiometer.compat import ensure_node_tree

    verts, faces = [], []
    for q in (pane if pane is not None else pane_quads()):
        faces.append(tuple(range(len(verts), len(verts) + 4)))
        verts += q
    me = bpy.data.meshes.new("pane")
    me.from_pydata(verts, [], faces)

    m = bpy.data.materials.new("glass")
    t = ensure_node_tree(m)
    t.nodes.clear()
    out = t.nodes.new("ShaderNodeOutputMaterial")
    g = t.nodes.new("ShaderNodeBsdfGlass")
    g.inputs["Roughness"].default_value = 0.0
    g.inputs["IOR"].default_value = IOR
    g.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    t.links.new(g.outputs[0], out.inputs[0])
    me.materials.append(m)
    ob = bpy.data.objects.new("pane", me)
    scene.collection.objects.link(ob)
    return ob


def boxes_room_boxes(t=0.2, W=4.0, D=5.0, H=2.8, window=(1.0, 3.0, 0.9, 2.2), mullion=None):  # noqa: N803
    """A W x D x H room built as a user builds one in Blender: nine separate boxes [(lo, hi)] that touch (floor,
    roof, three walls, the window wall as four boxes round a window x0..x1, z0..z1 in the wall y in [-t, 0]);
    no single closed surface. ``mullion``: (x0, x1) a post splitting the window."""
    x0, x1, z0, z1 = window
    boxes = [((-t, -t, -t), (W + t, D + t, 0.0)), ((-t, -t, H), (W + t, D + t, H + t)), ((-t, 0.0, 0.0), (0.0, D, H)),
             ((W, 0.0, 0.0), (W + t, D, H)), ((-t, D, 0.0), (W + t, D + t, H)), ((-t, -t, 0.0), (x0, 0.0, H)),
             ((x1, -t, 0.0), (W + t, 0.0, H)), ((x0, -t, 0.0), (x1, 0.0, z0)), ((x0, -t, z1), (x1, 0.0, H))]
    if mullion is not None:
        boxes.append(((mullion[0], -t, z0), (mullion[1], 0.0, z1)))
    return boxes


def boxes_quads(boxes):
    """``boxes_room_boxes`` as named quads (``build_blender``, ``radiance_daylight_factor``): each box's 6 faces,
    outward normals; the floor box "floor", the roof box "ceiling", the rest "walls"."""
    out = []
    for k, ((x0, y0, z0), (x1, y1, z1)) in enumerate(boxes):
        v = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (x0, y0, z1), (x1, y0, z1), (x1, y1, z1),
             (x0, y1, z1)]
        name = "floor" if k == 0 else "ceiling" if k == 1 else "walls"
        out += [(name, [v[i] for i in f]) for f in ((0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6),
                                                     (3, 0, 4, 7))]
    return out


def boxes_pane(window=(1.0, 3.0, 0.9, 2.2)):
    """A 6 mm pane at the room side of the boxes room's window (y from -PANE to 0, touching the reveals): its 6
    faces for the solid and its mid-plane polygon for Radiance's thin ``glass``."""
    x0, x1, z0, z1 = window
    rect = [(x0, 0.0, z0), (x1, 0.0, z0), (x1, 0.0, z1), (x0, 0.0, z1)]  # counter-clockwise seen from outside (-y)
    n = np.array([0.0, -1.0, 0.0])
    mid = [tuple(float(c) for c in np.asarray(p) + 0.5 * PANE * n) for p in rect]
    return slab_quads(rect, n, PANE), mid


def build_boxes_blender(scene, boxes):
    """``boxes_room_boxes`` as separate objects, each a closed box with a Diffuse BSDF: the floor RHO["floor"],
    the roof RHO["ceiling"], the rest RHO["walls"]."""
    import bpy

    mats = {name: diffuse_material(name, RHO[name]) for name in RHO}
    out = []
    for k, ((x0, y0, z0), (x1, y1, z1)) in enumerate(boxes):
        me = bpy.data.meshes.new(f"box {k}")
        v = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0), (x0, y0, z1), (x1, y0, z1), (x1, y1, z1),
             (x0, y1, z1)]
        me.from_pydata(v, [], [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)])
        me.materials.append(mats["floor" if k == 0 else "ceiling" if k == 1 else "walls"])
        ob = bpy.data.objects.new(f"box {k}", me)
        scene.collection.objects.link(ob)
        out.append(ob)
    return out


def build_solid_blender(scene, boxes):
    """``boxes_room_boxes`` joined into one closed solid (a Boolean union, each box's material kept): walls, floor
    and roof with depth as one mesh whose window is a tunnel through it, as a solidified or imported room is. The
    room's air lies outside that closed shell. Returns the object."""
    import bmesh
    import bpy

    parts = build_boxes_blender(scene, boxes)
    base = parts[0]
    for k, other in enumerate(parts[1:]):
        mod = base.modifiers.new(f"union {k}", "BOOLEAN")
        mod.operation, mod.solver, mod.object = "UNION", "EXACT", other
        mod.material_mode = "TRANSFER"
    depsgraph = bpy.context.evaluated_depsgraph_get()
    me = bpy.data.meshes.new_from_object(base.evaluated_get(depsgraph), preserve_all_data_layers=True,
                                         depsgraph=depsgraph)
    bm = bmesh.new()
    bm.from_mesh(me)
    bmesh.ops.remove_doubles(bm, verts=bm.verts, dist=1e-6)
    bm.to_mesh(me)
    bm.free()
    for ob in parts:
        old = ob.data
        bpy.data.objects.remove(ob)
        bpy.data.meshes.remove(old)
    me.name = "room solid"
    solid = bpy.data.objects.new("room solid", me)
    scene.collection.objects.link(solid)
    return solid


def diffuse_material(name, rho):
    """A new material ``name``: a Diffuse BSDF of grey reflectance ``rho`` (the package's scene builder)."""
    from radiometer.demo.builders import diffuse_material as builder

    return builder(name, rho)


def build_blender(scene, room_quads=None):
    """The room's quads (default ``quads()``) as one mesh with a Diffuse BSDF per name in RHO."""
    import bpy

    room_quads = room_quads if room_quads is not None else quads()
    order = list(RHO) + sorted({name for name, _ in room_quads} - set(RHO))
    rho = {**RHO_EXTRA, **RHO}
    me = bpy.data.meshes.new("room")
    verts, faces, index = [], [], []
    for name, q in room_quads:
        faces.append(tuple(range(len(verts), len(verts) + 4)))
        verts += q
        index.append(order.index(name))
    me.from_pydata(verts, [], faces)
    for name in order:
        me.materials.append(diffuse_material(name, rho[name]))
    for poly, k in zip(me.polygons, index):
        poly.material_index = k
    ob = bpy.data.objects.new("room", me)
    scene.collection.objects.link(ob)
    return ob


def radiance_bin():
    import pyradiance

    root = os.path.dirname(pyradiance.__file__)
    return os.path.join(root, "bin"), os.path.join(root, "lib")


def radiance_daylight_factor(folder, points, normals=(0, 0, 1), samples=150_000, ground_reflectance=0.2, seed=1,
                             glass=False, cache=False, room_quads=None, pane=None):
    """DF (%) and its relative standard error per point, from ``rtrace -I`` used as a path tracer:
    -aa 0 (no ambient cache), -ad 1 -as 0 (one hemisphere ray per input line), -ab 32 -lr 64 -lw 1e-9,
    -u+ (uncorrelated sampling), each point repeated ``samples`` times; the mean and its standard
    error over the repeats. The sky: a brightfunc glow source over the whole sphere, L/Lz =
    (1 + 2 Dz) / 3 above the horizon and the ground rho x 7/9 below it (sharp horizon; gensky's
    blended ground glow is NOT used). DF = 100 E / (7 pi / 9), the overcast sky's E_h for Lz = 1.
    ``glass``: the 6 mm pane as a closed box of Radiance ``dielectric`` (n = 1.52, no absorption,
    outward normals), the same solid as the Blender pane (not Radiance's thin ``glass``). NOTE: Radiance's
    dielectric averages the Fresnel reflectance over s and p at each interface (src/rt/dielectric.c), so its
    slab passes less at oblique incidence than a slab whose polarisations are followed apart (1.3 % less
    sky at (2, 0.4, 0.85); bench/coverage_daylight_emitters.md). ``glass="thin"``: Radiance's thin ``glass``
    instead (one polygon in the pane's mid-plane, transmissivity 1, n = 1.52: s and p summed separately
    over the internal reflections, no lateral shift; the thin-pane model Radiometer measures with).
    ``room_quads``: the room's named quads (default ``quads()``), as ``build_blender`` takes them; a name not in
    RHO takes its reflectance from RHO_EXTRA (e.g. ``obstruction``). ``pane``: (its 6 faces, its mid-plane
    polygon) for a pane elsewhere than the window (``roof_pane()``), default ``pane_quads()`` and the window's
    mid-plane. ``cache``
    (the tests; never the benches, which time rtrace and want fresh draws): Radiance's answer on the same
    scene.rad, sky.cal, rays and command comes from the committed cache when it has one
    (tests/bpy/radiance_run.py; RADIOMETER_RADIANCE_RERUN=1 runs rtrace every time)."""
    bindir, libdir = radiance_bin()
    env = dict(os.environ, PATH=bindir + os.pathsep + os.environ.get("PATH", ""),
               RAYPATH=os.pathsep.join([folder, libdir]))
    with open(os.path.join(folder, "sky.cal"), "w") as f:
        f.write(f"skybr = if(Dz, (1 + 2*Dz)/3, {ground_reflectance!r}*7/9);\n")
    lines = ["void brightfunc skyfunc\n2 skybr sky.cal\n0\n0\n", "skyfunc glow skyglow\n0\n0\n4 1 1 1 0\n",
             "skyglow source sky\n0\n0\n4 0 0 1 360\n"]
    room_quads = room_quads if room_quads is not None else quads()
    for name, r in RHO.items():
        lines.append(f"void plastic {name}\n0\n0\n5 {r} {r} {r} 0 0\n")
    for name in sorted({name for name, _ in room_quads} - set(RHO)):  # only where used: other scenes unchanged
        r = RHO_EXTRA[name]
        lines.append(f"void plastic {name}\n0\n0\n5 {r} {r} {r} 0 0\n")
    for k, (name, q) in enumerate(room_quads):
        lines.append(f"{name} polygon p{k}\n0\n0\n12 " + " ".join(f"{c:g}" for v in q for c in v) + "\n")
    if glass == "thin":
        x0, x1, z0, z1 = WINDOW
        y = -PANE / 2
        lines.append(f"void glass pane_glass\n0\n0\n4 1 1 1 {IOR}\n")
        q = [(x0, y, z0), (x1, y, z0), (x1, y, z1), (x0, y, z1)] if pane is None else pane[1]
        lines.append("pane_glass polygon g0\n0\n0\n12 " + " ".join(f"{c:g}" for v in q for c in v) + "\n")
    elif glass:
        lines.append(f"void dielectric pane_glass\n0\n0\n5 1 1 1 {IOR} 0\n")
        for k, q in enumerate(pane_quads() if pane is None else pane[0]):
            lines.append(f"pane_glass polygon g{k}\n0\n0\n12 " + " ".join(f"{c:g}" for v in q for c in v) + "\n")
    with open(os.path.join(folder, "scene.rad"), "w") as f:
        f.write("".join(lines))
    normals = np.broadcast_to(np.asarray(normals, float), (len(points), 3))
    sensors = [f"{p[0]} {p[1]} {p[2]} {n[0]} {n[1]} {n[2]}\n" for p, n in zip(points, normals)]
    command = ["rtrace", "-h", "-I", "-ab", "32", "-aa", "0", "-ad", "1", "-as", "0", "-lw", "1e-9", "-lr", "64",
               "-u+", "scene.oct"]

    def run():
        with open(os.path.join(folder, "scene.oct"), "wb") as f:
            subprocess.run(["oconv", "scene.rad"], cwd=folder, env=env, stdout=f, check=True)
        rays = "".join(line * samples for line in sensors)
        out = subprocess.run(command, cwd=folder, env=env, input=rays, capture_output=True, text=True, check=True)
        y = np.array(out.stdout.split(), float).reshape(len(points), samples, 3)[..., 1]  # equal RGB: channel G
        return {"mean": y.mean(axis=1).tolist(), "std": y.std(axis=1, ddof=1).tolist()}

    if not cache:
        return _df(run(), samples)
    # Radiance's answer on these same files and rays is cached (tests/bpy/radiance_run.py: cached_radiance)
    inputs = {name: open(os.path.join(folder, name), "rb").read() for name in ("scene.rad", "sky.cal")}
    params = {"function": "radiance_daylight_factor", "oconv": ["oconv", "scene.rad"], "rtrace": command,
              "sensors": sensors, "samples": samples}
    return _df(_radiance_run().cached_radiance("tests/bpy/daylight_room.py radiance_daylight_factor", env, inputs,
                                               params, run), samples)


def _df(result, samples):
    """DF (%) and its relative standard error from rtrace's mean and standard deviation per point."""
    mean, std = np.array(result["mean"], float), np.array(result["std"], float)
    return 100.0 * mean / (7 * np.pi / 9), std / np.sqrt(samples) / mean


def _radiance_run():
    """tests/bpy/radiance_run.py by its path (this file is also loaded by path and run as a script)."""
    import importlib.util

    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "radiance_run.py")
    spec = importlib.util.spec_from_file_location("radiance_run", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
