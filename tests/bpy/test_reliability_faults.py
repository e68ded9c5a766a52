"""Faults through the whole pipeline (issue 6): a render that fails, an unwritable temporary folder, a
missing or corrupt EXR, a broken material, cancel mid-measurement, KeyboardInterrupt. After each: the
user's scene is unchanged (``scene_fingerprint``), no ``radiometer_*`` data-blocks or temporary files
remain, and the user gets a clear one-line ``RadiometerError`` (or the KeyboardInterrupt itself).

Reference value where a reading is checked: E = P / (4 pi r^2) for a point light of radius 0 (FACTS.md).
"""

import math
import os
import stat
import tempfile

import bpy
import pytest

from radiometer import api
from radiometer.errors import MeasurementCancelled, RadiometerError
from radiometer.measure.meter import camera
from radiometer.measure.render import sensors
from radiometer.measure.blender.scene_guard import scene_fingerprint

# EEVEE's engine id: BLENDER_EEVEE_NEXT in Blender 4.2-4.5, BLENDER_EEVEE again since 5.0.
EEVEE = "BLENDER_EEVEE" if bpy.app.version >= (5, 0, 0) else "BLENDER_EEVEE_NEXT"


def all_data_names():
    """Names of every ID in every bpy.data collection (not only those the scene guard watches)."""
    names = set()
    for attr in dir(bpy.data):
        coll = getattr(bpy.data, attr, None)
        if isinstance(coll, bpy.types.bpy_prop_collection) and attr not in {"window_managers", "screens",
                                                                              "workspaces"}:
            names |= {(attr, getattr(i, "name", "")) for i in coll}
    return names


def radiometer_blocks():
    return sorted(n for n in all_data_names() if n[1].startswith("radiometer"))


def user_scene(build):
    """A scene with settings a measurement must not touch, a camera, geometry and an area light."""
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "AREA", (0, 0, 2), energy=30.0, size=0.5)
    build.light(scene, "POINT", (1, 0, 2), energy=10.0, shadow_soft_size=0.0)
    floor = build.plane(scene, size=4.0, albedo=0.5, name="floor")
    cam = bpy.data.objects.new("user cam", bpy.data.cameras.new("user cam"))
    scene.collection.objects.link(cam)
    scene.camera = cam
    scene.render.engine = EEVEE
    scene.render.resolution_x, scene.render.resolution_y = 1234, 567
    scene.render.filepath = "//user_out_"
    scene.render.image_settings.file_format = "PNG"
    scene.cycles.samples = 77
    scene.frame_set(3)
    bpy.context.view_layer.objects.active = floor
    floor.select_set(True)
    return scene


@pytest.fixture
def private_tmp(tmp_path, monkeypatch):
    """Temporary files go to a private folder, so leftovers are ours (other processes share /tmp)."""
    folder = tmp_path / "tmp"
    folder.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(folder))
    return folder


def assert_clean(scene, before, private_tmp):
    assert scene_fingerprint(scene) == before
    assert radiometer_blocks() == []
    assert list(private_tmp.iterdir()) == []


class _Proxy:
    """Stands in for a module or bpy.ops submodule, overriding some attributes."""

    def __init__(self, real, **overrides):
        self._real, self._overrides = real, overrides

    def __getattr__(self, name):
        return self._overrides[name] if name in self._overrides else getattr(self._real, name)


def patch_render(monkeypatch, fake):
    """Make camera.py's ``bpy.ops.render.render`` call ``fake`` (bpy.ops submodules are created afresh
    on every attribute access, so they cannot be monkeypatched in place)."""
    fake_bpy = _Proxy(bpy, ops=_Proxy(bpy.ops, render=_Proxy(bpy.ops.render, render=fake)))
    monkeypatch.setattr(camera, "bpy", fake_bpy)


def one_line(exc):
    text = str(exc)
    assert text and "\n" not in text and "Traceback" not in text
    return text


# --- a render that fails ------------------------------------------------------------------------------

