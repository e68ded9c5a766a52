"""Meters sealed off from every source (issue 31, dark meters): a reading that is exactly 0 by proof.

A closed surface (every edge shared by an even number of triangles, ``sky_aperture.closed_components``) parts
space in two: a path from a point of odd crossing parity to one of even parity crosses it. When its
triangles are opaque and stop every kind of ray (``SceneGeometry.sealing_triangles``: diffuse, glossy,
transmission, shadow and volume rays see them, no holdout), no light path crosses it: light is absorbed
or reflected back to the side it came from. So a meter on one side of such a shell receives nothing
from a source wholly on the other side. A meter for which every source of the scene is cut off by some
shell reads exactly 0 with no sample spent (a box outside a closed room whose lights are all inside, a
meter in a closed cupboard of a daylit room).

A shell with openings proves the same for meters outside it where the openings look out on nothing (issue 31: a
grid that runs past a lit room's walls): every light source inside, the world black, every surface of the scene
behind or on each opening's plane. Light leaving through an opening then travels on in front of it and never comes
back, so a meter outside the shell and behind every opening's plane reads exactly 0 (``_behind_open_shell``). A
room of separate boxes (no single closed surface) proves the same where its walls' outer faces cover the faces of
the box round the scene but for its windows: light leaves that box only through the uncovered faces, so a meter
outside it, in front only of covered faces, reads exactly 0 (``_behind_covered_faces``).

What is proven, and what is refused (then nothing is proven and the meter is measured as before):
* the sources: every light's emitter answers ``extent()`` (points and reach), the emissive meshes by
  their triangles; the sun and the world lie at infinity, outside every shell; a light that casts no
  shadow (its light goes through surfaces), one without a known extent, an object with shadow linking
  (blockers), or a participating medium (its shader may emit) proves nothing;
* a source's whole extent is on one side of a shell: the box around it, grown by its reach and the
  tolerance, meets none of the shell's triangles (separating axes, every doubt read as "meets"), and
  the box's centre's side is decided by the crossing parity;
* the meter's side is decided by the crossing parity (a meter within the tolerance of the shell: not
  decided, so not proven);
* materials: only shader nodes through which no light passes (``shader_kinds.SEALING_SHADERS``, a
  whitelist: a Principled BSDF without alpha, transmission or subsurface, diffuse, glossy, metallic, sheen,
  toon, emission and their mixes), inside node groups too; geometry that is not triangulated (curves,
  point clouds, particle hair) proves nothing;
* tolerances: vertices welded within two float32 steps of the shell's largest coordinate
  (``WELD_FLOAT32_STEPS``); a crack narrower than that between two objects' edges counts as closed.
"""

import numpy as np

from . import visibility
from ..skies import sky_aperture

__all__ = ["source_extents", "sealed_off"]

_CUBE = np.array([[x, y, z] for x in (-1.0, 1.0) for y in (-1.0, 1.0) for z in (-1.0, 1.0)])


#: How far apart (in float32 steps of the largest coordinate) two vertices may be and still be one vertex of a
#: shell: a slit narrower than this reads as closed (2 steps: 0.5 mm at 2 km from the origin, 0.24 um at 1 m).
WELD_FLOAT32_STEPS = 2.0


def source_extents(model):
    """Every source of the model that emits: a list of (points (K, 3) m, reach m) or "infinity" (the sun,
    the world), or None when some source's extent is unknown or its light ignores surfaces."""
    if model.volumes or model.world_volume:
        return None  # a volume's shader may emit: its light's extent is not read
    if model.needs.get("blocker_linking", False):
        return None  # an object's shadow linking may let its light through the shell
    if model.geometry.unmodelled or model.needs.get("hair_particles", False):
        return None  # geometry not triangulated (curves, point clouds, particle hair) may emit or leak
    out = []
    for light in model.lights:
        if light.portal:
            continue  # guides world sampling, emits nothing
        if light.spec is None or not light.casts_shadow:
            return None
        if not light.spec.has_position:
            out.append("infinity")
            continue
        extent = light.spec.extent()
        if extent is None:
            return None
        out.append(extent)
    for mesh in model.emissive_meshes:
        extent = mesh.extent()
        if extent is None:
            return None
        out.append(extent)
    if model.needs.get("emissive_surfaces", False) and not model.emissive_meshes:
        return None  # surfaces emit, but were not read as emitters
    if model.world_emits:
        out.append("infinity")
    return out


