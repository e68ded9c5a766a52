"""bpy tier: every test starts from an empty factory scene with Radiometer registered."""

import pytest

bpy = pytest.importorskip("bpy")

from radiometer.demo import builders  # noqa: E402

# Blender 4.5's bpy module can hang at interpreter exit: its delayed-file-close thread and a global
# destructor wait on each other (gdb: GlobalState::~GlobalState in pthread_cond_destroy while
# delayed_close_thread_run waits); 5.0 exits normally. On 4.x the session ends with os._exit once
# pytest has reported, with pytest's exit status.
_session = {"status": 0}


def pytest_sessionfinish(session, exitstatus):
    _session["status"] = int(exitstatus)


def pytest_unconfigure(config):
    if bpy.app.version < (5, 0, 0):
        import os
        import sys

        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(_session["status"])


# Tests that change Blender's preferences get a true factory reset (preferences included); every other
# test gets the same empty factory scene reopened from a file saved once per session, as untitled
# (read_homefile: 0.03 s against 0.38 s for read_factory_settings, measured on this 2-core machine).
FACTORY_RESET_MODULES = {"test_device", "test_extension_install"}


@pytest.fixture(scope="session", autouse=True)  # session scope: made before any module's own scene
def empty_home_file(tmp_path_factory):
    """An empty factory scene saved once: reopened per test with ``read_homefile`` (stays untitled)."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    path = str(tmp_path_factory.mktemp("home") / "empty_factory.blend")
    bpy.ops.wm.save_as_mainfile(filepath=path, copy=True)
    return path


@pytest.fixture
def clean_blender(request, empty_home_file):
    import radiometer

    module = request.node.module.__name__.rpartition(".")[2] if request.node.module else ""
    if module in FACTORY_RESET_MODULES or request.node.get_closest_marker("factory_reset"):
        bpy.ops.wm.read_factory_settings(use_empty=True)
    else:
        bpy.ops.wm.read_homefile(filepath=empty_home_file, load_ui=False)
    radiometer.register()
    try:
        yield bpy
    finally:
        radiometer.unregister()


# The scene builders are the package's own (radiometer/demo/builders.py: also the demo's and the bench's).
make_black_world, add_light, add_plane = builders.black_world, builders.add_light, builders.add_plane


@pytest.fixture
def build():
    """Scene builders for tests: build.black_world(scene), build.light(...), build.plane(...)."""
    import types

    return types.SimpleNamespace(black_world=make_black_world, light=add_light, plane=add_plane)


def pytest_collection_modifyitems(config, items):
    """Every test of this tier needs Blender in the process: marked ``render`` (``-m "not render"``)."""
    here = __file__.rpartition("/")[0]
    for item in items:
        if str(item.fspath).startswith(here):
            item.add_marker(pytest.mark.render)