def test_bake_that_returns_cancelled_gives_clear_error(clean_blender, build, private_tmp, monkeypatch):
    scene = user_scene(build)
    before, names = scene_fingerprint(scene), all_data_names()
    monkeypatch.setattr(sensors, "run_bake", lambda *a, **k: {"CANCELLED"})
    with pytest.raises(Exception) as info:
        api.measure_illuminance((0, 0, 0.5), method="render")
    assert "did not finish" in one_line(info.value)
    assert_clean(scene, before, private_tmp)
    assert all_data_names() == names


def test_failed_bake_is_a_radiometer_error(clean_blender, build, private_tmp, monkeypatch):
    user_scene(build)
    monkeypatch.setattr(sensors, "run_bake", lambda *a, **k: {"CANCELLED"})
    with pytest.raises(RadiometerError):
        api.measure_illuminance((0, 0, 0.5), method="render")


def test_bake_operator_raising_inside_blender(clean_blender, build, private_tmp, monkeypatch):
    """The real operator fails: Cycles cannot bake an object without UVs ('no UV map')."""
    scene = user_scene(build)
    before = scene_fingerprint(scene)
    real = sensors.run_bake

    def bake_without_uvs(scene_, layer, obj):
        for o in obj if isinstance(obj, (list, tuple)) else [obj]:
            o.data.uv_layers.remove(o.data.uv_layers[0])
        return real(scene_, layer, obj)

    monkeypatch.setattr(sensors, "run_bake", bake_without_uvs)
    with pytest.raises((RuntimeError, RadiometerError)):
        api.measure_illuminance((0, 0, 0.5), method="render")
    assert_clean(scene, before, private_tmp)


@pytest.mark.parametrize("failure", ["raises", "cancelled", "no_file", "corrupt_file"])
def test_luminance_render_failures(clean_blender, build, private_tmp, monkeypatch, failure):
    """Camera path: bpy.ops.render.render raises / returns CANCELLED / writes nothing / writes garbage."""
    scene = user_scene(build)
    before = scene_fingerprint(scene)

    def fake_render(*_args, **_kwargs):
        if failure == "raises":
            raise RuntimeError("Error: simulated render failure")
        if failure == "cancelled":
            return {"CANCELLED"}
        if failure == "corrupt_file":
            with open(bpy.context.scene.render.filepath + ".exr", "wb") as f:
                f.write(b"v/1\x01 this is not an OpenEXR file" * 10)
        return {"FINISHED"}

    patch_render(monkeypatch, fake_render)
    expected = {"raises": (RuntimeError, RadiometerError), "cancelled": RadiometerError,
                "no_file": RadiometerError, "corrupt_file": RadiometerError}[failure]
    with pytest.raises(expected) as info:
        api.measure_luminance((0, 0, 1.0), (0, 0, -1), quality="preview")
    message = one_line(info.value)
    if failure == "no_file":
        assert "missing" in message
    if failure == "corrupt_file":
        assert "cannot read" in message
    assert_clean(scene, before, private_tmp)


def test_radiance_map_render_failure_writes_no_file(clean_blender, build, private_tmp, monkeypatch, tmp_path):
    scene = user_scene(build)
    before = scene_fingerprint(scene)
    patch_render(monkeypatch, lambda *a, **k: {"CANCELLED"})
    target = tmp_path / "out" / "map.exr"
    target.parent.mkdir()
    with pytest.raises(RadiometerError):
        api.capture_radiance_map((0, 0, 1.0), str(target), resolution=8, quality="preview")
    assert not target.exists()
    assert_clean(scene, before, private_tmp)


def test_radiance_map_into_missing_folder_is_refused(clean_blender, build, private_tmp, tmp_path):
    scene = user_scene(build)
    before = scene_fingerprint(scene)
    with pytest.raises(RadiometerError, match="does not exist"):
        api.capture_radiance_map((0, 0, 1.0), str(tmp_path / "nowhere" / "map.exr"), resolution=8)
    assert_clean(scene, before, private_tmp)


# --- unwritable temporary directory ---------------------------------------------------------------