def _box(points, grow):
    lo, hi = points.min(axis=0) - grow, points.max(axis=0) + grow
    centre, half = 0.5 * (lo + hi), 0.5 * (hi - lo)
    return centre, (centre + _CUBE * half, np.eye(3), np.eye(3))


def sealed_off(model, points_m):
    """(N,) bool: meters at ``points_m`` (N, 3) m that no source of ``model`` can reach (every source is
    cut off from them by a closed shell of sealing triangles; or, for meters outside the box round the scene, every
    source lies in a shell whose openings look out on nothing, ``_behind_open_shell``, or inside that box whose faces
    before the meter are covered whole, ``_behind_covered_faces``); and a note (str) saying how, or ""."""
    points_m = np.atleast_2d(np.asarray(points_m, float))
    none = np.zeros(len(points_m), bool)
    g = model.geometry
    sources = source_extents(model)
    if not sources or not g.count:
        return none, ""
    sealing = g.triangles[g.sealing_triangles()]
    if not len(sealing):
        return none, ""
    # Vertices are welded within two float32 steps of the shell's own coordinates (its mesh and transform
    # were float32): a gap wider than that is a gap.
    shell_tol = WELD_FLOAT32_STEPS * np.finfo(np.float32).eps * max(1.0, float(np.max(np.abs(sealing))))
    shells = sky_aperture.closed_components(sealing, shell_tol)
    # cut[s] (N,) bool: source s is cut off from each meter by some shell
    cut = np.zeros((len(sources), len(points_m)), bool)
    for idx in shells:
        tris = sealing[idx]
        meter_side = np.array([{True: 1, False: 0, None: -1}[v]
                               for v in sky_aperture.inside_enclosures(points_m, tris, [], shell_tol)])
        for s, source in enumerate(sources):
            if isinstance(source, str):
                side = 0  # at infinity: outside every shell
            else:
                points, reach = np.asarray(source[0], float).reshape(-1, 3), float(source[1])
                centre, box = _box(points, reach + shell_tol)
                if np.any(visibility.triangles_meet_polytope(tris, box, shell_tol)):
                    continue  # the source may touch or cross this shell: it cuts nothing off
                inside = sky_aperture.inside_enclosure(centre, tris, [], shell_tol)
                if inside is None:
                    continue
                side = int(inside)
            cut[s] |= (meter_side >= 0) & (meter_side != side)
    dark = np.all(cut, axis=0) if shells else none.copy()
    why = ("sealed off: a closed opaque shell of surfaces that stop every ray lies between the meter and every light "
           "source: exactly 0, nothing rendered (radiometry/scene/sealed.py)") if dark.any() else ""
    lo, hi = g.bounds()  # the box round the scene's triangles
    proofs = ((lambda pts: _behind_open_shell(model, sealing, sources, pts, shell_tol),
               "sealed off: every light source lies inside a closed opaque shell whose openings look out on nothing "
               "(every surface of the scene lies behind each opening's plane, the world is black), and the meter is "
               "outside it, behind every opening's plane: light leaving an opening travels on in front of it and never "
               "returns; exactly 0, nothing rendered (radiometry/scene/sealed.py)"),
              (lambda pts: _behind_covered_faces(model, sources, pts, shell_tol, lo, hi),
               "sealed off: every light source lies inside the box round the scene's surfaces, the world is black, "
               "and the meter is outside that box, in front only of faces of it that opaque surfaces cover whole (a "
               "room of boxes: its walls' outer faces): light leaves the box only through the other faces and never "
               "returns; exactly 0, nothing rendered (radiometry/scene/sealed.py)"))
    # The proofs below are searched only when some meter stands outside the box round the scene's triangles (for a
    # batch of meters in a room their search, seconds for a shell of thousands of triangles, is skipped; a meter they
    # could prove inside that box, e.g. beside a building on a ground plane, is then left to the render).
    beyond = np.any((points_m < lo - shell_tol) | (points_m > hi + shell_tol), axis=1)
    for proof, reason in proofs:  # the meters still in doubt, each proof in turn
        if not np.any(beyond & ~dark):
            break
        behind = proof(points_m[~dark])
        if behind.any():
            dark[np.flatnonzero(~dark)[behind]] = True
            why = (why + "; " if why else "") + reason
    return dark, why


