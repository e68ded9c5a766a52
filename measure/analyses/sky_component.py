"""The sky component (SC) of daylight-factor readings, proven in closed form (issue 31).

For each point, ``sky_components`` captures the scene (``meter.capture_model``: render-visible
triangles in metres), finds its apertures (``radiometry.sky_aperture.find_apertures``: holes in
planar groups of triangles) and states the direct light of the CIE overcast sky through them, exact,
only when all of these are proven:

1. every aperture is convex, and open or glazed with one recognised colour-neutral thin pane (then its
   T(theta) weighs the directions entering the pane's near face, ``_pane_in_opening``, with a hard
   bound from ``sky_aperture.pane_bounded_illuminance``: ``bound_lux``);
2. the opaque, shadow-casting triangles connected to the apertures (found among those triangles
   only, so that a pane does not close its opening) form a surface closed apart from them
   (``enclosure_closed``), the point is inside it (``inside_enclosure``), and the scene has no geometry
   without triangles and no participating medium: so every sky direction from the point leaves
   through an aperture or meets that opaque surface;
3. for each aperture, nothing stands in the directions from the point through it above the point's
   horizontal plane, out past every triangle of the scene (``aperture_clear``); or only opaque, shadow-casting
   triangles do (a building across the street, a cabinet by the window, an awning), none passing too near the
   point: then the sky is integrated over the aperture minus their silhouettes, exactly
   (``radiometry.skies.obstructed_aperture``), and the ground seen through that aperture is not stated.

Then SC = sum over apertures of the closed form (``aperture_illuminance``), and the world's ground
seen directly through the apertures (its luminance rho_g E_h / pi below the sharp horizon) is stated
too where the whole pyramid (below the horizontal plane as well) is proven clear. Otherwise the
reading's SC is None with the reason.

``daylight_factor`` (``method="auto"``) reads the SC from here where it is proven and renders only
the rest: ``gate_world`` darkens the temporary sky where a sensor would see it straight (Light Path
Ray Depth, the world's light sampling off), ``check_world_gate`` proves that gate once per Blender
session and device (docs/daylight-sky.md).
"""

import dataclasses
import math

import numpy as np

from ...radiometry.scene import scene_model
from ...radiometry.skies import sky_aperture


@dataclasses.dataclass
class SkyComponent:
    """``sky_lux``: the direct illuminance from the sky through the openings (lux; None when not
    proven), ``ground_lux``: from the world's ground seen directly through them (None when not
    proven), ``reason``: why not (empty when both are proven), ``apertures``: how many were used,
    ``inside``: the point is proven inside the closed room holding the openings."""

    sky_lux: object
    ground_lux: object
    reason: str
    apertures: int
    inside: bool = False
    #: lux: the hard bound on sky_lux + ground_lux from panes in openings (their T(theta) integrated by
    #: bounding subdivision, ``sky_aperture.pane_bounded_illuminance``); 0 where every opening is open
    bound_lux: float = 0.0
    #: openings seen through a recognised thin pane
    glazed: int = 0
    #: openings whose sky is seen past obstructions, their silhouettes clipped exactly
    #: (``radiometry.skies.obstructed_aperture``)
    clipped: int = 0
    #: why the room's proof was not used (no closed room holds the openings, or the point is outside the closed shell
    #: that holds them): the sky was integrated over every direction from the point that meets no surface at all
    #: (``obstructed_aperture.open_directions``); "" where the room's proof held
    past_every_surface: str = ""


#: Why a point's sky was taken past every surface where a closed shell with openings was found (``past_every_surface``):
#: outside it (the solid of thick walls whose window is a tunnel through it: the room's air lies outside), or where
#: the ray-parity test could not tell.
OUTSIDE_SHELL = "the point is outside the only closed shell with openings (the solid of thick walls, or a point outdoors)"
UNDECIDED_SHELL = "the point is not proven inside the closed shell with openings"
OUTSIDE_SHELL_ALL = "the points are outside the only closed shell with openings (the solid of thick walls, or outdoors)"


def _no_room(why):
    """``past_every_surface`` where no closed shell with openings was found (``why``: ``_closed_shell``'s reason)."""
    return f"no closed room holds the openings: {why}"


def _scene_refusal(model):
    g = model.geometry
    if g.unmodelled:
        return "geometry without triangles may let sky in or block it"
    if model.volumes or model.world_volume:
        return "a participating medium attenuates and scatters the sky's light"
    if not g.count:
        return "no surfaces: the meter's own sky proof applies"
    return ""


def opaque_mask(model):
    """The captured triangles that close a room and block the sky: opaque, of objects that stop every kind of ray
    (the meter's first ray, diffuse, glossy, shadow: an object hidden from diffuse rays but casting shadows would
    let the meter see the sky through it) and of a material that lets no light through
    (``SceneGeometry.sealing_triangles``)."""
    return model.geometry.sealing_triangles()


def _closed_shell(model, points_m=()):
    """(loops, shell triangles, all triangles, tol, reach) of the model's convex openings in a closed
    opaque shell (conditions 1-2 of the module's docstring), or the reason (str) why not."""
    why = _scene_refusal(model)
    if why:
        return why
    lo, hi = model.geometry.bounds()
    tol = _proof_tolerance(model, points_m)
    key = ("closed_shell", tol)
    if key not in model.derived:
        model.derived[key] = _find_shell(model, tol, float(np.linalg.norm(hi - lo)) + 1.0)
    return model.derived[key]


def _proof_tolerance(model, points_m):
    """The proofs' length tolerance (m): ten float32 steps of the largest coordinate, the scene's or the points'."""
    lo, hi = model.geometry.bounds()
    return 10.0 * scene_model.length_tolerance(np.r_[lo, hi, np.asarray(points_m, float).ravel()])


def _find_shell(model, tol, reach):
    tris = model.geometry.triangles
    sealing = tris[opaque_mask(model)]
    found = sky_aperture.find_apertures(sealing, tol)  # a pane's faces do not close an opening
    if not found:
        return "no opening found in the scene's surfaces"
    # the edges' pieces once for both searches below (the costly part: every edge against every vertex)
    pieces = sky_aperture.edge_pieces(sealing, tol) if len(sealing) <= sky_aperture.CLOSURE_MAX_TRIANGLES else None
    # a hole in a plane that other faces close is no opening (a window frame's ring, a tunnel's mouth)
    loops = sky_aperture.shell_holes(sealing, [poly for poly, _normal in found], tol, pieces=pieces)
    if not loops:
        return ("no opening found in the scene's surfaces (the holes found in planes are closed by other faces: "
                "a tunnel through a solid, a frame's ring)")
    bent = [k for k, poly in enumerate(loops) if not sky_aperture.is_convex(poly, tol)]
    if bent:
        return f"{len(bent)} opening(s) are not convex (the closed form needs convex ones)"
    closed, comp, why = sky_aperture.enclosure_closed(sealing, loops, tol, pieces=pieces)
    if not closed:
        return why
    return loops, sealing[comp], tris, tol, reach


def _clear_proofs(points_m, inner, loops, tris, tol, reach):
    """``clear_at(i, k, sky_only, ignore)``: whether nothing stands in point i's view through opening k
    (``sky_aperture.apertures_clear``; ``ignore`` holds the opening's coplanar wall); each proof is found for every
    point of ``inner`` at once, the first time it is asked, and remembered."""
    proofs = {}  # (opening, sky_only, what is set aside) -> (P,) the proof at every point inside

    def clear_at(i, k, sky_only, ignore):
        key = (k, bool(sky_only), np.packbits(ignore).tobytes())
        if key not in proofs:
            proofs[key] = np.zeros(len(points_m), bool)
            proofs[key][inner] = sky_aperture.apertures_clear(points_m[inner], loops[k], tris, tol, reach,
                                                              sky_only=sky_only, ignore=ignore, coplanar_checked=True)
        return bool(proofs[key][i])

    return clear_at


