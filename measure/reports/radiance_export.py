"""Export the scene for Radiance: what a Radiance or Honeybee user runs to check Radiometer's numbers.

Read from the meter's own capture (``capture.scene_capture``: the triangles Cycles renders, in metres,
with their material slots, the thin panes and the lights as emitters), the world as the meter reads
it (``capture.world_capture``), the meters and the work planes' grids (``analyses.grid``) and the
cameras. Written by the pure writers ``radiometry.scene.radiance_format`` and
``radiometry.skies.radiance_sky``; all files together or none (``outputs.FileSet``). The scene is only
read (the capture's probe render runs inside the scene guard).

Files (``OUT/``): scene.rad (materials, geometry, panes, electric lights), sky.rad (+ radiometer_sky.cal)
the scene's world exactly and its sun lights, sky_gensky.rad the nearest gensky line when one exists,
sky_overcast.rad (+ radiometer_overcast.cal) the CIE overcast sky of the daylight factor (E_h 10 000 lx:
DF in % = 179 x rtrace -I's Y / 100), one .pts per work plane and meters.pts, one .vf per camera,
a ``<light>.dat`` intensity table per IES light, README.txt (how to run it, and one line per thing not mapped)
and radiance_export.json (the manifest). docs/radiance-export.md has the mapping and the measured agreement.
"""

import json
import math
import os

import bpy
import numpy as np

from ... import outputs
from ...errors import RadiometerError
from ...radiometry.scene import radiance_format as rad
from ...radiometry.skies import cie_sky, radiance_sky
from ..analyses import grid
from ..blender.identity import geometry_objects
from ..capture.world_capture import CIE_SKY_TAG
from ..meter import point_meter

MANIFEST = "radiance_export.json"
#: The daylight factor's sky (CIE overcast, the E_h of ``cie_sky.TYPICAL_HORIZONTAL_ILLUMINANCE``).
DF_HORIZONTAL_LUX = 10_000.0
#: Radius (m) of the sphere that stands in for a Cycles point or spot light of radius 0.
POINT_RADIUS_M = 0.005
#: Sides of the equal-area polygon standing in for a disk or ellipse area light.
DISK_SIDES = 64
#: Cycles' surface where an object has no material: grey diffuse 0.8.
DEFAULT_GREY = 0.8
#: What an unmapped surface is written as (and said so in the README): grey plastic of this reflectance.
UNMAPPED_GREY = 0.5
#: Radiance's default sun disc where Cycles' sun has angle 0 (a delta): the sun's mean angular diameter.
SUN_ANGLE_DEG = 0.533

#: rtrace's ambient parameters in README.txt: in the side-lit room behind a 6 mm pane they read the daylight factor
#: within 0.6 % of the path tracer of the tests (4.699 / 6.345 / 4.738 % against 4.724 / 6.347 / 4.709 %);
#: -ab 5 -ad 1024 -as 512 -aa 0.1 -ar 256 -lw 1e-4 read 3.3 % low at the back (measured, docs/radiance-export.md).
RTRACE_PARAMETERS = "-ab 6 -ad 2048 -as 1024 -aa 0.05 -ar 512 -lw 1e-5"


class _Export:
    """What the export gathers before anything is written: file texts and the README's lines."""

    def __init__(self):
        self.files = {}
        self.unmapped = []
        self.notes = []
        self.taken = set()
        self.summary = {}

    def name(self, text):
        return rad.identifier(text, self.taken)


# --- materials -----------------------------------------------------------------------------------------

def _linked(node, *names):
    return any(node.inputs.get(n) is not None and node.inputs[n].is_linked for n in names)


def _value(node, name, default=0.0):
    socket = node.inputs.get(name)
    return default if socket is None else socket.default_value


