"""Issue 32: panes as users model them. A pane is recognised whether its transform sits in the object
matrix or was applied to its float32 mesh (Apply Rotation, CAD/IFC imports), tilted 0-90 deg, 0.3-10 m
wide, up to 1 km from the origin; the sun through each reads E_dn cos(theta) T(theta).

The reference T is written here from the textbook, independently of ``thin_glass.slab``: Fresnel's
equations for r_s, r_p of one interface (Hecht, Optics, 4.42-4.43) and Stokes' sum of the incoherent
multiple reflections in a lossless plate, T = (1 - r) / (1 + r) per polarisation (Born & Wolf,
Principles of Optics, 7.6; Stokes 1862), averaged over the two polarisations (unpolarised sunlight).
"""

import math

import numpy as np
import pytest

from radiometer.radiometry import emitters
from radiometer.radiometry.scene import scene_model, thin_glass

IOR, THICKNESS, E_DN = 1.52, 0.006, 100.0  # -, m, W/m^2 per channel


def _plate_T(cos_i, n=IOR):
    """Clear plate transmittance (references in the module docstring)."""
    sin_t = math.sqrt(1.0 - cos_i ** 2) / n
    cos_t = math.sqrt(1.0 - sin_t ** 2)
    rs = ((cos_i - n * cos_t) / (cos_i + n * cos_t)) ** 2
    rp = ((n * cos_i - cos_t) / (n * cos_i + cos_t)) ** 2
    return 0.5 * ((1 - rs) / (1 + rs) + (1 - rp) / (1 + rp))


def _box(half_x, half_y, half_z):
    """(8, 3) vertices and (12, 3) vertex indices of a box centred on the origin (a flat pane)."""
    v = np.array([[x, y, z] for z in (-half_z, half_z) for y in (-half_y, half_y) for x in (-half_x, half_x)])
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (1, 3, 7, 5), (3, 2, 6, 7), (2, 0, 4, 6)]
    tris = [(a, b, c) for a, b, c, _d in quads] + [(a, c, d) for a, _b, c, d in quads]
    return v, np.array(tris)


def _rotation(tilt_deg, azimuth_deg):
    t, a = math.radians(tilt_deg), math.radians(azimuth_deg)
    rx = np.array([[1, 0, 0], [0, math.cos(t), -math.sin(t)], [0, math.sin(t), math.cos(t)]])
    rz = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])
    return rz @ rx


def _captured(mode, size, tilt, location, azimuth=30.0, aspect=0.6):
    """(world triangles (T, 3, 3) m, tolerance m) of a pane as ``measure.capture.scene_capture`` reads it: float32
    mesh coordinates times a float32 object matrix, in float64.

    ``object``: the box in its own frame, the rotation (and a non-uniform scale) in the matrix;
    ``applied``: the transform applied to the mesh (float32 world coordinates, identity matrix);
    ``cad``: the applied mesh sits 1 km away in its own frame and the object matrix moves it back."""
    L, W = size, size * aspect
    rot = _rotation(tilt, azimuth)
    location = np.asarray(location, float)
    if mode == "object":
        v, tri = _box(0.5, 0.5, THICKNESS / 2)
        matrix = rot @ np.diag([L, W, 1.0])  # scaled to size: a non-uniform scale of a unit square
    else:
        v, tri = _box(L / 2, W / 2, THICKNESS / 2)
        v = v @ rot.T + location
        matrix, location = np.eye(3), np.zeros(3)
        if mode == "cad":
            far = np.array([1000.0, -700.0, 50.0])
            v, location = v + far, -far
    local = v.astype(np.float32).astype(np.float64)
    m32 = matrix.astype(np.float32).astype(np.float64)
    t32 = location.astype(np.float32).astype(np.float64)
    world = (local @ m32.T + t32)[tri]
    local_extent = float(np.abs(local).max()) * float(np.linalg.norm(m32, 2))
    return world, thin_glass.coordinate_tolerance(float(np.abs(world).max()), local_extent)


TILTS = (0.0, 7.0, 30.0, 45.0, 60.0, 89.9, 90.0)
SIZES = (0.3, 1.0, 6.0, 10.0)
PLACES = ((0.0, 0.0, 3.0), (7.0, -3.0, 10.0), (250.0, 180.0, 40.0), (1000.0, 0.0, 0.0), (-600.0, 790.0, 90.0))


@pytest.mark.parametrize("mode", ["object", "applied", "cad"])
def test_panes_recognised_over_tilts_sizes_and_places(mode):
    failed = []
    for tilt in TILTS:
        for size in SIZES:
            for place in PLACES:
                world, tol = _captured(mode, size, tilt, place)
                geom, why = thin_glass.pane_geometry(world, tol)
                if geom is None:
                    failed.append((tilt, size, place, why))
                    continue
                assert geom.thickness == pytest.approx(THICKNESS, abs=4 * tol)
                n_true = _rotation(tilt, 30.0)[:, 2]
                # The normal is known to float32 rounding across the pane's width (0.6 x size).
                angle = math.acos(min(1.0, abs(float(geom.normal @ n_true))))
                assert angle <= 2 * tol / (0.6 * size), (tilt, size, place, angle)
    assert not failed, failed