@pytest.fixture
def unwritable_tmp(tmp_path, monkeypatch):
    folder = tmp_path / "readonly"
    folder.mkdir()
    folder.chmod(stat.S_IRUSR | stat.S_IXUSR)
    monkeypatch.setattr(tempfile, "tempdir", str(folder))
    try:
        probe = folder / "probe"
        probe.write_text("x")
        probe.unlink()
        folder.chmod(0o700)
        pytest.skip("running as root: a read-only folder is still writable (chmod cannot simulate it)")
    except PermissionError:
        pass
    yield folder
    folder.chmod(0o700)


def test_unwritable_temp_dir_luminance(clean_blender, build, unwritable_tmp):
    scene = user_scene(build)
    before = scene_fingerprint(scene)
    with pytest.raises(RadiometerError):
        api.measure_luminance((0, 0, 1.0), (0, 0, -1), quality="preview")
    assert scene_fingerprint(scene) == before and radiometer_blocks() == []


def test_temp_dir_that_is_a_file(clean_blender, build, tmp_path, monkeypatch):
    """Works as root too: TMPDIR pointing at a regular file cannot hold the render output."""
    scene = user_scene(build)
    before = scene_fingerprint(scene)
    not_a_dir = tmp_path / "file"
    not_a_dir.write_text("x")
    monkeypatch.setattr(tempfile, "tempdir", str(not_a_dir))
    with pytest.raises(Exception) as info:
        api.measure_luminance((0, 0, 1.0), (0, 0, -1), quality="preview")
    assert scene_fingerprint(scene) == before and radiometer_blocks() == []
    one_line(info.value)


def test_temp_dir_that_is_a_file_is_a_radiometer_error(clean_blender, build, tmp_path, monkeypatch):
    user_scene(build)
    not_a_dir = tmp_path / "file"
    not_a_dir.write_text("x")
    monkeypatch.setattr(tempfile, "tempdir", str(not_a_dir))
    with pytest.raises(RadiometerError):
        api.measure_luminance((0, 0, 1.0), (0, 0, -1), quality="preview")


def test_illuminance_needs_no_temp_files(clean_blender, build, tmp_path, monkeypatch):
    """The bake path keeps everything in memory: an unusable temp folder does not matter to it."""
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0, 0, 2), energy=100.0, shadow_soft_size=0.0)
    not_a_dir = tmp_path / "file"
    not_a_dir.write_text("x")
    monkeypatch.setattr(tempfile, "tempdir", str(not_a_dir))
    r = api.measure_illuminance((0, 0, 0), method="render")
    assert r.irradiance == pytest.approx(100 / (4 * math.pi * 4), rel=1e-4)


# --- broken material --------------------------------------------------------------------------------

def test_broken_material_still_measures_and_restores(clean_blender, build, private_tmp):
    """A material whose output has a dangling group node and a missing image: Cycles renders it (as
    black/pink), the reading stays finite and the scene is left as it was."""
    scene = user_scene(build)
    floor = bpy.data.objects["floor"]
    mat = floor.active_material
    tree = mat.node_tree
    group = tree.nodes.new("ShaderNodeGroup")  # a group node with no node tree
    tex = tree.nodes.new("ShaderNodeTexImage")
    img = bpy.data.images.new("missing", 4, 4)
    img.source, img.filepath = "FILE", "/nonexistent/radiometer_missing.png"
    tex.image = img
    tree.links.new(tex.outputs["Color"], tree.nodes["Diffuse BSDF"].inputs["Color"])
    assert group.node_tree is None
    before = scene_fingerprint(scene)
    r = api.measure_illuminance((0, 0, 0.5), method="render", quality="preview")
    assert math.isfinite(r.irradiance) and r.irradiance > 0
    assert_clean(scene, before, private_tmp)


# --- cancel and KeyboardInterrupt mid-way -------------------------------------------------------------

def counter_cancel(after):
    calls = {"n": 0}

    def cancelled():
        calls["n"] += 1
        return calls["n"] > after

    return cancelled, calls