class _PastObstructions:
    """The overcast sky's direct light at a point through an opening past the triangles in the way, their
    silhouettes clipped (``obstructed_aperture.unblocked_pieces``). What meets each point's pyramid above its
    horizon is found for every point of ``inner`` at once, the first time an opening is asked, and remembered."""

    def __init__(self, points_m, normals, inner, loops, tris, tol, reach, see_through, zenith_luminance):
        self.points_m, self.normals, self.inner, self.loops = points_m, normals, inner, loops
        self.tris, self.tol, self.reach, self.see_through, self.lz = tris, tol, reach, see_through, zenith_luminance
        self._found = {}

    def blockers(self, i, k, wall):
        """Indices of the triangles that meet point i's pyramid through opening k (None: no pyramid)."""
        if k not in self._found:
            self._found[k] = dict(zip(self.inner.tolist(), sky_aperture.apertures_blockers(
                self.points_m[self.inner], self.loops[k], self.tris, self.tol, self.reach, sky_only=True,
                ignore=wall, coplanar_checked=True)))
        return self._found[k].get(i)

    def see_through_among(self, i, k, wall):
        b = self.blockers(i, k, wall)
        return b is not None and bool(np.any(self.see_through[b]))

    def sky(self, i, k, wall):
        """lux past the opaque triangles in the way, or the reason (str) why not."""
        from ...radiometry.skies import obstructed_aperture

        blockers = self.blockers(i, k, wall)
        if blockers is None:
            return "the point lies at an opening's edge"
        if np.any(self.see_through[blockers]):
            return "a surface may stand between the point and the sky through an opening (see-through ones among it)"
        pieces = obstructed_aperture.unblocked_pieces(self.points_m[i], self.loops[k], self.tris[blockers], self.tol)
        if isinstance(pieces, str):
            return pieces
        if not pieces:
            return 0.0
        p, n = self.points_m[i], self.normals[i]
        e = sky_aperture.aperture_illuminance(pieces, [p] * len(pieces), [n] * len(pieces),
                                              zenith_luminance=self.lz, ground_luminance=0.0)[0]
        return float(np.sum(e))


def sky_components(scene, points_m, normals, *, ground_reflectance, horizontal_lux, model=None, target_rel_error=0.01):
    """One :class:`SkyComponent` per point (``points_m`` (N, 3) in metres, unit ``normals`` (N, 3)) for the
    CIE overcast sky of unobstructed horizontal illuminance ``horizontal_lux`` over a ground of
    ``ground_reflectance``."""
    from ..meter import point_meter as meter
    from .analysis_common import view_layer_of

    model = model or meter.capture_model(scene, view_layer_of(scene))
    points_m, normals = np.asarray(points_m, float), np.asarray(normals, float)

    def refuse(why):
        return [SkyComponent(None, None, why, 0) for _ in range(len(points_m))]

    shell = _closed_shell(model, points_m)
    lz = 9.0 * horizontal_lux / (7.0 * math.pi)            # overcast: E_h = 7 pi Lz / 9
    if isinstance(shell, str):
        why = _scene_refusal(model)
        return refuse(shell) if why else _sky_past_every_surface(
            model, points_m, normals, lz, _no_room(shell), PANE_TOL_SHARE * float(target_rel_error or 0.01))
    loops, shell, tris, tol, reach = shell
    lg = ground_reflectance * horizontal_lux / math.pi
    # The wall around each opening, coplanar with it, cannot block a direction through it: found once per
    # opening, not per point (``aperture_clear``'s ``ignore``).
    around = [sky_aperture.coplanar_outside(tris, poly, tol) for poly in loops]
    pane_tol = PANE_TOL_SHARE * float(target_rel_error or 0.01)  # a pane's T(theta) bound, relative
    see_through = ~opaque_mask(model)
    # the open openings' closed forms, every point at once (used where the view through is proven clear)
    open_lux = [sky_aperture.aperture_illuminance(poly, points_m, normals, zenith_luminance=lz, ground_luminance=lg)
                for poly in loops]
    states, jobs = [], []  # per point [sky, ground, why, bound, glazed, pane jobs]; jobs (point, glazing, opening)
    insides = sky_aperture.inside_enclosures(points_m, shell, loops, tol)
    inner = np.flatnonzero([v is True for v in insides])
    # A point outside the closed shell is not in the dark for that: the shell may be the solid of thick walls whose
    # window is a tunnel through it (one mesh, walls with depth), the room's air outside it. Such points, and those
    # the parity test could not place, take the proof that needs no room: the sky over every direction that meets no
    # surface (``_sky_past_every_surface``).
    past_shell = {}
    for state, where in ((False, OUTSIDE_SHELL), (None, UNDECIDED_SHELL)):
        idx = np.flatnonzero([v is state for v in insides])
        if idx.size:
            found = _sky_past_every_surface(model, points_m[idx], normals[idx], lz, where, pane_tol)
            past_shell.update(zip(idx.tolist(), found))
    clear_at = _clear_proofs(points_m, inner, loops, tris, tol, reach)
    past = _PastObstructions(points_m, normals, inner, loops, tris, tol, reach, see_through, lz)

    for i, (p, n) in enumerate(zip(points_m, normals)):
        inside = insides[i]
        if inside is not True:
            states.append(past_shell[i])
            continue
        sky, ground, why, pending, clipped = 0.0, 0.0, "", [], 0
        for k, ((poly, wall), (s_all, g_all)) in enumerate(zip(zip(loops, around), open_lux)):
            s, gr = float(s_all[i]), float(g_all[i])

            def clear(sky_only, ignore=wall, i=i, k=k):
                return clear_at(i, k, sky_only, ignore)

            # the whole pyramid clear proves its part above the horizon clear too: one test where it holds
            whole = clear(False) if gr > 0.0 and ground is not None else None
            if s > 0.0 and not whole and not clear(True):
                if clear(True, wall | see_through):
                    pane = _pane_in_opening(model, p, poly, tol, clear, wall, sky_only=gr <= 0.0)
                    if isinstance(pane, str):
                        sky, why = None, pane
                        break
                    pending.append((len(jobs), gr > 0.0))  # its T(theta) bound: all points' together, below
                    jobs.append((i, pane, poly))
                    continue
                # opaque triangles in the way: the sky past their silhouettes, exactly; the ground seen through
                # this opening is then not stated (what they reflect, and the ground around them, is rendered)
                if past.see_through_among(i, k, wall):  # a pane in the opening, opaque obstructions beyond it
                    pane = _pane_in_opening(model, p, poly, tol, clear, wall, sky_only=True,
                                            beyond=(past.blockers(i, k, wall), tris))
                    if isinstance(pane, str):
                        sky, why = None, pane
                        break
                    pending.append((len(jobs), False))
                    jobs.append((i, pane, poly))
                    clipped += 1
                    if gr > 0.0:
                        ground = None
                    continue
                seen = past.sky(i, k, wall)
                if isinstance(seen, str):
                    sky, why = None, seen
                    break
                sky, clipped = sky + seen, clipped + 1
                if gr > 0.0:
                    ground = None
                continue
            sky += s
            if ground is not None and gr > 0.0:
                ground = ground + gr if whole else None
        states.append([sky, ground, why, 0.0, 0, pending if sky is not None else [], clipped])
    wanted = sorted({j for st in states if isinstance(st, list) for j, _g in st[5]})
    through = _through_panes([jobs[j] for j in wanted], points_m, normals, lz, lg, pane_tol)
    through = dict(zip(wanted, through))
    out = []
    for st in states:
        if isinstance(st, SkyComponent):
            out.append(st)
            continue
        sky, ground, why, bound, glazed, pending, clipped = st
        for j, ground_seen in pending:
            (e_sky, h_sky), (e_ground, h_ground) = through[j]
            sky, bound, glazed = sky + e_sky, bound + h_sky + h_ground, glazed + 1
            if ground is not None and ground_seen:
                ground = ground + e_ground if jobs[j][1].whole else None
        if sky is None:
            ground = None
        elif ground is None:
            why = "a surface outside may stand in front of the world's ground seen through an opening"
        out.append(SkyComponent(sky, ground, why, len(loops), True, bound, glazed, clipped if sky is not None else 0))
    return out


#: Opaque triangles above which ``_sky_past_every_surface`` is not tried (its cost grows with them, about
#: 40 ms a point for a room of nine boxes): a scene whose room is not one closed shell is then rendered whole.
PAST_EVERY_SURFACE_MAX_TRIANGLES = 5000


