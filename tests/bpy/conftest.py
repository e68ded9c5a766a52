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


@pytest.fixture
def clean_blender():
    import radiometer

    bpy.ops.wm.read_factory_settings(use_empty=True)
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
