"""The capture layer builds emitters once per capture (radiometry/emitters): kinds, stable identity,
ray visibility, and emissive meshes whose radiance convention is checked against a Cycles render."""

import math

import bpy
import numpy as np
import pytest

from radiometer import api
from radiometer.compat import ensure_node_tree
from radiometer.measure.capture import scene_capture
from radiometer.radiometry import emitters


def _emissive_plane(scene, size, z, colour, strength, principled=False):
    h = size / 2
    mesh = bpy.data.meshes.new("glow")
    mesh.from_pydata([(-h, -h, 0), (h, -h, 0), (h, h, 0), (-h, h, 0)], [], [(0, 1, 2, 3)])
    mat = bpy.data.materials.new("glow")
    tree = ensure_node_tree(mat)
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputMaterial")
    if principled:
        node = tree.nodes.new("ShaderNodeBsdfPrincipled")
        node.inputs["Base Color"].default_value = (0, 0, 0, 1)
        node.inputs["Emission Color"].default_value = colour + (1.0,)
        node.inputs["Emission Strength"].default_value = strength
        tree.links.new(node.outputs["BSDF"], out.inputs["Surface"])
    else:
        node = tree.nodes.new("ShaderNodeEmission")
        node.inputs["Color"].default_value = colour + (1.0,)
        node.inputs["Strength"].default_value = strength
        tree.links.new(node.outputs["Emission"], out.inputs["Surface"])
    mesh.materials.append(mat)
    obj = bpy.data.objects.new("glow", mesh)
    obj.location = (0.0, 0.0, z)
    scene.collection.objects.link(obj)
    return obj


