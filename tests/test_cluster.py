"""Scale-out plumbing without Blender: sys.path cleaning, bpy-free imports, unreachable scheduler (issue 20)."""

import socket
import subprocess
import sys

import pytest

from radiometer.cluster import worker
from radiometer.errors import RadiometerError

SITE = "/opt/venv/lib/python3.11/site-packages"


def test_clean_sys_path_drops_blender_script_folders_only():
    # The folders `import bpy` puts on sys.path (measured, bpy 5.0.1 as a module), and the user's
    # Blender config scripts; everything else (site-packages, the stdlib, "") stays.
    path = [f"{SITE}/bpy/5.0/scripts/startup", f"{SITE}/bpy/5.0/scripts/modules", "",
            "/usr/lib/python3.11", SITE, f"{SITE}/bpy/5.0/scripts/freestyle/modules",
            "/root/.config/blender/5.0/scripts/addons/modules", f"{SITE}/bpy/5.0/scripts/addons_core",
            "/home/u/projects/bpy-tools", "/srv/blender/scripts-old"]
    removed = worker.clean_sys_path(path)
    assert path == ["", "/usr/lib/python3.11", SITE, "/home/u/projects/bpy-tools", "/srv/blender/scripts-old"]
    assert len(removed) == 5


def test_cluster_modules_import_without_bpy():
    # Workers unpickle these before the first task cleans sys.path: they must not import bpy.
    code = ("import sys\n"
            "import radiometer.cluster, radiometer.cluster.worker, radiometer.cluster.source\n"
            "import radiometer.measure.analyses.batch, radiometer.cluster.plugin, radiometer.commands.batch\n"
            "assert 'bpy' not in sys.modules, 'bpy imported'\n")
    subprocess.run([sys.executable, "-c", code], check=True, cwd="/")


def _closed_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]  # closed again when the block ends: nothing listens there


def test_unreachable_scheduler_is_one_line():
    pytest.importorskip("distributed")
    from radiometer.cluster import connect

    address = f"tcp://127.0.0.1:{_closed_port()}"
    with pytest.raises(RadiometerError) as info:
        connect(address, timeout_s=1.0)
    message = str(info.value)
    assert "\n" not in message and address in message and "cannot reach the Dask scheduler" in message


def test_not_an_address_is_one_line():
    pytest.importorskip("distributed")
    from radiometer.cluster import connect

    with pytest.raises(RadiometerError, match="not a scheduler address"):
        connect("   ")


def test_task_functions_must_be_importable_by_name():
    with pytest.raises(RadiometerError, match="importable module-level function"):
        worker.function_name(lambda scene: None)

    def local(scene):
        return None

    with pytest.raises(RadiometerError, match="importable module-level function"):
        worker.function_name(local)
    from radiometer.measure.analyses import batch

    assert worker.function_name(batch.measure_file) == "radiometer.measure.analyses.batch:measure_file"
    assert worker.resolve("radiometer.measure.analyses.batch:measure_file") is batch.measure_file


def test_workers_and_scheduler_together_are_refused():
    from radiometer.cluster import cluster_client

    with pytest.raises(RadiometerError, match="not both"):
        with cluster_client(workers=2, scheduler="tcp://127.0.0.1:8786"):
            pass


def test_cli_unreachable_scheduler_exit_2_one_line(tmp_path):
    pytest.importorskip("distributed")
    blend = tmp_path / "a.blend"
    blend.write_bytes(b"BLENDER-v500" + bytes(64))  # never opened: the scheduler is asked for first
    address = f"tcp://127.0.0.1:{_closed_port()}"
    out = subprocess.run([sys.executable, "-m", "radiometer", "batch", str(blend), "--scheduler", address],
                         capture_output=True, text=True, cwd="/", timeout=120)
    assert out.returncode == 2, out.stderr
    lines = [line for line in out.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and "cannot reach the Dask scheduler" in lines[0] and address in lines[0], out.stderr
