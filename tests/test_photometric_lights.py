"""Photometric point lights in the pure model (radiometry.emitters with a light's Photometry table) and the
``luminaire`` CLI subcommand."""

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from radiometer.radiometry import emitters
from radiometer.radiometry.photometry import photometric_files as pf


def _table(func, h=np.arange(0.0, 360.0 + 1e-9, 30.0), v=np.arange(0.0, 180.0 + 1e-9, 10.0), vector_map=None):
    values = np.array([[func(vv, hh) for vv in v] for hh in h])
    kwargs = {} if vector_map is None else {"vector_map": vector_map}
    return emitters.Photometry.light_table(h_deg=h, v_deg=v, values=values, **kwargs)


def _rot(ax, angle):
    c, s = math.cos(angle), math.sin(angle)
    i, j = [(1, 2), (2, 0), (0, 1)][ax]
    m = np.eye(3)
    m[i, i], m[i, j], m[j, i], m[j, j] = c, -s, s, c
    return m


def test_table_light_gives_i_cos_over_r2_in_cycles_frame():
    # Cycles' frame: h = atan2(x, y) + 180 deg of the light-to-receiver vector, v = acos(-z).
    table = _table(lambda v, h: 1.0 + h / 100.0 + v / 1000.0)
    axes = _rot(2, 0.7) @ _rot(0, 0.3)
    spec = emitters.CyclesLight(kind="POINT", radius=0.0, position=(1.0, 2.0, 3.0), axes=axes,
                            rgb_power=(2.0, 1.0, 0.5), intensity_table=table)
    for v, h in ((30.0, 90.0), (60.0, 240.0), (110.0, 330.0)):
        a = math.radians(h) - math.pi
        local = np.array([math.sin(math.radians(v)) * math.sin(a), math.sin(math.radians(v)) * math.cos(a),
                          -math.cos(math.radians(v))])
        d = axes @ local
        r = 2.5
        p = spec.position + r * d
        n = -d
        e = spec.irradiance_at(p, n)[0]
        expected = (1.0 + h / 100.0 + v / 1000.0) / r**2 * np.array([2.0, 1.0, 0.5])
        np.testing.assert_allclose(e, expected, rtol=1e-12)
        np.testing.assert_allclose(spec.intensity_towards(d), expected * r**2, rtol=1e-12)
        tilted = n + 0.5 * np.cross(n, [0.0, 0.0, 1.0])
        cos = float(unit(tilted) @ n)
        np.testing.assert_allclose(spec.irradiance_at(p, tilted)[0], expected * cos, rtol=1e-12)
    exact, model, note = spec.exactness()
    assert exact and model == "photometric point"


def unit(x):
    return np.asarray(x) / np.linalg.norm(x)


def test_mapping_of_the_importer_turns_radiometer_convention_into_cycles():
    # The importer's Mapping: rotation z = -90 deg, scale (1, -1, 1): local (x, y, z) -> (-y, -x, z),
    # so C0 = local +X and C90 = local +Y in Radiometer's table.
    photometry = pf.Photometry(vertical_angles_deg=np.arange(0.0, 180.1, 10.0),
                               horizontal_angles_deg=np.arange(0.0, 360.1, 90.0),
                               candela=np.array([[k] * 19 for k in (1.0, 2.0, 3.0, 4.0, 1.0)]), symmetry="none")
    h, v, values = pf.cycles_ies_table(pf.to_ies_text(photometry))
    vmap = _rot(2, -math.pi / 2) @ np.diag([1.0, -1.0, 1.0])
    table = emitters.Photometry.light_table(h_deg=h, v_deg=v, values=values / pf.CYCLES_CANDELA_TO_WATT, vector_map=vmap)
    for direction, plane in (((1, 0, -1), 1.0), ((0, 1, -1), 2.0), ((-1, 0, -1), 3.0), ((0, -1, -1), 4.0)):
        assert table.lookup(unit(direction)) == pytest.approx(plane, rel=1e-6), direction


def test_table_light_validation_and_zero_distance():
    table = _table(lambda v, h: 1.0)
    with pytest.raises(ValueError, match="radius 0"):
        emitters.CyclesLight(kind="SPOT", intensity_table=table)
    with pytest.raises(ValueError, match="radius 0"):
        emitters.CyclesLight(kind="POINT", radius=0.1, intensity_table=table)
    with pytest.raises(ValueError, match=">= 0"):
        emitters.Photometry.light_table(h_deg=[0, 360], v_deg=[0, 180], values=[[1, -1], [1, 1]])
    spec = emitters.CyclesLight(kind="POINT", radius=0.0, intensity_table=table)
    with pytest.raises(ValueError, match="zero distance"):
        spec.irradiance_at((0.0, 0.0, 0.0), (0.0, 0.0, 1.0))[0]
    # shapes broadcast like every other light
    e = spec.irradiance_at(np.zeros((2, 4, 3)) + [0.0, 0.0, -1.0], (0.0, 0.0, 1.0))[0]
    assert e.shape == (2, 4, 3) and np.allclose(e, 1.0)


def test_light_spec_from_values_folds_the_emission_colour():
    table = emitters.Photometry.light_table(h_deg=[0, 360], v_deg=[0, 180], values=np.ones((2, 2)), rgb_scale=(1.0, 0.5, 0.25))
    spec = emitters.from_blender_values({"type": "POINT", "energy": 2.0, "shadow_soft_size": 0.0,
                                          "intensity_table": table})
    np.testing.assert_allclose(spec.rgb_power, [2.0, 1.0, 0.5])


def _cli(*args, cwd="/"):
    return subprocess.run([sys.executable, "-m", "radiometer", *args], capture_output=True, text=True, cwd=cwd,
                          timeout=300)


@pytest.mark.subprocess  # runs the Blender-backed CLI in a child process
def test_cli_luminaire_summary_json_and_bad_input(tmp_path):
    v = np.arange(0.0, 180.0 + 1e-9, 5.0)
    path = tmp_path / "iso.ies"
    path.write_text("IESNA:LM-63-2002\n[MANUFAC] Acme\nTILT=NONE\n1 1000 1 %d 1 1 2 0 0 0\n1 1 10\n%s\n0\n%s\n"
                    % (v.size, " ".join(f"{x:g}" for x in v), " ".join(["50"] * v.size)))
    out = tmp_path / "s.json"
    r = _cli("luminaire", str(path), "--json", str(out))
    assert r.returncode == 0, r.stderr
    assert "628.3" in r.stdout and "Acme" in r.stdout          # 4 pi x 50 lm
    data = json.loads(out.read_text())
    assert data["lumens"] == pytest.approx(4 * math.pi * 50.0) and data["rated_lumens"] == 1000.0
    bad = tmp_path / "bad.ies"
    bad.write_text("IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 3 1 1 2 0 0 0\n1 1 10\n0 90 45\n0\n1 2 3\n")
    r = _cli("luminaire", str(bad))
    assert r.returncode == 2
    assert r.stderr.strip().count("\n") == 0 and "increasing" in r.stderr and "Traceback" not in r.stderr