def _surface_node(material):
    from ...compat import active_node_tree

    tree = active_node_tree(material)
    if tree is None:
        return None
    outputs_ = [n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputMaterial" and not n.mute]
    active = [n for n in outputs_ if n.is_active_output] or outputs_
    surface = active[0].inputs.get("Surface") if active else None
    if surface is None or not surface.is_linked:
        return None
    node = surface.links[0].from_node
    while node.bl_idname == "NodeReroute" and node.inputs[0].is_linked:
        node = node.inputs[0].links[0].from_node
    return node


def material_primitive(material, name):
    """(Radiance primitive text, reason or "") for a Blender material: Diffuse BSDF -> plastic; Principled
    BSDF -> plastic (dielectric: diffuse = Base Color, specular = Fresnel at normal incidence of its IOR,
    roughness alpha = roughness^2) or metal (Metallic 1); Glossy / Metallic BSDF -> metal. Anything else
    (linked inputs, mixes, other closures) is written as grey plastic and the reason returned."""
    if material is None:
        return rad.plastic(name, DEFAULT_GREY), ""
    node = _surface_node(material)
    kind = node.bl_idname if node is not None else None
    unmapped = rad.plastic(name, UNMAPPED_GREY)
    grey = f"; written as grey plastic {UNMAPPED_GREY:g}"
    if kind == "ShaderNodeBsdfDiffuse":
        if _linked(node, "Color"):
            return unmapped, "Diffuse BSDF with a linked Color (texture)" + grey
        why = "" if float(_value(node, "Roughness", 0.0)) == 0.0 else "Oren-Nayar roughness dropped (Lambertian)"
        return rad.plastic(name, np.clip(_value(node, "Color")[:3], 0, 1)), why
    if kind == "ShaderNodeBsdfPrincipled":
        if _linked(node, "Base Color", "Metallic", "Roughness", "IOR"):
            return unmapped, "Principled BSDF with linked inputs (textures)" + grey
        base = np.clip(_value(node, "Base Color")[:3], 0, 1)
        metallic = float(_value(node, "Metallic", 0.0))
        alpha = float(_value(node, "Roughness", 0.5)) ** 2
        why = ""
        for extra in ("Transmission Weight", "Coat Weight", "Sheen Weight", "Subsurface Weight"):
            if float(_value(node, extra, 0.0)) != 0.0:
                why = f"Principled BSDF {extra} {float(_value(node, extra)):g} dropped"
        if metallic >= 0.5:
            if metallic != 1.0:
                why = why or f"Metallic {metallic:g} written as metal"
            return rad.metal(name, base, 1.0, alpha), why
        if metallic != 0.0:
            why = why or f"Metallic {metallic:g} written as plastic"
        ior = float(_value(node, "IOR", 1.5))
        level = float(_value(node, "Specular IOR Level", 0.5))
        f0 = min(1.0, ((ior - 1) / (ior + 1)) ** 2 * 2.0 * level)
        return rad.plastic(name, base, f0, alpha), why
    if kind in ("ShaderNodeBsdfGlossy", "ShaderNodeBsdfAnisotropic"):
        if _linked(node, "Color", "Roughness"):
            return unmapped, "Glossy BSDF with linked inputs" + grey
        return rad.metal(name, np.clip(_value(node, "Color")[:3], 0, 1), 1.0, float(_value(node, "Roughness")) ** 2), ""
    if kind == "ShaderNodeBsdfMetallic":
        if _linked(node, "Base Color", "Roughness"):
            return unmapped, "Metallic BSDF with linked inputs" + grey
        return rad.metal(name, np.clip(_value(node, "Base Color")[:3], 0, 1), 1.0,
                         float(_value(node, "Roughness", 0.5)) ** 2), ""
    return unmapped, f"shader {kind or 'with no surface'} has no Radiance counterpart here" + grey


def _geometry(ex, scene, model):
    """scene.rad's materials, opaque triangles and panes."""
    g = model.geometry
    parts = ["# Radiometer Radiance export: materials and geometry (metres)\n"]
    if not g.count:
        ex.notes.append("the scene has no render-visible geometry")
    objects = geometry_objects(g)
    slots = g.material_slot if g.material_slot is not None else np.zeros(g.count, int)
    pane = np.asarray(g.pane_of, int)
    emissive = np.asarray(g.emissive, bool) if len(g.emissive) == g.count else np.zeros(g.count, bool)
    opaque = np.asarray(g.opaque, bool) if len(g.opaque) == g.count else np.ones(g.count, bool)
    refractors = {name: why for name, why in model.refractors}
    materials = {}  # material pointer -> identifier
    ranges = g.object_ranges()
    written = 0
    for k, obj_name in enumerate(g.object_names):
        part = slice(*ranges[k]) if ranges is not None else np.flatnonzero(g.object_index == k)
        tris, slot = g.triangles[part], slots[part]
        keep = (pane[part] < 0) & ~emissive[part]
        if not opaque[part][keep].all():
            why = refractors.get(obj_name, "transmissive surface that is not a thin pane")
            ex.unmapped.append(f"{obj_name}: {why}; not exported (Radiance would need its solid as dielectric)")
            keep &= opaque[part]
        if not g.reflects[k]:
            ex.unmapped.append(f"{obj_name}: sends no light in Cycles (invisible to diffuse, glossy and transmission "
                               "rays, or black: a Diffuse BSDF of colour 0); exported as an ordinary surface")
        obj = objects[k] if k < len(objects) else None
        obj_id = ex.name(obj_name)
        for j in np.unique(slot[keep]):
            material = None
            if obj is not None and 0 <= j < len(obj.material_slots):
                material = obj.material_slots[j].material
            key = material.as_pointer() if material is not None else 0
            if key not in materials:
                label = material.name if material is not None else "default_grey"
                materials[key] = ex.name(label)
                text, why = material_primitive(material, materials[key])
                parts.append(text)
                if why:
                    ex.unmapped.append(f"{label} (material): {why}")
            sel = keep & (slot == j)
            parts.append(rad.triangles(materials[key], f"{obj_id}.{j}", tris[sel]))
            written += int(sel.sum())
    for k, p in model.panes.items():
        gm = p.geometry
        t, _r, _a = p.optics(1.0)
        mat = ex.name(f"{p.name}_glass")
        parts.append(rad.glass(mat, np.clip(t, 0, 1), p.ior))
        h = 0.5 * (min(gm.heights) + max(gm.heights))
        verts = gm.origin + gm.hull[:, :1] * gm.u + gm.hull[:, 1:] * gm.v
        verts = verts + (h - verts @ gm.normal)[:, None] * gm.normal
        parts.append(rad.polygon(mat, ex.name(f"{p.name}_pane"), verts))
        tn = rad.glass_transmissivity(np.clip(t, 0, 1), p.ior)
        ex.notes.append(f"pane {p.name}: {p.model}; normal transmittance {float(np.mean(t)):.4f} -> Radiance glass "
                        f"transmissivity {float(np.mean(tn)):.4f}, one polygon at the pane's mid-plane")
        if p.trick:
            ex.unmapped.append(f"{p.name}: the 'Is Shadow Ray -> Transparent' glass trick lets Cycles' direct light "
                               "through unfiltered; Radiance's glass filters it")
        if abs(p.ior - 1.52) > 1e-6:
            ex.notes.append(f"pane {p.name}: index {p.ior:g} written as glass's 4th argument")
    ex.summary["triangles"] = written
    ex.summary["materials"] = len(materials)
    ex.summary["panes"] = len(model.panes)
    for name in g.unmodelled:
        ex.unmapped.append(f"{name}: geometry the capture does not triangulate; not exported")
    for name, *_box in model.volumes:
        ex.unmapped.append(f"{name}: participating medium (volume); not exported")
    return parts


# --- lights --------------------------------------------------------------------------------------------

def _lights(ex, scene, model, efficacy):
    """scene.rad's electric lights and emitting surfaces; sky.rad's suns (returned apart)."""
    parts, suns = [], []
    for lt in model.lights:
        spec = lt.spec
        if lt.portal:
            ex.notes.append(f"{lt.name}: a light portal (guides Cycles' world sampling, emits nothing); not exported")
            continue
        if spec is None:
            ex.unmapped.append(f"{lt.name}: light not modelled ({lt.uncovered or 'no closed form'}); not exported")
            continue
        if not lt.casts_shadow or not lt.reaches_diffuse:
            ex.unmapped.append(f"{lt.name}: shadow or diffuse-ray visibility switched off in Cycles; exported as a "
                               "plain light")
        ident = ex.name(lt.name)
        mat = ex.name(f"{lt.name}_mat")
        power = np.asarray(spec.rgb_power, float)
        shape = spec.luminous_shape()
        if shape == "distant":
            angle = math.degrees(spec.angle) if spec.angle > 0 else SUN_ANGLE_DEG
            if spec.angle == 0:
                ex.notes.append(f"{lt.name}: a sun of angle 0 written as a {SUN_ANGLE_DEG} deg disc (same irradiance)")
            radiance = rad.to_radiance_units(rad.distant_radiance(power, math.radians(angle)), efficacy)
            suns.append(rad.light(mat, radiance)
                        + rad.source(mat, ident, -spec.emission_direction, angle))
            continue
        if getattr(spec, "intensity_table", None) is not None:
            parts.append(_photometric(ex, lt, spec, ident, mat, efficacy))
            continue
        if shape == "sphere":
            r = spec.radius if spec.radius > 0 else POINT_RADIUS_M
            intensity = power / (4.0 * math.pi)  # W/sr: Cycles' point and spot (on the cone's axis)
            radiance = rad.to_radiance_units(rad.sphere_light_radiance(intensity, r), efficacy)
            if spec.has_cone:
                parts.append(rad.spotlight(mat, radiance, math.degrees(spec.spot_size),
                                           spec.emission_direction, focus=0.01 * r))
                if spec.spot_blend > 0:
                    ex.unmapped.append(f"{lt.name}: spot blend {spec.spot_blend:g} dropped (Radiance's spotlight has "
                                       "a hard edge)")
            else:
                parts.append(rad.light(mat, radiance))
            parts.append(rad.sphere(mat, ident, spec.position, r))
            if spec.radius == 0:
                ex.notes.append(f"{lt.name}: a point of radius 0 written as a sphere of {1000 * POINT_RADIUS_M:g} mm")
            continue
        if shape in ("round", "polygon"):
            eu, ev = spec.edges
            round_ = shape == "round"
            if round_ and abs(np.linalg.norm(eu) - np.linalg.norm(ev)) < 1e-9 * np.linalg.norm(eu) \
                    and abs(np.dot(eu, ev)) < 1e-9 * np.dot(eu, eu):  # a circle: Radiance's ring
                radius = 0.5 * float(np.linalg.norm(eu))
                radiance = rad.to_radiance_units(np.asarray(spec.power_w(), float) / (math.pi * math.pi * radius**2),
                                                 efficacy)
                parts.append(rad.light(mat, radiance) + rad.ring(mat, ident, spec.position, spec.emission_direction,
                                                                  radius))
                _spread_note(ex, lt, spec)
                continue
            if round_:
                ex.notes.append(f"{lt.name}: an ellipse written as an equal-area {DISK_SIDES}-gon (Radiance samples "
                                "a many-sided polygon source less exactly than a ring)")
                kk = math.sqrt((2 * math.pi / DISK_SIDES) / math.sin(2 * math.pi / DISK_SIDES))  # equal area
                phi = np.arange(DISK_SIDES) * (2 * math.pi / DISK_SIDES)
                ab = 0.5 * kk * np.stack([np.cos(phi), np.sin(phi)], axis=1)
                area = math.pi / 4 * float(np.linalg.norm(np.cross(eu, ev)))
            else:
                ab = np.array([[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]])
                area = float(np.linalg.norm(np.cross(eu, ev)))
            verts = spec.position + ab[:, :1] * eu + ab[:, 1:] * ev
            if np.dot(np.cross(eu, ev), spec.emission_direction) < 0:
                verts = verts[::-1]  # counter-clockwise seen from the side it lights
            radiance = rad.to_radiance_units(np.asarray(spec.power_w(), float) / (math.pi * area), efficacy)
            parts.append(rad.light(mat, radiance) + rad.polygon(mat, ident, verts))
            _spread_note(ex, lt, spec)
            continue
        ex.unmapped.append(f"{lt.name}: {spec.describe()} not mapped")
    for mesh in model.emissive_meshes:
        if mesh.radiance is None:
            ex.unmapped.append(f"{mesh.name}: emission not a plain value (linked or mixed); not exported")
            continue
        ident = ex.name(mesh.name)
        values = np.unique(mesh.radiance, axis=0)
        for j, value in enumerate(values):
            sel = np.all(mesh.radiance == value, axis=1)
            mat = ex.name(f"{mesh.name}_light{j}")
            parts.append(rad.light(mat, rad.to_radiance_units(value, efficacy)))
            parts.append(rad.triangles(mat, f"{ident}.{j}", mesh.triangles[sel]))
        ex.unmapped.append(f"{mesh.name}: emitting surface written as Radiance light, which emits from the front "
                           "of each face only (Cycles emits from both sides)")
    ex.summary["lights"] = len(model.lights)
    return parts, suns


def _spread_note(ex, lt, spec):
    if spec.spread < math.pi:
        ex.unmapped.append(f"{lt.name}: area light spread {math.degrees(spec.spread):g} deg dropped (written Lambertian)")


def _photometric(ex, lt, spec, ident, mat, efficacy):
    """A photometric (IES) light: its world-space intensity (the emitter's own, Cycles' interpolation of
    the file) tabulated on ies2rad's angles (``source.cal``: src_theta from the nadir, src_phi from +X
    towards +Y, both of the direction leaving the light) into ``<ident>.dat``, read by ``brightdata`` with
    ``corr`` on a 5 mm sphere of ``light`` (a sphere's projected area is pi r^2 from every side, so
    L = I / (pi r^2)). The resampling's error (bilinear on the 1 x 2.5 deg grid against the emitter at the
    cells' centres) goes to the notes."""
    theta = np.linspace(0.0, 180.0, 181)
    phi = np.linspace(0.0, 360.0, 145)
    t, p = np.meshgrid(np.radians(theta), np.radians(phi), indexing="ij")
    dirs = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), -np.cos(t)], axis=-1)
    values = np.asarray(spec.intensity_towards(dirs), float)  # (181, 145, 3) W/sr per channel
    totals = values.reshape(-1, 3).sum(axis=0)
    c = int(np.argmax(totals))
    table = values[..., c]
    colour = totals / totals[c] if totals[c] > 0 else np.ones(3)
    tc, pc = np.radians(theta[:-1] + 0.5), np.radians(phi[:-1] + 1.25)
    tt, pp = np.meshgrid(tc, pc, indexing="ij")
    mid = np.asarray(spec.intensity_towards(np.stack([np.sin(tt) * np.cos(pp), np.sin(tt) * np.sin(pp),
                                                      -np.cos(tt)], axis=-1)), float)[..., c]
    bilinear = 0.25 * (table[:-1, :-1] + table[1:, :-1] + table[:-1, 1:] + table[1:, 1:])
    peak = float(table.max())
    error = float(np.abs(bilinear - mid).max()) / peak if peak > 0 else 0.0
    r = POINT_RADIUS_M
    data = f"2\n0 180 {len(theta)}\n0 360 {len(phi)}\n" + "".join(
        " ".join(f"{v:.7g}" for v in row) + "\n" for row in table)
    ex.files[f"{ident}.dat"] = data
    ex.notes.append(f"{lt.name}: photometric light tabulated from its intensity on 1 x 2.5 deg ({ident}.dat, "
                    f"source.cal's src_theta/src_phi); resampling error <= {100 * error:.2g} % of the peak intensity")
    ex.summary.setdefault("photometric_resampling_error", {})[lt.name] = error
    dist = ex.name(f"{lt.name}_dist")
    multiplier = float(efficacy) / rad.RADIANCE_EFFICACY / (math.pi * r * r)
    return (rad.primitive("void", "brightdata", dist, (multiplier,),
                          ("corr", f"{ident}.dat", "source.cal", "src_theta", "src_phi"))
            + rad.light(mat, colour, modifier=dist) + rad.sphere(mat, ident, spec.position, r))