#: Most distinct grid lines per axis on one face of the bounding box for ``_face_covered`` (else: not proven).
FACE_GRID_MAX = 512


def _half_rectangles(flat, tol):
    """Axis-aligned rectangles (R, 4) (u0, u1, v0, v1) that pairs of the 2-D triangles ``flat`` (T, 3, 2) cover
    whole: two right triangles with axis-aligned legs on the same rectangle, missing opposite corners (a quad split
    along a diagonal, as every box face is). Other triangles are left out (they may cover more: never counted)."""
    lo, hi = flat.min(axis=1), flat.max(axis=1)                                          # (T, 2)
    near_lo, near_hi = np.abs(flat - lo[:, None]) <= tol, np.abs(flat - hi[:, None]) <= tol  # (T, 3, 2)
    at_corner = np.all(near_lo | near_hi, axis=2)                                        # (T, 3)
    code = 2 * near_lo[..., 0] + near_lo[..., 1]                                         # corner 0..3 of each vertex
    distinct = ((code[:, 0] != code[:, 1]) & (code[:, 1] != code[:, 2]) & (code[:, 0] != code[:, 2]))
    sized = np.all(hi - lo > tol, axis=1)
    half = np.flatnonzero(np.all(at_corner, axis=1) & distinct & sized)  # a right triangle on 3 corners of its box
    if not half.size:
        return np.zeros((0, 4))
    missing = 6 - code[half].sum(axis=1)                                                 # the corner it leaves
    keys = np.round(np.c_[lo[half], hi[half]] / tol).astype(np.int64)
    _uniq, first, group = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    masks = np.zeros(group.max() + 1, np.int64)
    np.bitwise_or.at(masks, group.ravel(), np.left_shift(1, missing))
    whole = ((masks & 0b1001) == 0b1001) | ((masks & 0b0110) == 0b0110)                 # opposite corners: 0-3, 1-2
    take = half[first[whole]]
    return np.c_[lo[take, 0], hi[take, 0], lo[take, 1], hi[take, 1]]


def _face_covered(rects, u_range, v_range, tol):
    """True when the axis-aligned ``rects`` (R, 4) cover the face u_range x v_range whole: the grid through every
    rectangle's sides cuts the face into cells each inside or outside every rectangle; each cell's centre must lie
    in one of them."""
    if not len(rects):
        return False
    us = np.unique(np.clip(np.r_[u_range, rects[:, 0], rects[:, 1]], *u_range))
    vs = np.unique(np.clip(np.r_[v_range, rects[:, 2], rects[:, 3]], *v_range))
    if len(us) > FACE_GRID_MAX or len(vs) > FACE_GRID_MAX:
        return False
    cu, cv = 0.5 * (us[1:] + us[:-1]), 0.5 * (vs[1:] + vs[:-1])
    cu, cv = cu[np.diff(us) > tol], cv[np.diff(vs) > tol]  # slivers narrower than the tolerance are cracks welded
    # the cells whose centres each rectangle holds, counted by a 2-D difference array (one pass for all rectangles)
    i0, i1 = np.searchsorted(cu, rects[:, 0] - tol, "left"), np.searchsorted(cu, rects[:, 1] + tol, "right")
    j0, j1 = np.searchsorted(cv, rects[:, 2] - tol, "left"), np.searchsorted(cv, rects[:, 3] + tol, "right")
    count = np.zeros((len(cu) + 1, len(cv) + 1), np.int64)
    for i, j, sign in ((i0, j0, 1), (i1, j0, -1), (i0, j1, -1), (i1, j1, 1)):
        np.add.at(count, (i, j), sign)
    return bool(np.all(count.cumsum(axis=0).cumsum(axis=1)[:-1, :-1] > 0))


