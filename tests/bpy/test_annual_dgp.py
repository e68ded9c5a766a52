"""Annual DGP at one eye (measure/analyses/annual_dgp.py, issue 34), checked outdoors where E_v has closed forms.

An eye 1.5 m above an empty scene looks south (+Y north) through six days of a synthetic March at London:
three overcast days (no direct sun) and three clear ones. References, independent of the renders:

- the daylight coefficients of a vertical plane, in closed form (the integral of max(0, n.w) over each
  patch, as tests/bpy/test_annual.py), times the same sky vectors: the rendered E_v must look like its
  stated standard error (RMS z < 1.5, none beyond 4; the dome test's criterion);
- the continuous Perez sky (its luminance on a 180 x 720 grid over the hemisphere, normalised to the
  hour's diffuse horizontal illuminance) + the ground (rho E_gh / 2 on a vertical plane): where no sun
  shines E_v is within 3 stated standard errors + 0.6 % of it (Tregenza's 145 patches read 0.36-0.45 % low
  on this vertical eye, measured here);
- at the sunny hours the sun (SPA) stands south of the eye's plane with nothing in the way: full DGP with
  L = E_dn / omega_sun and P at the sun's direction, recomputed here with ``glare_dgp.dgp``; at the overcast
  hours the simplified DGPs of the same E_v.
"""

import datetime as dt
import importlib.util
import json
import math
import pathlib

import bpy
import numpy as np
import pytest

from radiometer.radiometry.metrics import glare, glare_dgp

HERE = pathlib.Path(__file__).resolve().parent
EYE, VIEW = (0.0, 0.0, 1.5), (0.0, -1.0, 0.0)
FIRST_DAY, DAYS, OVERCAST_DAYS = 78, 6, 3  # from 20 March


def _room_module():
    spec = importlib.util.spec_from_file_location("annual_room", HERE / "annual_room.py")
    room = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(room)
    return room


def write_march(path):
    """Six days from 20 March (UTC+0, London): overcast (direct 0, diffuse 60 + 200 sin h W/m^2) for three
    days, then clear (direct 1000 exp(-0.16 / sin h), diffuse 40 + 60 sin h)."""
    from radiometer.radiometry.sun import solar_position

    room = _room_module()
    year = room.write_epw(path.with_name("year.epw"))
    lines = year.read_text(encoding="latin-1").splitlines()
    recs = [r.split(",") for r in lines[8 + 24 * FIRST_DAY: 8 + 24 * (FIRST_DAY + DAYS)]]
    times = [dt.datetime(2026, 1, 1, tzinfo=dt.timezone.utc) + dt.timedelta(days=FIRST_DAY, hours=h + 0.5)
             for h in range(24 * DAYS)]
    pos = solar_position.solar_position(solar_position.unix_seconds(times), room.LATITUDE, room.LONGITUDE)
    sin_h = np.sin(np.radians(np.asarray(pos.elevation_deg, float)))
    for k, r in enumerate(recs):
        dni, dhi = 0.0, 0.0
        if sin_h[k] > 0.01:
            dni, dhi = ((0.0, 60.0 + 200.0 * sin_h[k]) if k < 24 * OVERCAST_DAYS
                        else (1000.0 * math.exp(-0.16 / sin_h[k]), 40.0 + 60.0 * sin_h[k]))
        r[13], r[14], r[15] = str(round(dhi + dni * max(sin_h[k], 0.0))), str(round(dni)), str(round(dhi))
    path.write_text("\n".join(lines[:8] + [",".join(r) for r in recs]) + "\n", encoding="latin-1")
    return path


def patch_closed_form(patches, normal, n=200):
    """(P,) integral over each patch of max(0, n.w) dw (lux per cd/m^2), midpoint rule."""
    out = np.empty(patches.count)
    for p in range(patches.count):
        a0, a1 = (-math.pi / 2, 0.0) if p == 0 else (patches.alt_lo[p], patches.alt_hi[p])
        z0, z1 = (0.0, 2 * math.pi) if p in (0, patches.count - 1) else (patches.az_lo[p], patches.az_hi[p])
        alt = a0 + (np.arange(n) + 0.5) * (a1 - a0) / n
        az = z0 + (np.arange(n) + 0.5) * (z1 - z0) / n
        A, Z = np.meshgrid(alt, az, indexing="ij")
        w = np.stack([np.cos(A) * np.sin(Z), np.cos(A) * np.cos(Z), np.sin(A)], axis=-1)
        out[p] = float(np.sum(np.maximum(w @ normal, 0) * np.cos(A)) * (a1 - a0) / n * (z1 - z0) / n)
    return out