# --- sky -----------------------------------------------------------------------------------------------

def _sky(ex, request, model, suns, ground_reflectance):
    """sky.rad (+ its .cal), sky_gensky.rad and the daylight factor's overcast sky."""
    scene, scale, efficacy = request.scene, request.scale_length, request.efficacy
    world = model.world
    head = "# Radiometer Radiance export: the scene's world and suns (Radiance watts of 179 lm/W)\n"
    body = ""
    if world is not None and getattr(world, "kind", None) == "cie_sky":
        info = {}
        try:
            info = json.loads(scene.world[CIE_SKY_TAG])
        except (KeyError, TypeError, ValueError):
            pass
        lz = rad.to_radiance_units(world.zenith_radiance / scale**2, efficacy)
        lg = rad.to_radiance_units(world.ground_radiance / scale**2, efficacy)
        ex.files[radiance_sky.SKY_CAL] = radiance_sky.sky_cal(world.sky_type, world.sun_direction, lz, lg)
        body = radiance_sky.sky_rad()
        command = None
        if "horizontal_illuminance_lux" in info:
            command = radiance_sky.gensky_command(world.sky_type, world.sun_direction,
                                                  info["horizontal_illuminance_lux"], info["ground_reflectance"])
        if command is not None:
            ex.files["sky_gensky.rad"] = radiance_sky.gensky_rad(command)
            head += (f"# gensky equivalent (sky_gensky.rad): {command}\n# (gensky blends its ground into the sky "
                     "within ~10 deg of the horizon; the lines below keep Radiometer's sharp horizon)\n")
        else:
            ex.notes.append(f"CIE sky type {world.sky_type}: no gensky sky is this type; sky.rad's brightfunc is exact")
        ex.summary["sky"] = f"CIE sky {world.sky_type}"
    elif world is not None and getattr(world, "kind", None) == "constant":
        value = rad.to_radiance_units(np.asarray(world.radiance, float) / scale**2, efficacy)
        body = rad.glow("sky_glow", value) + rad.source("sky_glow", "sky", (0.0, 0.0, 1.0), 360.0)
        ex.summary["sky"] = "uniform world"
    elif world is not None and getattr(world, "kind", None) == "black" or not model.world_emits:
        ex.notes.append("the world is black: sky.rad holds no sky")
        ex.summary["sky"] = "none"
    else:
        why = getattr(world, "reason", "") or getattr(world, "kind", "")
        ex.unmapped.append(f"world {scene.world.name if scene.world else ''}: {why or 'not modelled'}; not exported "
                           "(use sky_overcast.rad or a gensky/gendaylit sky)")
        ex.summary["sky"] = "not mapped"
    ex.files["sky.rad"] = head + body + "".join(suns)
    lz = cie_sky.zenith_luminance(DF_HORIZONTAL_LUX, "overcast") / rad.RADIANCE_EFFICACY
    lg = cie_sky.ground_luminance(DF_HORIZONTAL_LUX, ground_reflectance) / rad.RADIANCE_EFFICACY
    ex.files["radiometer_overcast.cal"] = radiance_sky.sky_cal("overcast", None, lz, lg)
    command = radiance_sky.gensky_command("overcast", None, DF_HORIZONTAL_LUX, ground_reflectance)
    ex.files["sky_overcast.rad"] = (
        f"# CIE overcast sky for the daylight factor: E_h {DF_HORIZONTAL_LUX:g} lx, ground reflectance "
        f"{ground_reflectance:g}, sharp horizon; DF (%) = 179 x Y / {DF_HORIZONTAL_LUX / 100:g}\n"
        f"# gensky equivalent (blended horizon): {command}\n" + radiance_sky.sky_rad("radiometer_overcast.cal"))