def test_sun_through_each_pane_is_the_plate_closed_form():
    """plan_direct reads the sun through every pane of the sweep as E_dn x cap x T (the planner's own
    crossing proof and slab): within 1e-4 of E_dn cos(theta) T_plate(theta), theta the sun's angle to the
    pane, for three sun angles per pane."""
    worst = 0.0
    for mode in ("object", "applied", "cad"):
        for tilt in TILTS:
            for size in SIZES:
                for place in PLACES[::2]:
                    world, tol = _captured(mode, size, tilt, place)
                    geom, why = thin_glass.pane_geometry(world, tol)
                    assert geom is not None, (mode, tilt, size, place, why)
                    rot = _rotation(tilt, 30.0)
                    n, u = rot[:, 2], rot[:, 0]
                    centre = np.asarray(place, float) if mode == "object" else world.reshape(-1, 3).mean(axis=0)
                    pane = thin_glass.Pane(name="Roof", ior=IOR, thickness=geom.thickness, geometry=geom,
                                           model="test pane")
                    geometry = scene_model.SceneGeometry(
                        triangles=world, object_index=np.zeros(len(world), int), object_names=["Roof"],
                        casts_shadow=np.array([True]), opaque=np.zeros(len(world), bool),
                        reflects=np.array([True]), emissive=np.zeros(len(world), bool),
                        pane_of=np.zeros(len(world), int))
                    for theta in (0.0, 25.0, 60.0):
                        to_sun = math.cos(math.radians(theta)) * n + math.sin(math.radians(theta)) * u
                        depth = min(1.0, 0.2 * size / max(math.tan(math.radians(theta)), 0.1))
                        meter = centre - n * depth  # under the pane, facing it; the sun's ray crosses near its middle
                        sun = emitters.CyclesLight(name="sun", kind="SUN", axes=_axes_towards(-to_sun),
                                                   rgb_power=(E_DN,) * 3, angle=math.radians(0.53))
                        model = scene_model.SceneModel(lights=[scene_model.ModelLight("sun", sun)], geometry=geometry,
                                                       panes={0: pane})
                        plan = scene_model.plan_direct(model, [meter], [n])
                        assert plan.status[0, 0] in (scene_model.EXACT, scene_model.BOUNDED), plan.reason[0, 0]
                        e = sun.irradiance_at(meter[None, :], n[None, :])[0][0, 0] * plan.transmittance[0, 0, 0]
                        expected = E_DN * math.cos(math.radians(theta)) * _plate_T(math.cos(math.radians(theta)))
                        err = abs(e / expected - 1.0)
                        worst = max(worst, err)
                        assert err <= 1e-4, (mode, tilt, size, place, theta, e, expected)
    assert worst > 0.0  # the sun's 0.53 deg disc: the cap is not exactly cos(theta)


def _axes_towards(direction):
    """Orthonormal columns (x, y, z) with local -Z along ``direction`` (a Cycles light's emission)."""
    z = -np.asarray(direction, float) / np.linalg.norm(direction)
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    return np.stack([x, np.cross(z, x), z], axis=1)


def test_real_bevels_and_tapers_are_still_refused():
    """The tolerance admits float32 rounding, not shape: a 6 mm pane whose upper face is smaller by twice
    the tolerance along each edge (a taper: 6 um at 3 m from the origin, 2 mm at 1 km, where float32
    steps are 61 um), or with one corner raised as much (not planar), is no pane."""
    rot = _rotation(45.0, 0.0)
    for place in ((0.0, 0.0, 3.0), (1000.0, 0.0, 0.0)):
        v, tri = _box(1.0, 0.6, THICKNESS / 2)
        v = v @ rot.T + place
        tol = thin_glass.coordinate_tolerance(float(np.abs(v).max()))
        assert thin_glass.pane_geometry(v[tri], tol)[0] is not None
        v32 = v.astype(np.float32).astype(np.float64)
        assert thin_glass.pane_geometry(v32[tri], tol)[0] is not None
        local, _ = _box(1.0 - 2 * tol, 0.6 - 2 * tol, THICKNESS / 2)
        taper = v.copy()
        taper[4:] = local[4:] @ rot.T + place
        geom, why = thin_glass.pane_geometry(taper[tri], tol)
        assert geom is None and "square" in why, why
        raised = v.copy()
        raised[0] += 2 * tol * rot[:, 2]
        geom, why = thin_glass.pane_geometry(raised[tri], tol)
        assert geom is None and "planar" in why, why


def test_tolerance_follows_the_mesh_frame_not_only_the_world():
    """A CAD mesh 1 km from its own origin, moved back by its transform, carries float32 rounding of
    1 km coordinates: the capture's tolerance takes the larger of the two frames."""
    assert thin_glass.coordinate_tolerance(3.0) == pytest.approx(3e-6)
    assert thin_glass.coordinate_tolerance(3.0, 1000.0) == pytest.approx(1e-3)
    assert thin_glass.coordinate_tolerance(0.2) == pytest.approx(1e-6)  # the 1 m floor
    assert thin_glass.coordinate_tolerance(float("nan"), 2.0) == pytest.approx(2e-6)