def _sky_past_every_surface(model, points_m, normals, lz, no_shell, rel_tol):
    """Where no closed room holds the openings or the point (``no_shell`` says why; e.g. walls, floor and roof built of
    separate boxes): per point the CIE overcast sky over every direction above the point's plane that meets no
    triangle that stops every kind of ray (``_open_directions``), exact, when every other triangle in those
    directions belongs to a recognised colour-neutral thin pane: the directions entering a pane's near face
    (``_pane_core``) carry its T(theta), bounded by subdivision to ``rel_tol`` (``pane_bounded_illuminances``), the
    rest of its silhouette (its rim) lies between 0 and the open sky (half of it stated, half the bound), and the
    directions beside it are open sky. The ground seen straight is not stated (the caller renders it)."""
    from ...radiometry.skies import obstructed_aperture

    g = model.geometry
    pane_of = np.asarray(g.pane_of if g.pane_of is not None else np.full(g.count, -1), int)
    panes = {i: pane for i, pane in (model.panes or {}).items() if pane.geometry is not None and not pane.trick}
    in_pane = ~opaque_mask(model) & np.isin(pane_of, list(panes))
    pane_tris = {i: g.triangles[in_pane & (pane_of == i)] for i in panes}
    found, tol = _open_directions(model, points_m, normals, in_pane)
    if isinstance(found, str):
        return [SkyComponent(None, None, f"{no_shell}; {found}", 0) for _ in range(len(points_m))]
    out, jobs = [], {}  # jobs: pane index -> [(point, core polygon)]
    for i, (p, n, pieces) in enumerate(zip(points_m, normals, found)):
        why = pieces if isinstance(pieces, str) else ""
        sky, bound, glazed = 0.0, 0.0, set()
        free, banded = [], []  # open sky; (whole piece, its part beside the pane) of pieces a pane meets
        for q in ([] if why else pieces):
            met = []
            for k, pt in pane_tris.items():
                rest = obstructed_aperture.unblocked_pieces(p, q, pt, tol)
                if isinstance(rest, str):
                    why = rest
                    break
                if _area(rest) < _area([q]) * (1.0 - 1e-12):
                    met.append((k, rest))
            if why:
                break
            if not met:
                free.append(q)
                continue
            if len(met) > 1:
                why = "directions to the sky pass through two panes (rendered)"
                break
            k, rest = met[0]
            pane = panes[k]
            if len({float(v) for v in pane.tint_t}) > 1 or len({float(v) for v in pane.absorption}) > 1 \
                    or len({float(v) for v in pane.tint_r}) > 1:
                why = f"the pane {pane.source or pane.name!r} is tinted (its T differs by colour: rendered)"
                break
            margin = 2.0 * max(float(tol), float(getattr(pane.geometry, "tol", 0.0)))
            core = _pane_core(pane.geometry, p, q, margin)
            banded.append((q, rest, core))
            free += rest
            glazed.add(k)
            if core is not None:
                jobs.setdefault(k, []).append((i, core))
        if why:
            out.append(SkyComponent(None, None, f"{no_shell}; past every surface: {why}", 0))
            continue
        if free:
            sky = float(np.sum(sky_aperture.aperture_illuminance(free, [p] * len(free), [n] * len(free),
                                                                 zenith_luminance=lz, ground_luminance=0.0)[0]))
        for q, rest, core in banded:  # the rim: the pane's silhouette outside its core, between 0 and the open sky
            whole = [q] + ([core] if core is not None else [])
            e = sky_aperture.aperture_illuminance(whole, [p] * len(whole), [n] * len(whole), zenith_luminance=lz,
                                                  ground_luminance=0.0)[0]
            beside = float(np.sum(sky_aperture.aperture_illuminance(rest, [p] * len(rest), [n] * len(rest),
                                                                    zenith_luminance=lz, ground_luminance=0.0)[0])) \
                if rest else 0.0
            band = max(float(e[0]) - beside - (float(e[1]) if core is not None else 0.0), 0.0)
            sky, bound = sky + 0.5 * band, bound + 0.5 * band
        out.append(SkyComponent(sky, None, "the world's ground seen straight is not stated past every surface", 0,
                                False, bound, len(glazed), past_every_surface=no_shell))
    for k, items in jobs.items():  # each pane's cores, every point at once: T(theta) by bounding subdivision
        pane = panes[k]

        def transmittance(c, pane=pane):
            return pane.optics(np.asarray(c, float))[0][..., 1]  # colour-neutral: every channel alike

        idx = [i for i, _core in items]
        est, half, _pieces = sky_aperture.pane_bounded_illuminances(
            [core for _i, core in items], points_m[idx], normals[idx], transmittance, pane.geometry.normal,
            zenith_luminance=lz, ground_luminance=0.0, rel_tol=rel_tol)
        for i, e, h in zip(idx, est, half):
            if out[i].sky_lux is not None:
                out[i].sky_lux += float(e)
                out[i].bound_lux += float(h)
    return out


def _area(polys):
    """Total area (m^2) of planar polygons (K, 3)."""
    return sum(0.5 * float(np.linalg.norm(np.sum(np.cross(q, np.roll(q, -1, axis=0)), axis=0)))
               for q in map(np.asarray, polys))


def _open_directions(model, points_m, normals, see_through_allowed):
    """(per point its directions above its plane that meet no triangle that stops every kind of ray: convex pieces
    (``obstructed_aperture.open_directions``), or the reason (str) why not there; the tolerance), or (the reason
    (str) why not at all, None). A point where any other triangle cuts those directions is refused, except
    triangles marked ``see_through_allowed`` (T,) bool (the caller's recognised panes)."""
    from ...radiometry.skies import obstructed_aperture

    g = model.geometry
    opaque = opaque_mask(model)
    if int(np.count_nonzero(opaque)) > PAST_EVERY_SURFACE_MAX_TRIANGLES:
        return f"the sky past every surface is not tried above {PAST_EVERY_SURFACE_MAX_TRIANGLES} opaque triangles", None
    tol = _proof_tolerance(model, points_m)
    tris, others = g.triangles[opaque], g.triangles[~opaque & ~np.asarray(see_through_allowed, bool)]
    solids = obstructed_aperture.closed_solids(tris, tol, g.object_index[opaque])  # far faces hidden by near ones
    pairs = obstructed_aperture.quad_pairs(tris, tol)  # a box face's two triangles subtracted as one quad
    # each point's side of each solid, all points at once (a ray-parity test per point would repeat the set-up)
    sides = [sky_aperture.inside_enclosures(points_m, tris[idx], [], tol) for idx, _sign in solids]
    out = []
    for i, (p, n) in enumerate(zip(points_m, np.broadcast_to(np.asarray(normals, float), np.shape(points_m)))):
        pieces = obstructed_aperture.open_directions(p, n, tris, tol, solids, pairs, [side[i] for side in sides])
        if isinstance(pieces, str):
            out.append(pieces)
            continue
        if len(others) and pieces:
            kept = _area(pieces)
            rest = [obstructed_aperture.unblocked_pieces(p, q, others, tol) for q in pieces]
            if any(isinstance(r, str) for r in rest) or kept - sum(_area(r) for r in rest) > 1e-9 * kept:
                out.append("a see-through surface that is not a recognised thin pane (or one that casts no shadow) "
                           "stands in the point's view of the sky")
                continue
        out.append(pieces)
    return out, tol


def openings_seen_whole(model, points_m, normals=None):
    """How every point sees the world through the convex openings, sky and ground (conditions 1-3 above with the
    whole pyramid clear, below the horizontal plane too): a list over openings of dicts ``opening`` ((K, 3)
    metres), ``pane`` (None where open, else the recognised colour-neutral thin pane in it) and ``cores`` (with a
    pane: per point the part of the opening whose directions enter its near face, ((N, K, 3) padded, counts (N,)),
    ``_pane_core``), and where opaque triangles stand in some point's view through an open opening ``pieces``:
    per point the list of convex polygons through which it sees past them (``_pieces_past_obstructions``); behind
    a pane with opaque triangles beyond it ``core_pieces`` and ``opening_pieces``: per point the core's and the
    opening's pieces past them; or the reason (str) why not at some point. Daylight coefficients take the patches' direct
    light from them in closed form (``radiometry.skies.patch_aperture``). Where no closed room holds the
    openings (a room of separate boxes), with ``normals`` (N, 3): one view of ``pieces`` per point, every direction
    above its plane that meets no surface (``obstructed_aperture.open_directions`` past the triangles that stop
    every kind of ray), when no other surface stands in any of them; else the reason."""
    points_m = np.atleast_2d(np.asarray(points_m, float))
    shell = _closed_shell(model, points_m)
    if isinstance(shell, str):
        return shell if normals is None or _scene_refusal(model) else _open_views(model, points_m, normals,
                                                                                  _no_room(shell))
    loops, shell, tris, tol, reach = shell
    inside = sky_aperture.inside_enclosures(points_m, shell, loops, tol)
    outside = sum(v is not True for v in inside)
    if all(v is False for v in inside) and normals is not None:
        # every point outside the closed shell: the solid of thick walls whose window is a tunnel through it (the
        # room's air outside it), as ``sky_components`` takes it: the view that needs no room. Points inside and
        # outside at once are refused: one dome render takes one kind of proof for all its meters.
        return _open_views(model, points_m, normals, OUTSIDE_SHELL_ALL)
    if outside:
        return f"{outside} point(s) not proven inside the room holding the openings"
    clear_at = _clear_proofs(points_m, np.arange(len(points_m)), loops, tris, tol, reach)
    see_through = ~opaque_mask(model)
    views = []
    for k, poly in enumerate(loops):
        around = sky_aperture.coplanar_outside(tris, poly, tol)
        if all(clear_at(i, k, False, around) for i in range(len(points_m))):
            views.append({"opening": poly, "pane": None, "cores": None})
            continue
        pieces = _pieces_past_obstructions(points_m, poly, tris, tol, reach, around, see_through)
        if not isinstance(pieces, str):
            views.append({"opening": poly, "pane": None, "cores": None, "pieces": pieces})
            continue
        glazings = []
        beyond = None
        if any(not clear_at(i, k, False, around | see_through) for i in range(len(points_m))):
            # opaque triangles besides the pane in some view: each point's pieces past them (sky and ground)
            beyond = sky_aperture.apertures_blockers(points_m, poly, tris, tol, reach, sky_only=False, ignore=around,
                                                     coplanar_checked=True)
        for i, p in enumerate(points_m):
            def clear(sky_only, ignore, i=i, k=k):
                return clear_at(i, k, sky_only, ignore)

            glazing = _pane_in_opening(model, p, poly, tol, clear, around, sky_only=False,
                                       beyond=None if beyond is None else (beyond[i], tris))
            if isinstance(glazing, str):
                return glazing
            if not glazing.whole:
                return "a surface outside may stand in front of the world's ground seen through an opening's pane"
            glazings.append(glazing)
        if len({id(g.pane) for g in glazings}) != 1:
            return "the points see an opening through different panes"
        k_max = max(len(g.core) for g in glazings)
        cores = np.stack([np.concatenate([g.core, np.repeat(g.core[-1:], k_max - len(g.core), axis=0)])
                          for g in glazings])
        views.append({"opening": poly, "pane": glazings[0].pane,
                      "cores": (cores, np.array([len(g.core) for g in glazings]))})
        if beyond is not None:
            views[-1]["core_pieces"] = [g.core_pieces for g in glazings]
            views[-1]["opening_pieces"] = [g.opening_pieces for g in glazings]
    return views


