"""Load (issue 6): many measurements in a row leak no data-blocks, leave bpy.data counts unchanged and
keep memory bounded. The bench (``make bench``, section 7) runs 1000 readings; this test runs 200.

Reference value: E = P / (4 pi r^2) for a point light of radius 0 (FACTS.md), so every reading is
also checked for correctness, not only for leaks.
"""

import math

import bpy
import numpy as np
import pytest

from radiometer import api


def all_counts():
    counts = {}
    for attr in dir(bpy.data):
        coll = getattr(bpy.data, attr, None)
        if isinstance(coll, bpy.types.bpy_prop_collection):
            counts[attr] = len(coll)
    return counts


def rss_mb():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    pytest.skip("no /proc/self/status")


def test_200_render_readings_leak_nothing(clean_blender, build):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "POINT", (0, 0, 2), energy=100.0, shadow_soft_size=0.0)
    api.measure_illuminance((0, 0, 0), method="render")  # warm-up: kernels, caches
    counts = all_counts()
    rng = np.random.default_rng(1)
    rss = {}
    for k in range(200):
        p = np.array([rng.uniform(-1, 1), rng.uniform(-1, 1), 0.0])
        r = api.measure_illuminance(p, method="render", quality="preview", seed=k)
        d2 = p[0] ** 2 + p[1] ** 2 + 4.0
        assert r.irradiance == pytest.approx(100 / (4 * math.pi) * 2 / d2 ** 1.5, rel=1e-4)
        if k in (19, 199):
            rss[k + 1] = rss_mb()
    assert all_counts() == counts
    # 180 readings after the 20th: a leak of one sensor image (16 px) + mesh per reading would be
    # small, so the counts above are the sharp check; memory must not grow by more than a few MB.
    assert rss[200] - rss[20] < 20.0, rss


def test_mixed_readings_in_a_row_leave_counts_unchanged(clean_blender, build, tmp_path):
    scene = bpy.context.scene
    build.black_world(scene)
    build.light(scene, "AREA", (0, 0, 2), energy=30.0, size=0.5)
    build.plane(scene, size=4.0, albedo=0.5, name="floor")
    bpy.ops.radiometer.add_meter(kind="ILLUMINANCE")
    bpy.context.active_object.location = (0.3, 0, 0.5)
    counts = all_counts()
    for k in range(10):
        api.measure_illuminance([(0, 0, 0.5), (0.5, 0.5, 0.5)], method="auto", quality="preview", seed=k)
        api.measure_illuminance((0, 0, 0.5), method="analytic")
        api.predict_illuminance((0, 0, 0.5))
        api.measure_luminance((0, 0, 1.0), (0, 0, -1), quality="preview")
        api.measure_meters(quality="preview")
    api.capture_radiance_map((0, 0, 1.0), str(tmp_path / "m.exr"), resolution=8, quality="preview")
    assert all_counts() == counts
    assert not [i.name for i in bpy.data.images if i.name.startswith("radiometer")]