def continuous_sky(weather, normal, rho=0.2, n=720):
    """Per record: (E_v of the continuous Perez sky + ground + direct sun on a plane of ``normal``, E_dn)."""
    from radiometer.radiometry.skies import perez, sky_patches
    from radiometer.radiometry.sun import solar_position

    times = weather.midpoint_datetimes(2026)
    sun = np.asarray(solar_position.solar_position(solar_position.unix_seconds(times), weather.latitude_deg,
                                                   weather.longitude_deg, elevation_m=weather.elevation_m).direction)
    m = n // 4
    alt = (np.arange(m) + 0.5) * (math.pi / 2) / m
    az = (np.arange(n) + 0.5) * 2 * math.pi / n
    A, Z = np.meshgrid(alt, az, indexing="ij")
    w = np.stack([np.cos(A) * np.sin(Z), np.cos(A) * np.cos(Z), np.sin(A)], -1)
    dw = np.cos(A) * (math.pi / 2 / m) * (2 * math.pi / n)
    zeta = math.pi / 2 - A
    patches = sky_patches.reinhart_patches(1)
    ev, e_dn = np.zeros(len(times)), np.zeros(len(times))
    for t, when in enumerate(times):
        s = sun[t]
        dew = weather.dew_point_c[t] if np.isfinite(weather.dew_point_c[t]) else 11.0
        _vec, info = perez.sky_vector(patches, s, float(weather.direct_normal_w_m2[t]),
                                      float(weather.diffuse_horizontal_w_m2[t]), when.timetuple().tm_yday, dew, rho)
        if info["parameters"] is None:
            continue
        z = float(perez.clamp_zenith(math.pi / 2 - math.asin(float(np.clip(s[2], -1, 1)))))
        cos_g = np.cos(z) * np.cos(zeta) + np.sin(z) * np.sin(zeta) * np.cos(np.abs(Z - math.atan2(s[0], s[1])))
        lum = perez.relative_luminance(zeta, np.arccos(np.clip(cos_g, -1, 1)), info["parameters"])
        lum *= info["diffuse_lux"] / np.sum(lum * np.sin(A) * dw)
        e_dn[t] = info["direct_normal_lux"] if s[2] > 0 else 0.0
        ground = rho * (info["diffuse_lux"] + e_dn[t] * max(s[2], 0.0)) / math.pi * math.pi * (1 - normal[2]) / 2
        ev[t] = np.sum(lum * np.maximum(w @ normal, 0) * dw) + ground + e_dn[t] * max(float(normal @ s), 0.0)
    return ev, e_dn, sun