def _open_views(model, points_m, normals, no_shell):
    """``openings_seen_whole`` where no closed room holds the openings: [{"opening": None, "pane": None, "cores":
    None, "pieces": per point its open directions, "no_room": why no closed room holds them}] or the reason (str) why
    not at some point (no surface but those
    that stop every kind of ray in any point's view: ``_open_directions``)."""
    found, _tol = _open_directions(model, points_m, normals, np.zeros(model.geometry.count, bool))
    if isinstance(found, str):
        return f"{no_shell}; {found}"
    why = next((f for f in found if isinstance(f, str)), None)
    if why is not None:
        return f"{no_shell}; past every surface: {why}"
    return [{"opening": None, "pane": None, "cores": None, "pieces": found, "no_room": no_shell}]


def _pieces_past_obstructions(points_m, poly, tris, tol, reach, wall, see_through):
    """Per point the convex pieces of opening ``poly`` through which it sees the world, sky and ground, past the
    opaque triangles in its whole pyramid (``obstructed_aperture.unblocked_pieces``; the opening itself where
    nothing is in the way), or the reason (str) why not at some point (a see-through triangle among them: the
    caller's pane proof decides)."""
    from ...radiometry.skies import obstructed_aperture

    blockers = sky_aperture.apertures_blockers(points_m, poly, tris, tol, reach, sky_only=False, ignore=wall,
                                               coplanar_checked=True)
    out = []
    for p, b in zip(points_m, blockers):
        if b is None:
            return "a point lies at an opening's edge"
        if np.any(see_through[b]):
            return "a see-through surface stands in a view through an opening"
        pieces = obstructed_aperture.unblocked_pieces(p, poly, tris[b], tol)
        if isinstance(pieces, str):
            return pieces
        out.append(pieces)
    return out


@dataclasses.dataclass
class _Glazing:
    """A recognised thin pane in an opening, seen from a point: ``core`` (K, 3) the part of the opening
    through which every direction enters the pane's near face inside its outline (``_pane_core``); the
    rest of the opening (a rim, where a ray may pass beside the pane) is bounded between 0 and its
    open-sky closed form."""

    pane: object
    whole: bool  #: the whole pyramid (below the horizon too) is proven, else only its sky part
    core: np.ndarray = None
    #: past opaque obstructions beyond the pane: the core's and the opening's convex pieces seen past their
    #: silhouettes (``obstructed_aperture.unblocked_pieces``); None: the core and the opening whole
    core_pieces: list = None
    opening_pieces: list = None


def _shrunk_hull(geom, margin):
    """The pane's convex outline (in its frame) moved inward by ``margin`` m on every edge."""
    a = np.asarray(geom.hull, float)
    b = np.roll(a, -1, axis=0)
    edge = b - a
    inward = np.stack([-edge[:, 1], edge[:, 0]], axis=1) / np.linalg.norm(edge, axis=1)[:, None]  # CCW hull
    d = np.einsum("ij,ij->i", inward, a) + margin
    prev = np.roll(np.arange(len(a)), 1)
    out = []
    for i in range(len(a)):  # vertex i: the lines of edges i-1 and i
        m = np.array([inward[prev[i]], inward[i]])
        out.append(np.linalg.solve(m, np.array([d[prev[i]], d[i]])))
    return np.array(out)


def _pane_core(geom, point, poly, margin):
    """The part of the convex opening ``poly`` whose directions from ``point`` enter the pane through its
    face nearest the point, inside its outline shrunk by ``margin``: the opening clipped by the cone over
    that face. The render's thin-pane stand-in (``measure.capture.glass.thin_pane_material``) applies the
    whole pane's T(theta) where a ray enters and lets it leave by any face clear, so every such
    direction carries T(theta) of its angle to the pane's normal, in the render as in the closed form."""
    p = np.asarray(point, float)
    hull = _shrunk_hull(geom, margin)
    core = np.asarray(poly, float) - p
    near = min(geom.heights, key=lambda h: abs(float(p @ geom.normal) - h))
    ahead = (np.asarray(poly, float) - p) @ geom.normal
    if not np.all(np.sign(ahead) == np.sign(near - float(p @ geom.normal))) or near == float(p @ geom.normal):
        return None  # the pane's near face is not between the point and the opening's far side
    base = geom.origin + (near - float(geom.origin @ geom.normal)) * geom.normal
    face = base + hull[:, :1] * geom.u + hull[:, 1:] * geom.v - p
    centre = face.mean(axis=0)
    for j in range(len(face)):
        nrm = np.cross(face[j], face[(j + 1) % len(face)])
        core = sky_aperture.clip_polygon(core, nrm, 1.0 if nrm @ centre >= 0.0 else -1.0)
        if len(core) < 3:
            return None
    return core + p


#: Relative width of the bound on the light through a pane (of the light through it), as a share of the
#: reading's relative target: a hard bound counted in the reading's error beside the render's (in
#: quadrature, as one sigma). Measured in the side-lit room behind a 6 mm pane, 100 points: 1e-3 took
#: 5.7 s of subdivision (about 20 rounds a point) against a 1 s render of the rest.
PANE_TOL_SHARE = 0.25


def _pane_in_opening(model, point, poly, tol, clear, wall, sky_only, beyond=None):
    """The :class:`_Glazing` of an opening whose view from ``point`` is clear but for one recognised,
    colour-neutral thin pane whose near face the directions through it enter (``_pane_core``), or the
    reason (str) why not. ``beyond``: (indices of the triangles in the point's view through the opening, above
    its horizon where ``sky_only``, else the whole pyramid; all triangles): besides the pane only opaque ones
    may be among them, and the glazing's pieces are what the point sees past their silhouettes."""
    g = model.geometry
    pane_of = np.asarray(g.pane_of if g.pane_of is not None else np.full(g.count, -1), int)
    p = np.asarray(point, float)
    for index, pane in (model.panes or {}).items():
        if pane.geometry is None or pane.trick:
            continue
        margin = 2.0 * max(float(tol), float(getattr(pane.geometry, "tol", 0.0)))
        core = _pane_core(pane.geometry, p, poly, margin)
        if core is None:
            continue
        pieces = (None, None)
        if beyond is None:
            if not clear(True, wall | (pane_of == index)):
                return "a surface besides the pane may stand between the point and the sky through an opening"
        else:
            pieces = _past_beyond_pane(model, p, poly, core, beyond, pane_of == index, tol)
            if isinstance(pieces, str):
                return pieces
        if len({float(v) for v in pane.tint_t}) > 1 or len({float(v) for v in pane.absorption}) > 1 \
                or len({float(v) for v in pane.tint_r}) > 1:
            return f"the pane {pane.source or pane.name!r} in an opening is tinted (its T differs by colour: rendered)"
        # with ``beyond`` the caller found the triangles in the pyramid it asks for (the whole one where not sky_only)
        whole = not sky_only and (beyond is not None or clear(False, wall | (pane_of == index)))
        return _Glazing(pane, bool(whole), core, *pieces)
    return "a see-through surface in an opening is not a recognised thin pane (rendered)"