# --- sensors and views ---------------------------------------------------------------------------------

def _sensors(ex, request, resolution, spacing, meter_list):
    scene, scale = request.scene, request.scale_length
    stems = outputs.Stems(["scene", "sky", "sky_gensky", "sky_overcast", "meters", "readme"])
    grids = []
    for obj in grid.work_planes(scene):
        try:
            layout = grid.grid_layout(request, obj, resolution, spacing)
        except RadiometerError as exc:
            ex.unmapped.append(f"{obj.name}: work plane not exported ({exc})")
            continue
        pts = layout.points.reshape(-1, 3) * scale
        name = stems(obj.name) + ".pts"
        ex.files[name] = rad.points(pts, layout.normal)
        grids.append({"plane": obj.name, "file": name, "nx": layout.nx, "ny": layout.ny})
    meters, depsgraph = [], bpy.context.evaluated_depsgraph_get()
    for meter in meter_list or ():
        ob = meter.obj
        if meter.kind != "ILLUMINANCE":
            ex.unmapped.append(f"{ob.name}: {meter.kind.lower()} meter; only illuminance meters go to meters.pts")
            continue
        mw = ob.evaluated_get(depsgraph).matrix_world
        meters.append((ob.name, np.array(mw.translation, float) * scale, np.array(mw.to_3x3().col[2], float)))
    if meters:
        ex.files["meters.pts"] = rad.points([m[1] for m in meters], [m[2] for m in meters])
    ex.summary["grids"] = grids
    ex.summary["meters"] = [m[0] for m in meters]
    return stems