def test_annual_dgp_outdoors_against_closed_forms(clean_blender, tmp_path):
    from radiometer import api
    from radiometer.measure.analyses import annual
    from radiometer.measure.analyses import daylight_coefficients as dcm
    from radiometer.radiometry.skies import sky_patches
    from radiometer.radiometry.sun import epw

    scene = bpy.context.scene
    if not dcm.supported(scene):
        pytest.skip("the dome coefficients need Blender 5.0")
    path = write_march(tmp_path / "march.epw")
    r = api.annual_dgp(EYE, VIEW, str(path), scene=scene, samples=2, seed=1, partial_period=True)
    weather = epw.read_epw(path)
    normal = np.array(VIEW)
    occ = r.occupied
    assert occ.sum() == 10 * DAYS and r.dgp.shape == (24 * DAYS,)
    overcast = occ & (np.arange(24 * DAYS) < 24 * OVERCAST_DAYS)
    sunny = occ & ~overcast

    # E_v against the closed-form coefficients, through the same sky vectors: the stated error holds
    patches = sky_patches.reinhart_patches(1)
    sky = annual.sky_matrix(weather, patches)
    ev_dc = sky.sky @ patch_closed_form(patches, normal)
    z = (r.vertical_illuminance - ev_dc)[occ] / r.vertical_illuminance_std_error[occ]
    print("E_v z against closed-form coefficients: RMS", np.sqrt(np.mean(z ** 2)), "max", np.abs(z).max())
    assert np.sqrt(np.mean(z ** 2)) < 1.5 and np.abs(z).max() < 4.0

    # E_v against the continuous sky where no sun shines
    ev_c, e_dn, sun = continuous_sky(weather, normal)
    gap = np.abs(r.vertical_illuminance - ev_c)[overcast]
    # 0.2 %: the patch-centre sampling; the sky normalised with cos(centre) x solid angle (gendaymtx's) was
    # 0.33-0.83 % short here (docs/daylight-sky.md, "Sky matrix against gendaymtx")
    allowed = 3 * r.vertical_illuminance_std_error[overcast] + 0.002 * ev_c[overcast]
    print("overcast E_v / continuous sky - 1 (%):", np.round(100 * (r.vertical_illuminance[overcast] / ev_c[overcast] - 1), 2))
    assert np.all(gap <= allowed) and ev_c[overcast].min() > 3000.0

    # overcast: DGPs of the same E_v; the sun is never seen
    assert not r.sun_seen[overcast].any()
    np.testing.assert_allclose(r.dgp[overcast], 6.22e-5 * r.vertical_illuminance[overcast] + 0.184, atol=1e-12)
    np.testing.assert_allclose(r.dgp_std_error[overcast], 6.22e-5 * r.vertical_illuminance_std_error[overcast],
                               rtol=1e-9)

    # sunny: the SPA sun is south of the eye's plane at every occupied hour, nothing blocks it
    assert np.all(sun[sunny] @ normal > 0) and r.sun_seen[sunny].all()
    omega = glare_dgp.SUN_SOLID_ANGLE_SR
    for t in np.flatnonzero(sunny):
        sigma, tau, elev = glare.view_angles(normal, sun[t])
        p = float(glare_dgp.position_index_dgp(sigma, tau, elev))
        ref = glare_dgp.dgp(r.vertical_illuminance[t], [e_dn[t] / omega], [omega], [p])
        assert r.dgp[t] == pytest.approx(ref, abs=1e-9), t
        assert r.sun_luminance[t] == pytest.approx(e_dn[t] / omega, rel=1e-9)
    assert np.all(r.dgp[sunny] > 0.5)   # the bare sun in view

    # counts and EN 17037 over the occupied hours
    d = r.dgp[occ]
    assert r.hours_above[0.40] == int(np.sum(d >= 0.40)) and r.share_above[0.45] == np.mean(d >= 0.45)
    row = api.en17037_table(dgp=r.occupied_dgp())[2]
    assert row["criterion"] == "protection from glare" and row["level"] == r.en17037["level"] == "not met"
    assert row["values"]["hours"] == 10 * DAYS


def test_cli_annual_dgp_and_its_bad_input(clean_blender, tmp_path, capsys):
    from radiometer import cli
    from radiometer.measure.analyses import daylight_coefficients as dcm

    if not dcm.supported(bpy.context.scene):
        pytest.skip("the dome coefficients need Blender 5.0")
    path = str(write_march(tmp_path / "march.epw"))
    points = tmp_path / "p.csv"
    points.write_text("0,0,0\n", encoding="utf-8")
    base = ["annual", "--epw", path, "--partial-period"]
    for extra, words in ((["--dgp-observer", "0", "0", "1.5", "0", "0", "1"], "vertical"),
                         (["--dgp-observer", "0", "0", "1.5", "0", "-1", "0", "--points", str(points)], "--points"),
                         (["--dgp-observer", "0", "0", "1.5", "nan", "-1", "0"], "finite"),
                         (["--points", str(points), "--low-light-correction"], "--dgp-observer")):
        assert cli._blender_cli(base + extra) == 2, extra
        err = capsys.readouterr().err
        assert words in err and "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    out_json, out_csv = tmp_path / "dgp.json", tmp_path / "dgp.csv"
    assert cli._blender_cli(base + ["--dgp-observer", "0", "0", "1.5", "0", "-1", "0", "--json", str(out_json),
                                    "--csv", str(out_csv)]) == 0
    printed = capsys.readouterr().out
    assert "annual DGP over 60 occupied hours (30 with the sun in view)" in printed
    data = json.loads(out_json.read_text(encoding="utf-8"))
    assert data["occupied_hours"] == 60 and len(data["hourly"]["dgp"]) == 24 * DAYS
    assert data["en17037_glare_protection"]["criterion"] == "protection from glare"
    rows = out_csv.read_text(encoding="utf-8").splitlines()
    assert rows[0].startswith("record,local_hour,occupied,dgp") and len(rows) == 1 + 24 * DAYS