def _past_beyond_pane(model, point, poly, core, beyond, of_pane, tol):
    """(core's pieces, opening's pieces) seen from ``point`` past the opaque triangles beyond the pane, or the
    reason (str) why not (``_pane_in_opening``'s ``beyond``)."""
    from ...radiometry.skies import obstructed_aperture

    idx, tris = beyond
    if idx is None:
        return "the point lies at an opening's edge"
    others = idx[~of_pane[idx]]
    if np.any(~opaque_mask(model)[others]):
        return "a see-through surface besides the pane stands between the point and the sky through an opening"
    out = []
    for polygon in (core, poly):
        pieces = obstructed_aperture.unblocked_pieces(point, polygon, tris[others], tol)
        if isinstance(pieces, str):
            return pieces
        out.append(pieces)
    return tuple(out)


def _through_panes(jobs, points_m, normals, lz, lg, rel_tol):
    """For each job (point index, :class:`_Glazing`, opening ``poly``): ((sky lux, its bound), (ground lux,
    its bound)) through the opening weighted by the pane's T(cos i) (the thin-pane closed form the render's
    stand-in uses too). The jobs behind one pane are bounded together (``pane_bounded_illuminances``), each
    point by its own subdivision."""
    results = [None] * len(jobs)
    groups = {}
    for k, (_i, glazing, _poly) in enumerate(jobs):
        groups.setdefault(id(glazing.pane), []).append(k)
    for ks in groups.values():
        pane = jobs[ks[0]][1].pane

        def transmittance(c, pane=pane):
            return pane.optics(np.asarray(c, float))[0][..., 1]  # colour-neutral: every channel alike

        pts = points_m[[jobs[k][0] for k in ks]]
        nrm = normals[[jobs[k][0] for k in ks]]
        cores = [jobs[k][1].core for k in ks]
        whole = np.array([jobs[k][1].whole for k in ks], bool)
        # past obstructions beyond the pane a job's core is its pieces (each bounded on its own, the bounds added)
        parts = [jobs[k][1].core_pieces if jobs[k][1].core_pieces is not None else [jobs[k][1].core] for k in ks]
        owner = np.array([j for j, ps in enumerate(parts) for _q in ps], int)
        sky_est, sky_half = np.zeros(len(ks)), np.zeros(len(ks))
        if owner.size:
            est, half, _pieces = sky_aperture.pane_bounded_illuminances(
                [q for ps in parts for q in ps], pts[owner], nrm[owner], transmittance, pane.geometry.normal,
                zenith_luminance=lz, ground_luminance=0.0, rel_tol=rel_tol)
            sky_est, sky_half = (np.bincount(owner, v, minlength=len(ks)) for v in (est, half))
        ground_est, ground_half = np.zeros(len(ks)), np.zeros(len(ks))
        if lg != 0.0 and whole.any():
            sel = np.flatnonzero(whole)
            e, h, _pieces = sky_aperture.pane_bounded_illuminances(
                [cores[j] for j in sel], pts[sel], nrm[sel], transmittance, pane.geometry.normal,
                zenith_luminance=0.0, ground_luminance=lg, rel_tol=rel_tol)
            ground_est[sel], ground_half[sel] = e, h
        # the rim of the opening outside the core: its rays cross the pane's edge; between 0 and the open sky
        rim = _open_over([jobs[k][1].opening_pieces if jobs[k][1].opening_pieces is not None else [jobs[k][2]]
                          for k in ks], pts, nrm, lz, lg)
        core = _open_over(parts, pts, nrm, lz, lg)
        band_sky = np.maximum(rim[0] - core[0], 0.0)
        band_ground = np.where(whole & (lg != 0.0), np.maximum(rim[1] - core[1], 0.0), 0.0)
        for j, k in enumerate(ks):
            results[k] = ((float(sky_est[j] + 0.5 * band_sky[j]), float(sky_half[j] + 0.5 * band_sky[j])),
                          (float(ground_est[j] + 0.5 * band_ground[j]), float(ground_half[j] + 0.5 * band_ground[j])))
    return results


def _open_over(polygons, pts, nrm, lz, lg):
    """(sky (J,), ground (J,)) lux of the open closed form over each job's list of convex polygons."""
    owner = np.array([j for j, ps in enumerate(polygons) for _q in ps], int)
    if not owner.size:
        return np.zeros(len(polygons)), np.zeros(len(polygons))
    sky, ground = sky_aperture.aperture_illuminance([q for ps in polygons for q in ps], pts[owner], nrm[owner],
                                                    zenith_luminance=lz, ground_luminance=lg)
    return np.bincount(owner, sky, minlength=len(polygons)), np.bincount(owner, ground, minlength=len(polygons))


# --- the openings as emitters (issue 31 item 1) -------------------------------------------------------

@dataclasses.dataclass
class Openings:
    """The openings of a closed opaque shell that look out on the world alone: ``loops`` (K, 3) in
    metres, ``outward`` unit normals and ``depth`` (m): how far see-through surfaces in an opening (a
    pane) stand out in front of its plane (0 for an open hole); ``reason`` why not (then all empty)."""

    loops: list
    outward: list
    depth: list = dataclasses.field(default_factory=list)
    reason: str = ""
    #: opaque surfaces stand in front of some opening, all of them below its lowest point (a ground plane): a ray
    #: leaving upwards still meets the world's sky alone, one leaving downwards may meet them, so the emitters carry
    #: the sky alone (``sky.opening_emitter_material(sky_only=True)``) and the ground seen through them is rendered
    sky_only: bool = False


def openings_to_world(model):
    """:class:`Openings` where a ray leaving the room through any opening meets nothing but the world,
    or a see-through surface standing in the opening (a pane) and then the world.

    Proof: the openings are convex holes of a closed opaque shell (``_closed_shell``), and every vertex
    of every render-visible triangle of the scene (the shell, furniture, anything outside) lies behind
    each opening's plane (within ``tol``), except see-through triangles lying wholly inside the opening's
    prism (a pane in the opening, up to ``depth`` in front of it). A ray through an opening then runs on
    in that open half-space, which holds nothing else. The outward side is the one every shell vertex
    lies behind; where neither side is (something of the building stands in front) it is refused.

    Opaque triangles in front that lie wholly at or below the opening's lowest point (a ground plane round the
    building) are allowed with ``sky_only``: a ray leaving the opening upwards never comes down to them, so the
    sky it meets is still the world's alone."""
    found = _closed_shell(model)
    if isinstance(found, str):
        return Openings([], [], [], found)
    loops, shell, tris, tol, _reach = found
    tris = np.asarray(tris, float)
    see_through = ~np.asarray(model.geometry.opaque, bool)
    shell_vertices = np.asarray(shell, float).reshape(-1, 3)
    outward, depth, sky_only = [], [], False
    for k, poly in enumerate(loops):
        centre = poly.mean(axis=0)
        normal, _offset = sky_aperture.polygon_plane(poly)  # Newell's normal of the loop
        # the shell's parts within the opening's outline (a frame touching its corners joins the shell) stand on
        # both sides of its plane: the side is the rest's
        sides = shell_vertices[~np.repeat(np.all(sky_aperture.inside_prism(
            shell_vertices, poly, centre, normal, tol).reshape(-1, 3), axis=1), 3)]
        if not len(sides):  # the whole shell within the outline (an open-topped box: the opening is its top)
            sides = shell_vertices
        if np.max((sides - centre) @ normal) > tol:
            normal = -normal
        if np.max((sides - centre) @ normal) > tol:
            return Openings([], [], [], f"the room's own surfaces stand in front of opening {k + 1} (e.g. a wing "
                                        "of the building or a deep reveal): its view out is not the world alone")
        ahead = (tris - centre) @ normal                                   # (T, 3) m in front of the plane
        front = np.any(ahead > tol, axis=1)
        held = see_through & front
        if held.any() and not np.all(sky_aperture.inside_prism(tris[held].reshape(-1, 3), poly, centre, normal, tol)):
            return Openings([], [], [], f"a see-through surface in front of opening {k + 1} reaches beyond it: "
                                        "what the opening looks out on is rendered")
        # opaque parts standing out of the opening within its outline (a window frame's bars, a mullion): Cycles'
        # next-event estimation from their faces to an emitter a few millimetres away weighs its samples by 1 / r^2,
        # and the batch means understated those heavy tails (issue 31's room with a frame and a mullion, 30 seeds x 6
        # points at 1 %: 82 % of 95 % intervals held on the emitters, 95 % on the gate path; with the bars black, 95 %)
        ahead_opaque = np.flatnonzero(front & ~see_through)
        framed = np.all(sky_aperture.inside_prism(tris[ahead_opaque].reshape(-1, 3), poly, centre, normal,
                                                  tol).reshape(-1, 3), axis=1)
        if framed.any():
            return Openings([], [], [], f"opaque parts stand out of opening {k + 1} within its outline (a frame's bars, "
                                        "a mullion): next-event estimation from them to an emitter beside them has "
                                        "tails the stated error would miss, so what the opening looks out on is "
                                        "rendered")
        # opaque faces inside the room that meet the opening's outline at an angle (a sill whose top is the window's
        # bottom edge, a floor under a window down to it): next-event estimation from points on them close to the
        # edge to the emitter has the heavy tails of a frame's bars (issue 31's room with a sill flush with the
        # window's bottom edge, 30 seeds x 6 points at 1 %: one point's readings scattered 1.83 x the error they
        # stated; the bare room 0.93-1.10)
        inner = np.flatnonzero(np.any(ahead < -tol, axis=1) & ~see_through)
        if inner.size and np.any(_segments_apart(tris[inner], poly) <= tol):
            return Openings([], [], [], f"an opaque surface inside the room meets the outline of opening {k + 1} at an "
                                        "angle (a sill at its edge, a floor or wall running on from it): next-event "
                                        "estimation from points beside that edge to an emitter in the opening has "
                                        "tails the stated error would miss, so the sky's direct part is gated instead")
        d = float(ahead[held].max()) if held.any() else 0.0
        # under the emitter's lowest point (a glazed opening's cup stands out past its pane: ``add_opening_emitters``)
        lowest = float((_cup_rim(poly, normal) if d > 0.0 else poly)[:, 2].min()) \
            + min(0.0, float(normal[2])) * (_cup_offset(d) if d > 0.0 else 0.0)
        below = np.all(tris[..., 2] <= lowest + tol, axis=1)
        if np.any(front & ~see_through & ~below):
            return Openings([], [], [], f"a surface of the scene lies in front of opening {k + 1} (outside the "
                                        "room): what the opening looks out on is rendered")
        sky_only |= bool(np.any(front & ~see_through & below))
        outward.append(normal)
        depth.append(d)
    return Openings(list(loops), outward, depth, sky_only=sky_only)


