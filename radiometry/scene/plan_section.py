"""A room in plan: where the scene's opaque triangles cross a horizontal plane (the work plane's
height), and the openings of its shell seen from above, for the daylight maps (``plots.daylight_map``).

Pure numpy (never imports bpy). Coordinates in metres, scene X/Y/Z (Z up), as the captured
``scene_model.SceneGeometry`` holds them.
"""

import numpy as np

from ..skies.sky_aperture import find_apertures

__all__ = ["section_segments", "plan_openings", "room_plan"]

#: An opening whose plan footprint has less area than this share of its own area is drawn as a segment
#: (a window in a wall); otherwise as its outline (a roof light).
FLAT_SHARE = 0.05


def section_segments(triangles, height, tol=1e-7):
    """Segments (S, 2, 2) in XY where the triangles (T, 3, 3) cross the plane z = ``height``.

    A vertex within ``tol`` of the plane lies on it. Triangles lying in the plane (every vertex on it,
    such as the work plane itself) and triangles that only touch it at one vertex give no segment; an
    edge lying in the plane is one segment (once per triangle that has it).
    """
    tris = np.asarray(triangles, float).reshape(-1, 3, 3)
    if not len(tris):
        return np.zeros((0, 2, 2))
    d = tris[:, :, 2] - float(height)
    d = np.where(np.abs(d) <= tol, 0.0, d)
    on = d == 0.0                                            # (T, 3) vertices on the plane
    a, b = [0, 1, 2], [1, 2, 0]
    da, db = d[:, a], d[:, b]
    cross = da * db < 0                                      # (T, 3) edges crossing strictly
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.where(cross, da / (da - db), 0.0)
    edge_pts = tris[:, a, :2] + s[:, :, None] * (tris[:, b, :2] - tris[:, a, :2])
    cand = np.concatenate([tris[:, :, :2], edge_pts], axis=1)      # (T, 6, 2)
    valid = np.concatenate([on, cross], axis=1)                    # (T, 6)
    keep = (valid.sum(axis=1) == 2) & ~on.all(axis=1)
    cand, valid = cand[keep], valid[keep]
    if not len(cand):
        return np.zeros((0, 2, 2))
    order = np.argsort(~valid, axis=1, kind="stable")[:, :2]
    seg = np.take_along_axis(cand, order[:, :, None], axis=1)
    length = np.linalg.norm(seg[:, 1] - seg[:, 0], axis=1)
    return seg[length > tol]


def plan_openings(triangles, tol=1e-6):
    """The shell's openings seen from above: a list of (K, 2) XY polylines in metres.

    Openings are the holes of the opaque surfaces' planes (``skies.sky_aperture.find_apertures``): a
    window in a wall (its plan footprint has almost no area) becomes the segment it spans along the wall,
    a roof light its outline, closed. A thick wall gives one line per face.
    """
    out = []
    for loop, _normal in find_apertures(triangles, tol):
        xy = np.asarray(loop, float)[:, :2]
        area3 = _area3(np.asarray(loop, float))
        area2 = abs(0.5 * np.sum(xy[:, 0] * np.roll(xy[:, 1], -1) - np.roll(xy[:, 0], -1) * xy[:, 1]))
        if area3 > 0 and area2 >= FLAT_SHARE * area3:
            out.append(np.vstack([xy, xy[:1]]))
            continue
        centred = xy - xy.mean(axis=0)
        _, _, vt = np.linalg.svd(centred, full_matrices=False)
        along = centred @ vt[0]
        if np.ptp(along) > tol:
            out.append(np.array([xy[np.argmin(along)], xy[np.argmax(along)]]))
    return out


def _area3(loop):
    n = np.zeros(3)
    for k in range(len(loop)):
        n += np.cross(loop[k], loop[(k + 1) % len(loop)])
    return 0.5 * float(np.linalg.norm(n))


def room_plan(triangles, opaque, height, tol=1e-6):
    """(walls (S, 2, 2), openings [(K, 2)]) of the plan at z = ``height`` m: the section of the opaque
    triangles (``opaque`` (T,) bool) and their openings (:func:`plan_openings`)."""
    tris = np.asarray(triangles, float).reshape(-1, 3, 3)
    mask = np.asarray(opaque, bool) if len(np.asarray(opaque)) == len(tris) else np.ones(len(tris), bool)
    solid = tris[mask]
    return section_segments(solid, height, tol), plan_openings(solid, tol)