def _views(ex, request, stems):
    scene, scale = request.scene, request.scale_length
    views = []
    cameras = [ob for ob in scene.objects if ob.type == "CAMERA"]
    depsgraph = bpy.context.evaluated_depsgraph_get()
    r = scene.render
    aspect = (r.resolution_x * r.pixel_aspect_x) / max(r.resolution_y * r.pixel_aspect_y, 1e-12)
    for ob in cameras:
        cam = ob.data
        mw = np.array(ob.evaluated_get(depsgraph).matrix_world, float)
        position = mw[:3, 3] * scale
        direction, up = -mw[:3, 2], mw[:3, 1]
        fit = cam.sensor_fit if cam.sensor_fit != "AUTO" else ("HORIZONTAL" if aspect >= 1 else "VERTICAL")
        larger_w = fit == "HORIZONTAL"
        if cam.type == "PERSP":
            size = cam.sensor_width if cam.sensor_fit == "AUTO" else (cam.sensor_width if larger_w else cam.sensor_height)
            half = math.atan(size / (2.0 * cam.lens))
            th, tv = (math.tan(half), math.tan(half) / aspect) if larger_w else (math.tan(half) * aspect, math.tan(half))
            h, v = 2 * math.degrees(math.atan(th)), 2 * math.degrees(math.atan(tv))
            proj = "v"
        elif cam.type == "ORTHO":
            s = cam.ortho_scale * scale
            h, v = (s, s / aspect) if larger_w else (s * aspect, s)
            proj = "l"
        else:
            ex.unmapped.append(f"{ob.name}: {cam.type.lower()} camera; no view written")
            continue
        shift = (cam.shift_x * (1.0 if larger_w else 1.0 / aspect), cam.shift_y * (aspect if larger_w else 1.0))
        name = stems(ob.name) + ".vf"
        ex.files[name] = rad.view(position, direction, up, h, v, proj, shift)
        views.append({"camera": ob.name, "file": name, "active": ob == scene.camera})
    ex.summary["views"] = views


