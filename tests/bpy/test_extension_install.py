"""The real install path (issue 2): Blender's validator and builder, then install into a temporary
user extension repository in a fresh process, enable, run operators, disable."""

import os
import subprocess
import sys
import textwrap
import zipfile

from radiometer.tools import extension


def test_manifest_validates_with_blenders_tool():
    result = extension.validate()
    assert result.returncode == 0, result.stdout + result.stderr
    assert "Success" in result.stdout


def test_zip_builds_and_keeps_dev_files_out(tmp_path):
    result, path = extension.build(str(tmp_path))
    assert result.returncode == 0, result.stdout + result.stderr
    names = zipfile.ZipFile(path).namelist()
    assert "blender_manifest.toml" in names and "__init__.py" in names
    assert "brdf/__init__.py" in names and "radiometry/__init__.py" in names and "measure/render/sensors.py" in names
    for excluded in ("tests/", "bench/", ".ci/", "Makefile", "requirements.txt", "tools/", "docs/"):
        assert not any(n.startswith(excluded) for n in names), excluded


def test_install_enable_run_disable_in_fresh_process(tmp_path):
    _result, path = extension.build(str(tmp_path / "dist"))
    script = textwrap.dedent(f"""
        import bpy, sys
        bpy.ops.extensions.package_install_files(filepath={path!r}, repo="user_default", enable_on_install=True)
        import addon_utils
        module = "bl_ext.user_default.radiometer"
        assert addon_utils.check(module)[1], "not enabled"
        assert "{tmp_path}" in sys.modules[module].__file__, sys.modules[module].__file__
        for op in ("add_meter", "measure", "assign_brdf", "check_inverse_square", "check_cosine_law",
                   "illuminance_grid", "set_light_power"):
            assert hasattr(bpy.ops.radiometer, op), op
        bpy.ops.radiometer.add_meter(kind="ILLUMINANCE")
        assert bpy.context.active_object.radiometer_meter.is_meter
        bpy.ops.preferences.addon_disable(module=module)
        assert not hasattr(bpy.types.Scene, "radiometer")
        print("INSTALL-OK", flush=True)
        import os
        os._exit(0)  # Blender 4.5's bpy can hang at exit (see tests/bpy/conftest.py)
    """)
    env = dict(os.environ, BLENDER_USER_RESOURCES=str(tmp_path / "user"))
    # Run from / so the repo's own copy (the .venv symlink) cannot be imported by mistake.
    out = subprocess.run([sys.executable, "-c", script], env=env, cwd="/", capture_output=True, text=True,
                         timeout=300)
    assert "INSTALL-OK" in out.stdout, out.stdout[-3000:] + out.stderr[-3000:]