def _segments_apart(triangles, poly):
    """(T,) the least distance (m) between the edges of each triangle (T, 3, 3) and the outline of the polygon
    ``poly`` (K, 3): segment to segment, closed form (clamped to both segments' ends)."""
    p0 = triangles.reshape(-1, 3)                                              # (3T, 3) edge starts
    p1 = np.roll(triangles, -1, axis=1).reshape(-1, 3)
    q0, q1 = poly, np.roll(poly, -1, axis=0)                                   # (K, 3)
    d1, d2 = (p1 - p0)[:, None, :], (q1 - q0)[None, :, :]
    r = p0[:, None, :] - q0[None, :, :]
    a, e = np.sum(d1 * d1, axis=2), np.sum(d2 * d2, axis=2)
    b, c, f = np.sum(d1 * d2, axis=2), np.sum(d1 * r, axis=2), np.sum(d2 * r, axis=2)
    denom = a * e - b * b
    with np.errstate(divide="ignore", invalid="ignore"):
        s = np.clip(np.where(denom > 1e-18, (b * f - c * e) / denom, 0.0), 0.0, 1.0)
        t = np.clip(np.where(e > 0, (b * s + f) / e, 0.0), 0.0, 1.0)
        s = np.clip(np.where(a > 0, (b * t - c) / a, 0.0), 0.0, 1.0)
    gap = np.linalg.norm(r + s[..., None] * d1 - t[..., None] * d2, axis=2)   # (3T, K)
    return gap.reshape(len(triangles), -1).min(axis=1)


def _cup_offset(depth):
    """How far out (m) a glazed opening's emitter stands: past its pane (``depth`` in front), 1 mm at least."""
    return depth + max(1e-3, 0.1 * depth)


#: How far (m) outside a convex opening's outline its emitter cup's sides stand, on the wall's outer face. A frame's
#: bars fill the opening's rim: cup sides on the outline itself lay in the bars' outer faces, where a renderer's
#: shadow ray to the emitter may stop on the bar or not (float32). Outside the outline the space in front is empty
#: (``openings_to_world``), so the cup still meets every ray that leaves through the opening, and nothing else.
CUP_MARGIN_M = 1e-3


def _cup_rim(poly, normal):
    """The convex opening ``poly`` (K, 3) grown in its plane by at least ``CUP_MARGIN_M`` on every side (scaled about
    its centroid: the nearest edge moves out by the margin, the others by more)."""
    centre = poly.mean(axis=0)
    edges = np.roll(poly, -1, axis=0) - poly
    inward = np.cross(normal, edges)
    inward /= np.linalg.norm(inward, axis=1, keepdims=True)
    reach = np.abs(np.einsum("kj,kj->k", centre - poly, inward))  # the centroid's distance to each edge's line
    return centre + (poly - centre) * (1.0 + CUP_MARGIN_M / float(reach.min()))


def add_opening_emitters(request, openings, info):
    """Inside the caller's guard: one emitter per opening (``sky.opening_emitter_material``: the sky and
    ground of the CIE sky ``info`` that a ray leaving through it meets), and a black world whose light
    sampling is off (the openings now carry all of the sky's light into the room). An open opening
    gets its own polygon; a glazed one a shallow cup around its pane (the polygon moved out past the
    pane, with sides back to the opening's rim), so that every ray through the pane meets the emitter.
    With ``openings.sky_only`` (a ground plane in front, below them) the emitters carry the sky alone and let the
    other rays through, and the world stays the sky (its light sampling off): it lights the ground plane, which
    the room sees through the openings. Returns (the emitters' object identities (session uid, library) for light
    linking, the black world: ``check_emitter_linking`` reads under it)."""
    import bpy

    from ..authoring import sky
    from ..blender import identity
    from ...compat import ensure_node_tree

    scene, scale = request.scene, request.scale_length
    keys = []
    for k, (poly, normal, depth) in enumerate(zip(openings.loops, openings.outward, openings.depth)):
        n = len(poly)
        if depth > 0.0:
            rim = _cup_rim(poly, normal)
            out = rim + _cup_offset(depth) * normal
            verts = np.r_[rim, out]
            faces = [tuple(range(n, 2 * n))] + [(j, (j + 1) % n, n + (j + 1) % n, n + j) for j in range(n)]
        else:
            verts, faces = poly, [tuple(range(n))]
        name = f"radiometer_opening {k + 1}"
        mesh = bpy.data.meshes.new(name)
        mesh.from_pydata([tuple(float(c) / scale for c in v) for v in verts], [], faces)
        mesh.materials.append(sky.opening_emitter_material(name, info, normal, sky_only=openings.sky_only))
        if len(faces) > 1:
            # The cup's sides, thin strips seen edge-on from the room, emit like its front to the rays that meet them
            # but are not sampled as lights: sampled, they tripled the variance of the rest (issue 31's room, a cup
            # 1 mm deep: 0.87 M samples for 100 points at 1 % against 0.31 M for the flat emitter; 0.32 M with the
            # sides found by the paths alone). Unbiased either way: what a light sample skips, a ray's hit counts.
            sides = sky.opening_emitter_material(name + " sides", info, normal, sky_only=openings.sky_only)
            sides.cycles.emission_sampling = "NONE"
            mesh.materials.append(sides)
            for side in mesh.polygons[1:]:
                side.material_index = 1
        obj = bpy.data.objects.new(name, mesh)
        scene.collection.objects.link(obj)
        keys.append(identity.object_identity(obj))
    world = bpy.data.worlds.new("radiometer_black")
    ensure_node_tree(world).nodes["Background"].inputs["Strength"].default_value = 0.0
    world.cycles.sampling_method = "NONE"
    if openings.sky_only:
        scene.world.cycles.sampling_method = "NONE"  # the temporary sky: the ground plane finds it by its bounces
    else:
        scene.world = world
    return frozenset(keys), world


#: The verdicts of ``check_emitter_linking``: (Blender version, Cycles device) -> (ok, note).
_LINK_CHECKS = {}