def _behind_covered_faces(model, sources, points_m, tol, lo, hi):
    """(N,) bool: meters that no light reaches because every source lies inside the box round the scene's
    triangles, the world is black (no source at infinity; ``source_extents`` refuses media), and the meter is
    outside the box and in front only of faces that opaque sealing triangles lying in them cover whole: light
    crossing the box's boundary meets such a face's triangles, or leaves through another face into that face's
    open front half-space, where nothing is, and never returns (a room of separate boxes, whose walls' outer faces
    cover the box's faces but for its windows). Coverage is counted from pairs of triangles that make axis-aligned
    rectangles (``_half_rectangles``) only. ``lo``, ``hi``: the box (``SceneGeometry.bounds``). Every doubt proves
    nothing."""
    none = np.zeros(len(points_m), bool)
    g = model.geometry
    if not len(points_m) or not g.count or any(isinstance(source, str) for source in sources):
        return none
    ok = np.any((points_m < lo - tol) | (points_m > hi + tol), axis=1)  # outside the box
    if not ok.any():
        return none  # (meters in a room: the faces' coverage is not needed)
    for points, reach in sources:  # every source wholly inside the box
        pts = np.asarray(points, float).reshape(-1, 3)
        if np.any(pts.min(axis=0) - reach < lo + tol) or np.any(pts.max(axis=0) + reach > hi - tol):
            return none
    key = ("covered faces", tol)
    if key not in model.derived:
        model.derived[key] = _covered_faces(g, lo, hi, tol)
    covered = model.derived[key]
    for axis in range(3):
        for side, plane in ((0, lo[axis]), (1, hi[axis])):
            if covered[axis][side]:
                continue
            ahead = (plane - points_m[:, axis]) if side == 0 else (points_m[:, axis] - plane)
            ok &= ahead < -tol  # strictly behind this face's plane (inside its half-space of the box)
    return ok


def _covered_faces(g, lo, hi, tol):
    """covered[axis][side] (bool): whether opaque sealing triangles of ``g`` lying in each face of the box ``lo`` ..
    ``hi`` round its triangles cover that face whole (``_face_covered``)."""
    sealing = g.triangles[g.sealing_triangles()]
    covered = [[False, False] for _ in range(3)]
    for axis in range(3):
        u_axis, v_axis = (axis + 1) % 3, (axis + 2) % 3
        for side, plane in ((0, lo[axis]), (1, hi[axis])):
            on = np.all(np.abs(sealing[:, :, axis] - plane) <= tol, axis=1)
            if not on.any():
                continue
            rects = _half_rectangles(sealing[on][:, :, [u_axis, v_axis]], tol)
            covered[axis][side] = _face_covered(rects, (lo[u_axis], hi[u_axis]), (lo[v_axis], hi[v_axis]), tol)
    return covered


#: How far a pane's face in front of an opening may be from perpendicular to its plane, or lean towards the room
#: (|cos| or -cos of its front normal with the opening's normal): ten float32 steps (the faces' coordinates are
#: float32).
FACE_COS_TOL = 10.0 * float(np.finfo(np.float32).eps)


def _open_shell(model, sealing, tol):
    """(shell triangles, opening loops, their outward normals) of the closed shell of ``sealing`` triangles with
    convex openings whose front half-spaces hold nothing of the scene (``_behind_open_shell``), or None; found
    once per capture (``model.derived``)."""
    key = ("open shell", tol)
    if key in model.derived:
        return model.derived[key]
    thickness = {k: float(getattr(pane, "thickness", 0.0)) for k, pane in model.panes.items()}
    model.derived[key] = found = _find_open_shell(model.geometry, thickness, sealing, tol)
    return found


def _keeps_going(tris, front_sign, slab, poly, centre, normal, tol):
    """True when the thin-pane triangles ``tris`` (T, 3, 3) in front of an opening send no light back: each lies in
    the opening's prism, and, with m its winding normal times ``front_sign`` (T,) (Cycles' front side: -1 for a
    mirrored object, 0 where not known), either is perpendicular to the plane (|m . ``normal``| <= ``FACE_COS_TOL``)
    or belongs to a ``slab`` (T,) bool and does not face the room (m . n >= -``FACE_COS_TOL``). The thin-pane
    stand-in (``measure.capture.glass.thin_pane_material``) passes a ray straight on, or mirrors it about the face:
    a slab's face only where the ray meets its front (d . m < 0), a single face from either side. A mirror leaves
    d . n - 2 (d . m)(m . n): unchanged about a perpendicular face, and no smaller about a slab's face that does not
    face the room where d . m < 0. So a ray leaving the room keeps moving away. Anything else in front (a single
    face parallel to the plane, a face turned to the room, a slab of unknown front) may mirror leaving light back
    past the wall."""
    if not np.all(sky_aperture.inside_prism(tris.reshape(-1, 3), poly, centre, normal, tol)):
        return False
    m = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    m = m / np.maximum(np.linalg.norm(m, axis=1, keepdims=True), 1e-300)
    c = m @ normal
    facing_away = slab & (front_sign != 0) & (front_sign * c >= -FACE_COS_TOL)
    return bool(np.all((np.abs(c) <= FACE_COS_TOL) | facing_away))