def _fresnel_slab(cos_i, n):
    """Transmittance of a clear, non-absorbing slab (both faces, every inter-reflection), unpolarised:
    the mean over s and p of (1 - R) / (1 + R), R the single-face Fresnel reflectance."""
    sin_t = math.sqrt(max(0.0, 1 - cos_i ** 2)) / n
    cos_t = math.sqrt(1 - sin_t ** 2)
    rs = ((cos_i - n * cos_t) / (cos_i + n * cos_t)) ** 2
    rp = ((cos_t - n * cos_i) / (cos_t + n * cos_i)) ** 2
    return 0.5 * ((1 - rs) / (1 + rs) + (1 - rp) / (1 + rp))


def test_annual_dgp_sees_the_sun_through_the_pane_only_when_its_ray_crosses_it(clean_blender, tmp_path):
    """The side-lit room of tests/bpy/daylight_room.py (window 1-3 m x 0.9-2.1 m in the south wall y = 0, a
    6 mm clear pane in it), an eye at (2, 1, 0.8) looking south: at each clear occupied hour, the sun is a
    glare source exactly when the ray from the eye to the SPA sun crosses the window rectangle (found here by
    a ray-plane intersection), with L = E_dn T(theta) / omega_sun, T the clear slab's Fresnel transmittance
    (closed form above); otherwise the hour is rated by DGPs."""
    from radiometer import api
    from radiometer.measure.analyses import daylight_coefficients as dcm
    from radiometer.radiometry.sun import epw

    spec = importlib.util.spec_from_file_location("daylight_room", HERE / "daylight_room.py")
    room = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(room)
    scene = bpy.context.scene
    room.build_blender(scene)
    room.add_pane_blender(scene)
    if not dcm.supported(scene):
        pytest.skip("the dome coefficients need Blender 5.0")
    eye = np.array([2.0, 1.0, 0.8])
    path = write_march(tmp_path / "march.epw")
    r = api.annual_dgp(tuple(eye), VIEW, str(path), scene=scene, samples=2, seed=2, partial_period=True)
    _ev, e_dn, sun = continuous_sky(epw.read_epw(path), np.array(VIEW))
    x0, x1, z0, z1 = room.WINDOW
    sunny = r.occupied & (np.arange(24 * DAYS) >= 24 * OVERCAST_DAYS)
    crossed = []
    for t in np.flatnonzero(sunny):
        s = sun[t]
        k = -eye[1] / s[1]                      # the ray eye + k s meets the wall plane y = 0
        x, z = eye[0] + k * s[0], eye[2] + k * s[2]
        margin = min(x - x0, x1 - x, z - z0, z1 - z)
        if abs(margin) < 0.01:
            continue                            # within 1 cm of the window's edge: either answer is fair
        inside = margin > 0
        crossed.append(inside)
        assert r.sun_seen[t] == inside, (t, x, z)
        if inside:
            cos_i = -s[1]                       # the pane's normal is -Y
            expected = e_dn[t] * _fresnel_slab(cos_i, room.IOR) / glare_dgp.SUN_SOLID_ANGLE_SR
            assert r.sun_luminance[t] == pytest.approx(expected, rel=1e-3), t
        else:
            assert r.sun_luminance[t] == 0.0
            assert r.dgp[t] == pytest.approx(min(1.0, 6.22e-5 * r.vertical_illuminance[t] + 0.184), abs=1e-12)
    print(r.summary())
    print("sunny hours with the sun's ray through the window:", int(sum(crossed)), "of", len(crossed))
    assert 3 <= sum(crossed) <= len(crossed) - 3   # both kinds of hour are tested