def check_emitter_linking(request, keys, sensor, normal, model, *, samples=256, dark_world=None, sky_only=None):
    """Prove on this Blender and device (cached per session and kind of emitter) that light linking keeps an
    emitting mesh's light out of a baked sensor entirely, by next-event estimation and by rays that hit it: at a
    point lit by the openings, a direct-only bake (0 bounces) must read more than 0 without the exclusion and exactly
    0 with it, both under ``dark_world`` (the black world). ``sky_only``: the CIE sky ``info`` of sky-only emitters
    (``Openings.sky_only``), which let rays through downwards: the linked-out bake then reads under that sky with a
    black ground, so that it also proves that a ray leaving upwards stops on the emitter (else the sensor would see
    the world's sky, already in the proven part) while the one going downwards meets nothing lit. Returns (ok, note)."""
    import bpy

    from ..authoring import sky
    from ..render import adaptive

    scene = request.scene
    key = (bpy.app.version_string, str(getattr(scene.cycles, "device", "CPU")), sky_only is not None)
    if key in _LINK_CHECKS:
        return _LINK_CHECKS[key]
    weights, efficacy = request.weights, request.efficacy
    check = request.but(seed=0, progress=None, cancelled=None)  # as the check always ran: seed 0, no progress
    read = {}
    world = scene.world
    try:
        for name, ex in (("open", frozenset()), ("linked out", frozenset(keys))):
            if dark_world is not None:
                scene.world = dark_world
            if name == "linked out" and sky_only is not None:  # the sky above a black ground, in the guard
                sky.set_cie_sky(request, sky_only["sky_type"], sun_direction=sky_only["sun_direction"],
                                horizontal_illuminance_lux=sky_only["horizontal_illuminance_lux"],
                                ground_reflectance=0.0)
                scene.world.cycles.sampling_method = "NONE"
            run = adaptive.render_hybrid(check, np.asarray(sensor, float)[None, :],
                                         np.asarray(normal, float)[None, :], needs=model.needs, bounces=0,
                                         fixed_samples=samples, exclusions=[ex], panes=model.panes)
            read[name] = efficacy * float(run["mean_rgb"][0] @ weights)
    finally:
        scene.world = world
    ok = read["open"] > 0.0 and read["linked out"] == 0.0
    note = (f"light linking was checked on this Blender ({key[0]}, {key[1]}): direct light from the openings' "
            f"emitters read {read['open']:.6g} lx at a meter and {read['linked out']:.3g} lx with the meter linked "
            "out" + (" under the sky (its ground black): the emitters stop the rays that leave upwards"
                     if sky_only is not None else "") + ("" if ok else ": linking does NOT keep them out here"))
    _LINK_CHECKS[key] = (ok, note)
    return ok, note


# --- rendering only the remainder (issue 31 item 2) --------------------------------------------------

#: Cycles' Ray Depth of the world hits that reach a baked sensor straight (measured on bpy 5.0.1: 2 in
#: the meter's bake for paths that hit the world; ``check_world_gate`` proves it again once per Blender
#: session and device). The world's own light sampling (next-event estimation) evaluates the same
#: shader at Ray Depth 1 from the sensor (measured: a gate on depth 1 read 4420 of 10 000 lx above the
#: room), so a depth gate is only consistent with it off: ``gate_world`` switches it off.
DIRECT_DEPTH = 2.0

#: The same for an emitting mesh, whether Cycles samples it as a light from the sensor or a ray from the sensor
#: hits it (``_gate``).
EMITTER_DIRECT_DEPTH = 1.0

#: The verdicts of ``check_world_gate``: (Blender version, Cycles device) -> (ok, note).
_GATE_CHECKS = {}


def gate_world(scene):
    """Inside the caller's guard, on the temporary sky world (``authoring.sky.set_cie_sky``): its
    emission multiplied by 1 - (Ray Depth in the direct band) x (above the horizon), so that the sky
    seen straight from a sensor is dark while the sky lighting any surface, and the ground below the
    horizon, stay. The world's light sampling is switched off (the world is the guard's temporary one):
    every world hit is then a BSDF-sampled ray whose depth says whether it left a sensor (2) or a
    surface (3 or more); with it on, a depth gate is biased (measured: direct + rest read 13 460 lx where
    the sky gives 10 000). Returns the gate's factor node (``set_gate_mode`` switches it)."""
    scene.world.cycles.sampling_method = "NONE"
    tree = scene.world.node_tree
    bg = next(node for node in tree.nodes if node.bl_idname == "ShaderNodeBackground")
    coord = tree.nodes.new("ShaderNodeTexCoord")
    sep = tree.nodes.new("ShaderNodeSeparateXYZ")
    tree.links.new(coord.outputs["Generated"], sep.inputs[0])
    return _gate(tree, bg.inputs["Strength"], sep.outputs["Z"], DIRECT_DEPTH)


def _gate(tree, strength, up, depth):
    """Nodes in ``tree`` that multiply what drives the ``strength`` socket by 1 - (direct band) x (``up`` > 0:
    above the horizon); returns the factor node (``set_gate_mode``). The direct band: the Light Path node's Ray
    Depth within 0.5 of ``depth``, where the light reaches a sensor straight. Cycles adds one to the depth where it
    evaluates the world (a hit or a light sample alike) or samples any emitter as a light, not where a ray hits an
    emitting mesh (its svm light-path node; measured on bpy 5.0.1 and proven per session by ``check_world_gate``
    and ``check_envelope_gate``): a world found by the paths' bounces only reads 2 there (``DIRECT_DEPTH``), an
    emitting mesh 1, whether its light was sampled from the sensor or hit by a ray from it."""
    from ..authoring.sky import math_socket

    source = strength.links[0].from_socket
    path = tree.nodes.new("ShaderNodeLightPath")
    band = math_socket(tree, "COMPARE", path.outputs["Ray Depth"], float(depth), 0.5)  # 1 where |depth - d| <= 0.5
    mask = math_socket(tree, "MULTIPLY", band, math_socket(tree, "GREATER_THAN", up, 0.0))
    factor = math_socket(tree, "MULTIPLY_ADD", mask, -1.0, 1.0)  # 1 - mask (mode "remainder")
    tree.links.new(math_socket(tree, "MULTIPLY", source, factor), strength)
    return factor.node


def set_gate_mode(factor, mode):
    """``remainder``: all but the direct sky; ``direct``: the direct sky alone (the check's band);
    ``off``: the whole sky (the gate open)."""
    mul, add = {"remainder": (-1.0, 1.0), "direct": (1.0, 0.0), "off": (0.0, 1.0)}[mode]
    factor.inputs[1].default_value, factor.inputs[2].default_value = mul, add


def check_world_gate(request, factor, model, *, horizontal_lux, samples=1024):
    """Prove the gate on this Blender and device (cached per session): a sensor facing up above every
    surface sees only sky, so with the direct band alone it must read the unobstructed sky (all its
    direct hits have Ray Depth 2, within 5 %: a wrong depth reads 0 or a fraction), and with the
    remainder exactly 0 (no direct hit deeper than the band). A reflection adds one to the depth, so the
    remainder keeps every reflected path. Returns (ok, note); leaves the gate in mode "remainder"."""
    key = _device_key(request)
    if key in _GATE_CHECKS:
        set_gate_mode(factor, "remainder")
        return _GATE_CHECKS[key]
    ok, read = _read_bands(request, [factor], model, _top_sensor(request, model), horizontal_lux, samples)
    note = (f"the light-path gate was checked on this Blender ({key[0]}, {key[1]}): a sensor above every surface, "
            f"facing up, read {read['direct']:.6g} lx from the direct band alone (the sky gives {horizontal_lux:g} lx) "
            f"and {read['remainder']:.3g} lx from the rest" + ("" if ok else ": the gate does NOT hold here"))
    _GATE_CHECKS[key] = (ok, note)
    return ok, note


def _device_key(request):
    """What a gate's proof holds for: (Blender version, Cycles device)."""
    import bpy

    return bpy.app.version_string, str(getattr(request.scene.cycles, "device", "CPU"))


def _top_sensor(request, model):
    """(3,) metres: 1 m above the middle of the scene's top, where a sensor facing up sees only sky."""
    lo, hi = model.geometry.bounds()
    return np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, hi[2] + 1.0])


def _read_bands(request, factors, model, top, horizontal_lux, samples):
    """(ok, {"direct": lx, "remainder": lx}) of a sensor at ``top`` (m) facing up, every gate of ``factors`` in
    each mode in turn (seed 0, no progress: as the checks always ran), then left in "remainder". ok: the direct
    band reads the unobstructed sky within 5 % and the remainder exactly 0."""
    from ..render import adaptive

    check = request.but(seed=0, progress=None, cancelled=None)
    read = {}
    for mode in ("direct", "remainder"):
        for f in factors:
            set_gate_mode(f, mode)
        request.view_layer.update()
        run = adaptive.render_hybrid(check, (top / request.scale_length)[None, :], np.array([[0.0, 0.0, 1.0]]),
                                     needs=model.needs, bounces=4, fixed_samples=samples)
        read[mode] = request.efficacy * float(run["mean_rgb"][0] @ request.weights)
    for f in factors:
        set_gate_mode(f, "remainder")
    ok = abs(read["direct"] - horizontal_lux) <= 0.05 * horizontal_lux and read["remainder"] == 0.0
    return ok, read


# --- a room of separate boxes: its windows as emitters (issue 31 item 1) -------------------------------