def _find_open_shell(g, pane_thickness, sealing, tol):
    """``_open_shell``'s search; ``pane_thickness``: {object index: thickness m} of the model's thin panes."""
    if len(sealing) > sky_aperture.CLOSURE_MAX_TRIANGLES:
        return None  # the search's cost grows faster than the scene: not proven
    loops = [poly for poly, _normal in sky_aperture.find_apertures(sealing, tol)]
    if not loops or not all(sky_aperture.is_convex(poly, tol) for poly in loops):
        return None  # (a cap of a concave loop, fanned, may not close it for the parity test)
    closed, comp, _why = sky_aperture.enclosure_closed(sealing, loops, tol)
    if not closed:
        return None
    shell = sealing[comp]
    shell_vertices = shell.reshape(-1, 3)
    thin_pane = np.isin(g.pane_of, list(pane_thickness)) & (g.pane_of >= 0)
    thick = np.zeros(max(len(g.object_names), 1))
    for k, t in pane_thickness.items():
        thick[k] = t
    slab = thin_pane & (thick[np.maximum(g.pane_of, 0)] > 0.0)
    mirrored = g.mirrored
    if mirrored is None or len(mirrored) != len(g.object_names):
        front_sign = np.zeros(g.count)  # Cycles' front side not known: perpendicular faces only
    else:
        front_sign = np.where(np.asarray(mirrored, bool)[g.object_index], -1.0, 1.0)
    normals = []
    for poly in loops:
        centre = poly.mean(axis=0)
        normal, _offset = sky_aperture.polygon_plane(poly)
        if np.max((shell_vertices - centre) @ normal) > tol:
            normal = -normal
        front = np.any((g.triangles - centre) @ normal > tol, axis=1)
        if np.any(front & ~thin_pane) or not _keeps_going(g.triangles[front], front_sign[front], slab[front], poly,
                                                           centre, normal, tol):
            return None  # something (of the shell or outside it) stands in front of this opening
        normals.append(normal)
    return shell, loops, normals


def _behind_open_shell(model, sealing, sources, points_m, tol):
    """(N,) bool: meters that no light reaches because every source lies inside a closed shell of ``sealing``
    triangles with openings (holes of planar faces, ``sky_aperture.find_apertures``; convex, so that their caps
    close it for the parity test) whose front half-spaces hold nothing: every triangle of the scene lies behind or
    on each opening's plane (within ``tol``) but a thin pane's in the opening that sends nothing back
    (``_keeps_going``), and no source is at infinity (the world, the sun). A path from a
    source to a point outside crosses the shell only through an opening, moving into its open front half-space; it
    meets nothing there and never comes back. So a meter outside the shell and behind every opening's plane (by
    more than ``tol``) receives nothing. Every doubt proves nothing."""
    none = np.zeros(len(points_m), bool)
    if not len(points_m) or any(isinstance(source, str) for source in sources):
        return none  # the world or the sun lights the outside
    found = _open_shell(model, sealing, tol)
    if found is None:
        return none
    shell, loops, normals = found
    front = np.zeros(len(points_m), bool)  # a meter in front of some opening may see it
    for poly, normal in zip(loops, normals):
        front |= (points_m - poly.mean(axis=0)) @ normal >= -tol
    if front.all():
        return none
    caps = np.concatenate([sky_aperture.fan_triangles(poly) for poly in loops])
    for points, reach in sources:  # every source wholly inside, clear of the shell and of its openings
        centre, box = _box(np.asarray(points, float).reshape(-1, 3), float(reach) + tol)
        if np.any(visibility.triangles_meet_polytope(np.concatenate([shell, caps]), box, tol)):
            return none
        if sky_aperture.inside_enclosure(centre, shell, loops, tol) is not True:
            return none
    out = none.copy()  # the parity test (arrays of meters x triangles) only where it can prove something
    candidates = np.flatnonzero(~front)
    out[candidates] = [v is False for v in sky_aperture.inside_enclosures(points_m[candidates], shell, loops, tol)]
    return out