@pytest.mark.slow
def test_annual_dgp_hours_against_radiance_coefficients(clean_blender):
    """The annual room of tests/bpy/annual_room.py (4 x 8 m, a 2.4 x 1 m south window), a synthetic London
    year, three eyes (looking at the window, along the window wall, at the window obliquely): the occupied
    hours with DGPs at or above 0.35 / 0.40 / 0.45 from Radiometer's E_v lie within its stated bounds (every
    hour 2 s.e. lower / higher), widened by Radiance's own run-to-run difference, of those from Radiance's
    daylight coefficients at the same eye (annual_dgp_reference.json: rcontrib -ab 8 -ad 65536, two runs)
    through the same sky matrix; the mean occupied E_v within 3 times the mean of its hourly standard errors
    (the hours' errors share the coefficients' and are correlated: the mean's error is at most that) plus
    Radiance's run-to-run difference.
    Honeybee's whole chain (gendaymtx's sky) is in the JSON and docs/deliverables.md: its sky differs."""
    import tempfile

    from radiometer import api
    from radiometer.measure.analyses import annual
    from radiometer.measure.analyses import daylight_coefficients as dcm
    from radiometer.radiometry.skies import sky_patches
    from radiometer.radiometry.sun import epw

    ref = json.loads((HERE / "annual_dgp_reference.json").read_text(encoding="utf-8"))
    room = _room_module()
    scene = bpy.context.scene
    room.room.build_blender(scene, room.quads())
    if not dcm.supported(scene):
        pytest.skip("the dome coefficients need Blender 5.0")
    with tempfile.TemporaryDirectory() as folder:
        path = room.write_epw(pathlib.Path(folder) / "year.epw")
        weather = epw.read_epw(path)
        sky = annual.sky_matrix(weather, sky_patches.reinhart_patches(1))
        for k, (eye, view) in enumerate(zip(ref["eyes"], ref["views"])):
            r = api.annual_dgp(tuple(eye), tuple(view), str(path), scene=scene, seed=1)
            occ = r.occupied
            assert int(occ.sum()) == ref["occupied_hours"]
            ev, se = r.vertical_illuminance[occ], r.vertical_illuminance_std_error[occ]
            ev_rad = [sky.sky[occ] @ np.asarray(run["dc_lux_per_cd_m2"][k]) for run in ref["runs"]]
            mean_rad = float(np.mean([e.mean() for e in ev_rad]))
            print(f"eye {k}: mean E_v {ev.mean():.0f} lx (mean s.e. {se.mean():.0f} lx) vs Radiance {mean_rad:.0f} lx; "
                  f"sun seen {int((r.sun_seen & occ).sum())} h")
            spread = abs(ev_rad[0].mean() - ev_rad[1].mean())
            assert abs(ev.mean() - mean_rad) <= 3 * se.mean() + spread, (k, ev.mean(), mean_rad, se.mean())
            for lim in (0.35, 0.40, 0.45):
                ours = [int(np.sum(6.22e-5 * (ev + f * 2 * se) + 0.184 >= lim)) for f in (-1, 0, 1)]
                theirs = [int(np.sum(6.22e-5 * e + 0.184 >= lim)) for e in ev_rad]
                noise = abs(theirs[0] - theirs[1])
                print(f"  DGPs >= {lim:.2f}: {ours[1]} h ({ours[0]}-{ours[2]}), Radiance {theirs}; with the sun's "
                      f"term {r.hours_above[lim]} h; gendaymtx {[run['gendaymtx_hours_at_or_above'][f'{lim:.2f}'][k] for run in ref['runs']]}")
                assert all(ours[0] - noise <= h <= ours[2] + noise for h in theirs), (k, lim, ours, theirs)