# --- the whole -----------------------------------------------------------------------------------------

def _readme(ex, scene):
    grids = ex.summary.get("grids", [])
    pts = grids[0]["file"] if grids else ("meters.pts" if "meters.pts" in ex.files else "points.pts")
    lines = [
        f"Radiance export of {bpy.data.filepath or 'an unsaved scene'} (scene {scene.name!r}), written by Radiometer.",
        "Lengths in metres; radiance in Radiance watts of 179 lm/W (rtrace -I output x 179 = lux).",
        "",
        "Run (the .cal files must be in the folder or on RAYPATH):",
        "  oconv sky.rad scene.rad > scene.oct",
        f"  rtrace -I+ -h -w {RTRACE_PARAMETERS} scene.oct < {pts} | rcalc -e '$1=179*(.265*$1+.67*$2+.065*$3)'",
        "Daylight factor (%) under the CIE overcast sky:",
        "  oconv sky_overcast.rad scene.rad > df.oct",
        f"  rtrace -I+ -h -w {RTRACE_PARAMETERS} df.oct < {pts} | rcalc -e '$1=179*(.265*$1+.67*$2+.065*$3)/100'",
        "Views: rpict -vf <camera>.vf -ab 5 scene.oct > view.hdr",
        "",
        "Mapping: Diffuse BSDF -> plastic; Principled BSDF -> plastic (specular = Fresnel at its IOR, roughness^2) or "
        "metal (Metallic 1); Glossy/Metallic BSDF -> metal; thin panes -> one glass polygon with the pane's "
        "transmissivity; area lights -> light polygons (disks: rings), point/spot lights -> light/spotlight spheres, "
        "IES lights -> brightdata (source.cal's corr, src_theta, src_phi) on a sphere, suns -> source; emitting "
        "surfaces -> light.",
        "Colour: Radiance weighs R, G, B as .265/.670/.065, Radiometer as the working colour space's Y: grey light "
        "reads the same, coloured light differs.",
        "",
        "Notes:",
    ]
    lines += [f"  {n}" for n in ex.notes] or ["  none"]
    lines += ["", "Not mapped (one line each):"]
    lines += [f"  {u}" for u in ex.unmapped] or ["  nothing"]
    return "\n".join(lines) + "\n"