#: How far out of the scene's bounding box the envelope emitters stand, relative to the proofs' tolerance
#: (far enough that no coplanar face of the box competes with them for a ray, Cycles' float32 included).
ENVELOPE_OFFSET_TOLERANCES = 100.0
#: And further out by this share of the gap's shorter side, and grown on every side by ``ENVELOPE_GROW`` x that distance
#: (``envelope.stood_off``: a ray leaving at up to ~56 deg from the face's normal still meets it). An emitter in the
#: wall's outer face touches the reveals of a thick wall, and next-event estimation from a reveal point next to its
#: edge weighs a sample by 1 / r^2: heavy tails that batch means understate. Measured in the room of boxes (0.2 m
#: walls, a 2 x 1.3 m window; 60 seeds at 2 %, scatter of the readings over their stated error at the point 2.5 m in;
#: the 100-point grid at 1 %): in the face 1.58x (4.2 s); 0.15 out 1.01x (7.3 s); 0.15 out and grown 1.33x (5.3 s);
#: 0.3 out and grown 0.88x (6.0 s).
ENVELOPE_STANDOFF = 0.3
#: Emitters only where the gaps cover at most this share of the bounding box's faces: a building's windows do (the
#: room of boxes: 2.4 %); a room and a block outside leave most of the box open (79 %), and emitters there, sampled
#: as lights from inside where they cannot be seen, made the obstruction room's daylight factor 3x slower (0.45
#: against 0.14 s a call of 5 points at 2 %, bench/coverage_daylight_emitters.py) for no gain.
ENVELOPE_MAX_SHARE = 0.1
ENVELOPE_GROW = 1.5


def add_envelope_emitters(request, model, info, points_m=None):
    """Inside the caller's guard, on the gate path (no closed room holds the openings, the world gated by
    ``gate_world``): an emitter on every gap of the faces of the scene's bounding box
    (``radiometry.scene.envelope.bounding_face_gaps``: for a room of boxes, its windows; each moved out
    ``ENVELOPE_STANDOFF`` of its shorter side and grown, ``envelope.stood_off``, still in the empty half-space),
    emitting the radiance of
    the CIE sky ``info`` that a ray leaving through it meets (``sky.opening_emitter_material``), gated like the
    world (``_gate``: the sky seen straight from a sensor dark, by hits and by light samples alike, so that the
    sky component stays the closed form's alone). Nothing lies in front of a gap, so a ray that meets an emitter
    would have met the world in the same direction: the light adds up as before whatever the gaps found, and
    Cycles now samples the windows as lights, where the world was found only by the paths' own bounces. Returns
    (the gates' factor nodes, the emitter objects, their area in m^2, ""), or ([], [], 0.0, why not): no gap, gaps
    over ``ENVELOPE_MAX_SHARE`` of the box's faces, or a meter of ``points_m`` ((N, 3) m) in front of an emitter's
    plane. An emitter is right for rays that cross it outwards (from the box); one that crosses it inwards, from a
    meter outside the box in front of it, would meet an emitter dark from that side where the wall or the room lay
    behind it. Every surface is inside the box, so only a meter's first ray can do that."""
    import bpy

    from ...radiometry.scene import envelope

    scene, scale = request.scene, request.scale_length
    tris = model.geometry.triangles
    if not len(tris):
        return [], [], 0.0, "the scene has no surfaces"
    if not np.all(np.asarray(model.geometry.opaque, bool)):
        # measured in the room of boxes behind a 6 mm pane (100 seeds at 2 %): with emitters behind the pane the
        # readings scattered 1.11-1.15x their stated error at three of five points and 85-91 % of 95 % intervals held
        # against Radiance (95 / 93 % without them), for 20 % less time
        return [], [], 0.0, "see-through surfaces (a pane) stand in the scene: behind them the emitters' readings " \
                            "scattered more than their stated error"
    tol = _proof_tolerance(model, ())
    gaps = envelope.bounding_face_gaps(tris, opaque_mask(model), tol, ENVELOPE_OFFSET_TOLERANCES * tol)
    if not gaps:
        return [], [], 0.0, "no gap in the faces of the scene's bounding box"
    lo, hi = model.geometry.bounds()
    size = np.asarray(hi, float) - np.asarray(lo, float)
    share = sum(_area([quad]) for quad, _n in gaps) / (2.0 * float(size[0] * size[1] + size[1] * size[2]
                                                                    + size[2] * size[0]))
    if share > ENVELOPE_MAX_SHARE:
        return [], [], 0.0, (f"the gaps in the faces of the scene's bounding box cover {100 * share:.0f} % of them "
                             "(more than a building's windows: they would be sampled as lights where they cannot be "
                             "seen)")
    gaps = envelope.stood_off(gaps, ENVELOPE_STANDOFF, ENVELOPE_GROW)
    if points_m is not None and len(points_m):
        pts = np.asarray(points_m, float).reshape(-1, 3)
        ahead = np.any([pts @ np.asarray(n, float) >= float(np.dot(n, quad[0])) - tol for quad, n in gaps], axis=0)
        if ahead.any():
            return [], [], 0.0, (f"{int(np.count_nonzero(ahead))} meter(s) stand outside the scene's bounding box in "
                                 "front of a gap, "
                                 "where an emitter there would hide what lies behind it")
    factors, objects, materials, area = [], [], {}, 0.0
    for k, (quad, normal) in enumerate(gaps):
        key = tuple(int(v) for v in normal)
        if key not in materials:
            materials[key], factor = envelope_emitter_material(f"radiometer_envelope {key}", info, normal)
            factors.append(factor)
        name = f"radiometer_envelope {k + 1}"
        mesh = bpy.data.meshes.new(name)
        mesh.from_pydata([tuple(float(c) / scale for c in v) for v in quad], [], [(0, 1, 2, 3)])
        mesh.materials.append(materials[key])
        obj = bpy.data.objects.new(name, mesh)
        scene.collection.objects.link(obj)
        objects.append(obj)
        area += float(np.linalg.norm(np.cross(quad[1] - quad[0], quad[3] - quad[0])))
    return factors, objects, area, ""


def remove_objects(objects):
    """Remove objects this analysis added (inside the caller's guard); returns []."""
    import bpy

    for ob in objects:
        bpy.data.objects.remove(ob)
    return []


def envelope_emitter_material(name, info, outward):
    """(material, its gate's factor node): ``sky.opening_emitter_material`` gated as the world is (``_gate``: the sky
    seen straight from a sensor dark), sampled as a light from both sides."""
    from ..authoring import sky

    mat = sky.opening_emitter_material(name, info, outward)
    mat.cycles.emission_sampling = "FRONT_BACK"
    tree = mat.node_tree
    emission = next(node for node in tree.nodes if node.bl_idname == "ShaderNodeEmission")
    # the z of the ray's unit direction, as ``sky.sky_radiance`` separated it for the sky's own horizon
    leaving_z = next(node for node in tree.nodes if node.bl_idname == "ShaderNodeSeparateXYZ").outputs["Z"]
    return mat, _gate(tree, emission.inputs["Strength"], leaving_z, EMITTER_DIRECT_DEPTH)


#: The verdicts of ``check_envelope_gate``: (Blender version, Cycles device) -> (ok, note).
_ENVELOPE_CHECKS = {}


def check_envelope_gate(request, factors, model, info, *, horizontal_lux, samples=1024):
    """Prove the envelope emitters' gate on this Blender and device (cached per session), as ``check_world_gate``
    proves the world's: a sensor above every surface, facing up, under a temporary emitter square (side 8 m, 0.5 m
    above it, the gated world beyond) must read the unobstructed sky with the direct band alone (within 5 %: an
    emitter's light samples or hits missed or counted twice read a fraction or more) and exactly 0 with the rest.
    ``factors``: the world's gate and the emitters'. Returns (ok, note); leaves every gate in mode "remainder"."""
    import bpy

    scene = request.scene
    key = _device_key(request)
    if key not in _ENVELOPE_CHECKS:
        scale = request.scale_length
        top = _top_sensor(request, model)
        square = top + np.array([[-4.0, -4.0, 0.5], [4.0, -4.0, 0.5], [4.0, 4.0, 0.5], [-4.0, 4.0, 0.5]])
        mat, factor = envelope_emitter_material("radiometer_envelope check", info, np.array([0.0, 0.0, 1.0]))
        mesh = bpy.data.meshes.new("radiometer_envelope check")
        mesh.from_pydata([tuple(float(c) / scale for c in v) for v in square], [], [(0, 1, 2, 3)])
        mesh.materials.append(mat)
        obj = bpy.data.objects.new("radiometer_envelope check", mesh)
        scene.collection.objects.link(obj)
        try:
            ok, read = _read_bands(request, list(factors) + [factor], model, top, horizontal_lux, samples)
        finally:
            bpy.data.objects.remove(obj)
            bpy.data.meshes.remove(mesh)
            bpy.data.materials.remove(mat)
        note = (f"the envelope emitters' gate was checked on this Blender ({key[0]}, {key[1]}): a sensor above "
                f"every surface, facing up under an emitter square, read {read['direct']:.6g} lx from the direct band "
                f"alone (the sky gives {horizontal_lux:g} lx) and {read['remainder']:.3g} lx from the rest"
                + ("" if ok else ": the gate does NOT hold here"))
        _ENVELOPE_CHECKS[key] = (ok, note)
    for f in factors:
        set_gate_mode(f, "remainder")
    request.view_layer.update()
    return _ENVELOPE_CHECKS[key]
