"""api.en12464_compliance on the test office: grid, UGR per observer and the EN 12464-1 table."""

import os
import sys

import bpy
import pytest

sys.path.insert(0, os.path.dirname(__file__))
import office  # noqa: E402

from radiometer import api  # noqa: E402


def test_office_compliance_table(clean_blender, build):
    scene = bpy.context.scene
    office.build(scene)
    plane = build.plane(scene, size=1.0, location=(0.0, 0.5, 0.75), name="Work Plane")
    plane.scale = (4.0, 2.4, 1.0)
    plane.hide_render = True
    grid = api.illuminance_grid(plane, resolution=(8, 5), quality="preview")
    out = api.en12464_compliance(plane, "office_writing", maintenance_factor=0.8, grid=grid,
                                 observers=[(office.EYE, office.VIEW)], quality="preview", scene=scene)
    checks = {c["quantity"]: c for c in out["checks"]}
    assert checks["Ēm"]["achieved"] == pytest.approx(0.8 * grid.stats["avg"])
    assert checks["Ēm"]["status"] in ("pass", "fail", "marginal")
    assert checks["U0"]["achieved"] == pytest.approx(grid.stats["u0"])
    assert checks["UGR (observer 1)"]["achieved"] == pytest.approx(out["glare"][0].ugr)
    assert checks["Ra"]["status"] == "not assessed"
    assert out["requirement"]["source"].startswith("EN 12464-1")
    with pytest.raises(api.RadiometerError):
        api.en12464_compliance(plane, "spaceship", grid=grid)