def export_radiance(out_dir, *, request, resolution=None, spacing=None, ground_reflectance=0.2, meters=None):
    """Write the Radiance export of the request's scene (``measure.blender.request``: its efficacy and unit
    scale too) into ``out_dir`` (created; see the module docstring).
    ``meters``: the scene's meters (``measure.meter.meter_objects.Meter``, from the caller: host code reads
    no UI settings); their illuminance meters go to meters.pts.
    ``resolution`` (nx, ny) or ``spacing`` (m) of the work planes' grids (default: EN 12464-1's, as
    ``grid`` uses); ``ground_reflectance`` of the daylight factor's overcast sky. Returns a dict: the
    written paths, what was not mapped, and a summary."""
    scene = request.scene
    try:
        rho = float(ground_reflectance)
    except (TypeError, ValueError):
        rho = float("nan")
    if not (0.0 <= rho <= 1.0):
        raise RadiometerError(f"ground_reflectance must be within 0..1, got {ground_reflectance!r}")
    full = os.path.abspath(os.fspath(out_dir))
    if os.path.islink(full):
        raise RadiometerError(f"cannot use the output folder {outputs.shown(out_dir)}: it is a symbolic link")
    if os.path.exists(full) and not os.path.isdir(full):
        raise RadiometerError(f"cannot use the output folder {outputs.shown(out_dir)}: it is a file, not a folder")
    efficacy = request.efficacy
    model = point_meter.capture_model(scene, request.view_layer)
    ex = _Export()
    geometry_parts = _geometry(ex, scene, model)
    light_parts, suns = _lights(ex, scene, model, efficacy)
    ex.files["scene.rad"] = "".join(geometry_parts + ["# lights\n"] + light_parts)
    _sky(ex, request, model, suns, rho)
    stems = _sensors(ex, request, resolution, spacing, meters)
    _views(ex, request, stems)
    ex.files["README.txt"] = _readme(ex, scene)
    try:
        os.makedirs(full, exist_ok=True)
    except OSError as exc:
        raise RadiometerError(f"cannot create the output folder {outputs.shown(out_dir)}: {exc.strerror or exc}") from None
    names = sorted(ex.files) + [MANIFEST]
    outputs.check_set(full, names, "Radiance export file")
    with outputs.FileSet(full, manifest=MANIFEST, name="radiance") as stage:
        for name, text in ex.files.items():
            outputs.write_text(stage.path(name), text)
        manifest = {"files": names, "unmapped": ex.unmapped, "notes": ex.notes, "summary": ex.summary,
                    "efficacy_lm_per_w": efficacy, "radiance_efficacy_lm_per_w": rad.RADIANCE_EFFICACY}
        outputs.write_text(stage.path(MANIFEST), json.dumps(outputs.json_safe(manifest), indent=2) + "\n")
        stage.commit()
    return {"out_dir": full, "files": [os.path.join(full, n) for n in names], "unmapped": list(ex.unmapped),
            "notes": list(ex.notes), "summary": ex.summary}