def test_cancel_between_bakes_of_a_reference_reading(clean_blender, build, private_tmp):
    scene = user_scene(build)
    before = scene_fingerprint(scene)
    cancelled, calls = counter_cancel(1)  # the pilot round runs, the second round is cancelled
    with pytest.raises(MeasurementCancelled) as info:
        api.measure_illuminance([(0, 0, 0.5), (0.5, 0, 0.5)], method="render", quality="reference",
                                target_rel_error=2e-4, cancelled=cancelled)
    assert calls["n"] == 2
    assert "cancelled" in one_line(info.value)
    assert_clean(scene, before, private_tmp)


def test_cancel_during_target_error_refinement(clean_blender, build, private_tmp):
    scene = user_scene(build)
    before = scene_fingerprint(scene)
    cancelled, calls = counter_cancel(1)  # the pilot bake runs; the refinement bake is cancelled
    with pytest.raises(MeasurementCancelled):  # no absolute floor: the pilot's error alone would stop it
        api.measure_illuminance((0, 0, 0.5), method="render", quality="preview", target_rel_error=1e-4,
                                target_abs_error=0.0, cancelled=cancelled)
    assert calls["n"] == 2
    assert_clean(scene, before, private_tmp)


def test_cancel_luminance_mid_way(clean_blender, build, private_tmp):
    scene = user_scene(build)
    before = scene_fingerprint(scene)
    cancelled, calls = counter_cancel(2)
    with pytest.raises(MeasurementCancelled):
        api.measure_luminance((0, 0, 1.0), (0, 0, -1), quality="preview", cancelled=cancelled)
    assert calls["n"] == 3
    assert_clean(scene, before, private_tmp)


def test_keyboard_interrupt_inside_the_bake(clean_blender, build, private_tmp, monkeypatch):
    scene = user_scene(build)
    before = scene_fingerprint(scene)

    def interrupted(*_a, **_k):
        raise KeyboardInterrupt

    monkeypatch.setattr(sensors, "run_bake", interrupted)
    with pytest.raises(KeyboardInterrupt):
        api.measure_illuminance((0, 0, 0.5), method="render")
    assert_clean(scene, before, private_tmp)


def test_keyboard_interrupt_from_luminance_progress(clean_blender, build, private_tmp):
    scene = user_scene(build)
    before = scene_fingerprint(scene)

    def progress(done, _total):
        if done == 2:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        api.measure_luminance((0, 0, 1.0), (0, 0, -1), quality="preview", progress=progress)
    assert_clean(scene, before, private_tmp)


def test_cli_reports_interrupt_in_one_line(clean_blender, build, monkeypatch, capsys, tmp_path):
    from radiometer import cli

    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0, 0, 2), energy=100.0, shadow_soft_size=0.0)
    bpy.ops.radiometer.add_meter(kind="ILLUMINANCE")
    scene.radiometer.method = "render"
    path = str(tmp_path / "s.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path)

    def interrupted(*_a, **_k):
        raise KeyboardInterrupt

    monkeypatch.setattr(sensors, "run_bake", interrupted)
    code = cli.main(["measure", path])
    err = capsys.readouterr().err
    assert code == 130 and err.strip().count("\n") == 0 and "interrupted" in err


# --- failing step of a multi-meter measurement keeps old readings -------------------------------------

def test_failed_second_step_writes_no_reading(clean_blender, build, private_tmp, monkeypatch):
    scene = user_scene(build)
    bpy.ops.radiometer.add_meter(kind="ILLUMINANCE")
    illum = bpy.context.active_object
    illum.location = (0, 0, 0.5)
    bpy.ops.radiometer.add_meter(kind="LUMINANCE")
    lum = bpy.context.active_object
    lum.location = (0, 0, 1.0)
    from radiometer import api

    patch_render(monkeypatch, lambda *a, **k: {"CANCELLED"})
    before = scene_fingerprint(scene)
    with pytest.raises(RadiometerError):
        api.measure_meters([illum, lum], scene=scene, quality="preview")
    assert not illum.radiometer_meter.has_reading and not lum.radiometer_meter.has_reading
    assert_clean(scene, before, private_tmp)
