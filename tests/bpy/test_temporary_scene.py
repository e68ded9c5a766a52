"""measure.blender.temporary_scene: Radiometer's own render scenes leave nothing behind, also when the render
fails, and share only what they are given with the user's scene."""

import os

import bpy
import pytest

from radiometer import api  # noqa: F401  (installs the efficacy reader, as in every session)
from radiometer.measure.blender import efficacy
from radiometer.measure.blender.temporary_scene import temporary_scene


def test_everything_made_is_removed_even_after_an_error(clean_blender, build):
    user = bpy.context.scene
    build.black_world(user)
    user.unit_settings.scale_length = 0.01
    user.radiometer.efficacy_convention = "CUSTOM"
    user.radiometer.efficacy = 250.0
    before = {name: len(getattr(bpy.data, name)) for name in ("scenes", "objects", "meshes", "cameras", "worlds")}
    with pytest.raises(RuntimeError, match="render failed"):
        with temporary_scene("radiometer_test_rig", like=user) as rig:
            assert rig.scene.world == user.world
            assert rig.scene.unit_settings.scale_length == user.unit_settings.scale_length
            assert efficacy.of(rig.scene) == 250.0  # the rig reads the user's efficacy (issue 30: no copied props)
            mesh = rig.keep(bpy.data.meshes.new("radiometer_test_mesh"))
            rig.link(bpy.data.objects.new("radiometer_test_object", mesh))
            rig.keep(bpy.data.cameras.new("radiometer_test_camera"))
            folder = rig.scratch()
            open(os.path.join(folder, "x.exr"), "wb").close()
            assert not user.objects  # the user's scene does not see the rig
            raise RuntimeError("render failed")
    assert {name: len(getattr(bpy.data, name)) for name in before} == before
    assert not os.path.exists(folder)
    assert bpy.context.scene == user and user.world is not None