def test_capture_builds_emitters_with_identity_and_visibility(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    lamp = build.light(scene, "POINT", (0, 0, 2), energy=10.0, shadow_soft_size=0.0)
    panel = build.light(scene, "AREA", (1, 0, 2), energy=5.0, size=0.5)
    panel.data.use_shadow = False
    panel.visible_glossy = False
    glow = _emissive_plane(scene, 0.5, 1.5, (1.0, 0.5, 0.25), 2.0, principled=True)
    model = scene_capture.capture(scene)
    by_name = {light.name: light for light in model.lights}
    point, area = by_name[lamp.name].emitter, by_name[panel.name].emitter
    assert isinstance(point, emitters.PointLight) and isinstance(area, emitters.AreaLight)
    assert point.source_id.object_uid == lamp.session_uid and point.source_id.instance == ()
    assert by_name[lamp.name].source_id == point.source_id
    V = emitters.RayVisibility
    for attr, flag in (("visible_camera", V.CAMERA), ("visible_diffuse", V.DIFFUSE), ("visible_glossy", V.GLOSSY)):
        assert bool(point.visibility & flag) == getattr(lamp, attr)      # Blender 5: lights not camera-visible
    assert point.visibility & V.SHADOW
    assert not area.visibility & emitters.RayVisibility.SHADOW and not area.visibility & emitters.RayVisibility.GLOSSY
    assert area.power_w() == pytest.approx(np.full(3, 5.0))
    # The emissive surface (a Principled BSDF's emission, as render_settings._node_types reads it) is an emitter.
    (mesh,) = model.emissive_meshes
    assert mesh.source_id.object_uid == glow.session_uid and mesh.source_id.part == 0
    assert mesh.flags & emitters.EmitterFlags.RENDERED_ONLY and model.emissive_surfaces
    np.testing.assert_allclose(mesh.radiance[0], [2.0, 1.0, 0.5])
    assert mesh.area_m2 == pytest.approx(0.25)
    np.testing.assert_allclose(mesh.power_w(), 2 * math.pi * 0.25 * np.array([2.0, 1.0, 0.5]), rtol=1e-6)
    assert len(model.emitters) == 3
    # Identity survives a rename (names are labels, not identities).
    lamp.name = "renamed"
    again = scene_capture.capture(scene)
    assert {l.source_id for l in again.lights} == {l.source_id for l in model.lights}


def test_emissive_mesh_radiance_is_cycles_emission_strength(clean_blender, build):
    """Cycles' Emission strength is radiance: a rendered meter under an emitting square reads the
    emitter's unoccluded closed form (L x the square's projected solid angle) within its error."""
    scene = bpy.context.scene
    build.black_world(scene)
    _emissive_plane(scene, 0.6, 0.5, (1.0, 1.0, 1.0), 3.0)
    model = scene_capture.capture(scene)
    (mesh,) = model.emissive_meshes
    expected = float(mesh.irradiance_at([0.0, 0.1, 0.0], [0.0, 0.0, 1.0])[0][1])
    reading = api.measure_illuminance((0.0, 0.1, 0.0), (0.0, 0.0, 1.0), method="render", target_rel_error=0.02)
    assert not reading.exact
    got = float(reading.irradiance_rgb[1])
    assert got == pytest.approx(expected, rel=3 * reading.rel_std_error + 1e-3)


def _isotropic_luminaire(folder, candela):
    """An imported IES file of ``candela`` cd in every direction: (path, light object)."""
    path = folder / "iso.ies"
    path.write_text("IESNA:LM-63-2002\n[TEST] isotropic\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 0\n"
                    f"0 90 180\n0\n{candela} {candela} {candela}\n")
    return path, api.import_luminaire(str(path))


def test_luminaire_summary_is_not_reread_on_every_redraw(clean_blender, tmp_path, monkeypatch):
    """The luminaire panel's summary comes from a cache keyed by the file's mtime and size (issue 17:
    the panel re-read and re-integrated the file on every redraw)."""
    import os

    from radiometer.measure.capture import luminaires
    from radiometer.radiometry.photometry import photometric_files as pf

    path, obj = _isotropic_luminaire(tmp_path, 100)
    reads = []
    real = pf.read_photometry
    monkeypatch.setattr(pf, "read_photometry", lambda p: reads.append(p) or real(p))
    first = luminaires.luminaire_summary(obj)
    assert luminaires.luminaire_summary(obj) == first and len(reads) == 1
    assert first["lumens"] == pytest.approx(400 * math.pi, rel=1e-9)   # isotropic 100 cd: 4 pi x 100 lm
    path.write_text(path.read_text().replace("100 100 100", "200 200 200"))
    os.utime(path, ns=(os.stat(path).st_atime_ns, os.stat(path).st_mtime_ns + 10**9))
    assert luminaires.luminaire_summary(obj)["lumens"] == pytest.approx(800 * math.pi, rel=1e-9)
    assert len(reads) == 2


def test_an_ies_text_is_parsed_once_for_every_capture(clean_blender, tmp_path, monkeypatch):
    """Issue 17: IES data went text -> table on every capture; the parsed table is kept per text."""
    from radiometer.measure.capture import luminaires
    from radiometer.radiometry.photometry import photometric_files as pf

    _path, obj = _isotropic_luminaire(tmp_path, 123)
    calls = []
    real = pf.cycles_ies_table
    monkeypatch.setattr(pf, "cycles_ies_table", lambda text: calls.append(1) or real(text))
    luminaires._cycles_table.cache_clear()
    scene = bpy.context.scene
    for height in (2.0, 3.0):                                  # an edit between captures
        obj.location.z = height
        model = scene_capture.capture(scene)
        (light,) = model.lights
        assert isinstance(light.emitter, emitters.PhotometricLight)
    assert len(calls) == 1
    # The emitter's flux is the file's: 4 pi x 123 cd over K (the importer's energy gives I / K W/sr).
    efficacy = luminaires.scene_efficacy(scene)
    assert light.emitter.luminous_flux_lm(np.full(3, 1 / 3), efficacy) == pytest.approx(4 * math.pi * 123, rel=1e-6)


@pytest.mark.parametrize("kind, black", [("diffuse 0", True), ("diffuse 0.1", False), ("diffuse linked", False),
                                         ("diffuse muted", False), ("principled 0", False), ("no material", False),
                                         ("black for EEVEE only", False)])
def test_only_a_black_diffuse_surface_counts_as_sending_nothing(clean_blender, kind, black):
    """Issue 31: an object 'reflects' unless its every material is one unmuted Diffuse BSDF of colour (0, 0, 0)
    (Cycles drops a closure of zero weight) on the output Cycles renders; a Principled BSDF at base colour 0 keeps its
    specular layer, and a black surface on an EEVEE-only output says nothing of what Cycles renders."""
    me = bpy.data.meshes.new("card")
    me.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)], [], [(0, 1, 2, 3)])
    ob = bpy.data.objects.new("card", me)
    bpy.context.scene.collection.objects.link(ob)
    if kind != "no material":
        m = bpy.data.materials.new("m")
        tree = ensure_node_tree(m)
        tree.nodes.clear()
        out = tree.nodes.new("ShaderNodeOutputMaterial")
        bsdf = tree.nodes.new("ShaderNodeBsdfPrincipled" if kind.startswith("principled") else "ShaderNodeBsdfDiffuse")
        bsdf.inputs["Base Color" if kind.startswith("principled") else "Color"].default_value = \
            (0.1, 0.1, 0.1, 1) if kind == "diffuse 0.1" else (0, 0, 0, 1)
        tree.links.new(bsdf.outputs[0], out.inputs["Surface"])
        if kind == "diffuse linked":
            rgb = tree.nodes.new("ShaderNodeRGB")
            rgb.outputs[0].default_value = (0, 0, 0, 1)
            tree.links.new(rgb.outputs[0], bsdf.inputs["Color"])
        bsdf.mute = kind == "diffuse muted"
        if kind == "black for EEVEE only":  # that output targets EEVEE; Cycles renders a white Diffuse BSDF
            out.target = "EEVEE"
            cycles_out = tree.nodes.new("ShaderNodeOutputMaterial")
            cycles_out.target = "CYCLES"
            white = tree.nodes.new("ShaderNodeBsdfDiffuse")
            white.inputs["Color"].default_value = (1, 1, 1, 1)
            tree.links.new(white.outputs[0], cycles_out.inputs["Surface"])
        me.materials.append(m)
    model = scene_capture.capture(bpy.context.scene)
    k = model.geometry.object_names.index("card")
    assert bool(model.geometry.reflects[k]) is (not black)
    assert bool(model.geometry.casts_shadow[k])  # black or not, it blocks
