"""Daylight glare probability (DGP) from a luminance picture (pure numpy).

Wienold & Christoffersen (2006), "Evaluation methods and development of a new glare prediction model
for daylight environments with the use of CCD cameras", Energy and Buildings 38, 743-757:

    DGP = 5.87e-5 E_v + 9.18e-2 log10(1 + sum_i L_i^2 omega_i / (E_v^1.87 P_i^2)) + 0.16

- ``E_v`` (lx): the vertical illuminance at the eye (the picture's own: sum of L cos(theta) omega over
  the hemisphere in front of the eye);
- ``L_i`` (cd/m²), ``omega_i`` (sr): glare source i's mean luminance (solid-angle weighted) and solid
  angle;
- ``P_i``: the position index at the source's centre. Above the line of sight Guth's, in Levin's form
  (:func:`radiometry.metrics.glare.position_index`, the one UGR uses); below it the Iwata & Osterhaus (2010)
  form that evalglare uses since v3.02: beta = atan(tan(sigma) sqrt(1 + 0.3225 cos²(tau))),
  P = exp(6.49e-3 beta + 21e-5 beta²) (degrees); P is capped at 16 as evalglare caps it.

DGP is capped at 1 (a probability). The *low-light correction* (Wienold 2009, in evalglare since
v1.03): for E_v < 1000 lx, DGP x exp(0.024 E_v - 4) / (1 + exp(0.024 E_v - 4)). evalglare applies it
only when asked (``-C l+``) since v2.14; here ``low_light_correction=False`` by default, as there.
The *simplified* DGPs = 6.22e-5 E_v + 0.184 (Wienold 2007) stands for DGP where no source is in
view (the annual method's hours without the sun in the field: :func:`hourly_dgp`, Wienold 2009).
Classes (Wienold 2009; EN 17037:2018 Annex C's glare-protection levels use the same limits):
imperceptible < 0.35 <= perceptible < 0.40 <= disturbing < 0.45 <= intolerable.

Glare sources are found as evalglare (J. Wienold, v3.05; read from its source, Radiance's
src/util/evalglare.c) finds them:

- pixels brighter than a threshold: a fixed luminance (evalglare's default 2000 cd/m²), or a
  multiple of the task zone's mean luminance (multiple 5 when a task zone is given) or of the mean
  luminance of the picture;
- bright pixels closer than 0.1 rad to one another form one source (evalglare's search radius -r 0.2,
  which it compares with twice the angle between pixels); evalglare grows sources by a scan, here by
  single linkage (8-neighbours, then any two sources whose border pixels lie within the radius);
- pixels of at least 50 000 cd/m² (the sun's disc) are taken out of their source and grouped on their
  own within 0.05 rad (evalglare's peak extraction, on by default);
- a source's position is the L x omega weighted mean of its pixels' directions (evalglare: of their
  pixel coordinates, then the pixel there), where P is taken.

Pictures: angular fisheye (Radiance ``-vta``; :func:`angular_fisheye`), top row first, luminance in
cd/m². Coordinates: right-handed, +Z up (Blender's), as ``radiometry.metrics.glare``.
"""

import dataclasses
import math

import numpy as np

from ...readings import AsDict
from . import glare

__all__ = ["dgp", "dgp_simplified", "low_light_factor", "dgp_class", "position_index_dgp", "angular_fisheye",
           "find_glare_sources", "dgp_from_picture", "DGPResult", "CLASS_LIMITS", "radiance_picture",
           "SUN_SOLID_ANGLE_SR", "sun_glare_source", "hourly_dgp"]

C_EV, C_LOG, C_0, EV_EXPONENT = 5.87e-5, 9.18e-2, 0.16, 1.87   #: Wienold & Christoffersen 2006
SIMPLIFIED_SLOPE, SIMPLIFIED_OFFSET = 6.22e-5, 0.184            #: DGPs, Wienold 2007
#: (class, upper limit): DGP below the limit falls in the class.
CLASS_LIMITS = (("imperceptible", 0.35), ("perceptible", 0.40), ("disturbing", 0.45), ("intolerable", math.inf))
THRESHOLD_CD_M2 = 2000.0      #: evalglare's default fixed threshold (since v2.05)
TASK_FACTOR = 5.0             #: evalglare's default multiple of the task luminance
MERGE_ANGLE_RAD = 0.1         #: bright pixels this close form one source (evalglare -r 0.2, halved)
PEAK_CD_M2 = 50000.0          #: evalglare's peak-extraction limit
PEAK_MERGE_ANGLE_RAD = 0.05
POSITION_INDEX_MAX = 16.0


def low_light_factor(vertical_illuminance):
    """Wienold's low-light factor exp(0.024 E - 4) / (1 + exp(0.024 E - 4)) below 1000 lx, else 1."""
    e = np.asarray(vertical_illuminance, float)
    z = np.exp(np.minimum(0.024 * e - 4.0, 50.0))
    return np.where(e < 1000.0, z / (1.0 + z), 1.0)


def dgp(vertical_illuminance, luminances=(), solid_angles=(), position_indices=(), *, low_light_correction=False):
    """DGP of glare sources (cd/m², sr, position index) at a vertical eye illuminance E_v (lx).

    E_v <= 0 or not finite: ValueError (the formula divides by E_v^1.87). Capped at 1.
    """
    ev = float(vertical_illuminance)
    if not (ev > 0 and math.isfinite(ev)):
        raise ValueError(f"the vertical illuminance must be > 0 lx, got {ev}")
    L = np.asarray(luminances, float)
    w = np.asarray(solid_angles, float)
    p = np.asarray(position_indices, float)
    s = float(np.sum(L * L * w / (p * p)))
    value = C_EV * ev + C_LOG * math.log10(1.0 + s / ev ** EV_EXPONENT) + C_0
    if low_light_correction:
        value *= float(low_light_factor(ev))
    return min(value, 1.0)


def dgp_simplified(vertical_illuminance):
    """DGPs = 6.22e-5 E_v + 0.184 (E_v lx, array-like), capped at 1."""
    return np.minimum(SIMPLIFIED_SLOPE * np.asarray(vertical_illuminance, float) + SIMPLIFIED_OFFSET, 1.0)


def dgp_class(value):
    """'imperceptible' | 'perceptible' | 'disturbing' | 'intolerable' for a DGP value."""
    v = float(value)
    if not math.isfinite(v):
        raise ValueError(f"DGP must be a finite number, got {value!r}")
    return next(name for name, limit in CLASS_LIMITS if v < limit)


def position_index_dgp(sigma_deg, tau_deg, elevation_deg):
    """Position index as evalglare takes it: Guth (Levin's form) above the line of sight, Iwata &
    Osterhaus (2010) below it (elevation < 0), capped at 16. Angles in degrees."""
    s = np.asarray(sigma_deg, float)
    t = np.asarray(tau_deg, float)
    above = glare.position_index(s, t)
    with np.errstate(invalid="ignore", over="ignore"):
        beta = np.degrees(np.arctan(np.tan(np.radians(s)) * np.sqrt(1.0 + 0.3225 * np.cos(np.radians(t)) ** 2)))
        below = np.exp(6.49e-3 * beta + 21e-5 * beta * beta)
    return np.minimum(np.where(np.asarray(elevation_deg) < 0.0, below, above), POSITION_INDEX_MAX)


def angular_fisheye(width, height, view_direction, up=(0.0, 0.0, 1.0), fov_deg=180.0):
    """Pixel geometry of an angular (equidistant) fisheye, Radiance's ``-vta -vh fov -vv fov``.

    Returns (directions (H, W, 3) unit, solid_angles (H, W) sr, valid (H, W) bool), top row first,
    x to the right of the line of sight. A pixel at image offset (x, y) from the centre (in units of
    the picture's width and height) looks theta = pi rho (fov / 180) from the line of sight,
    rho = |(x, y)|; its solid angle is the Jacobian at its centre, pi sin(theta) / rho' dx' dy'
    (rho', x', y' scaled by fov / 180): the sum over the hemisphere is 2 pi to O(pixel²).
    ``valid``: pixels whose centre looks into the front hemisphere (evalglare's valid pixels).
    """
    w, h = int(width), int(height)
    if w < 1 or h < 1:
        raise ValueError(f"a picture needs at least 1 x 1 pixels, got {w} x {h}")
    f, u, r = glare.view_frame(view_direction, up)
    k = float(fov_deg) / 180.0
    xs = ((np.arange(w) + 0.5) / w - 0.5) * k
    ys = (0.5 - (np.arange(h) + 0.5) / h) * k
    X, Y = np.meshgrid(xs, ys)
    rho = np.hypot(X, Y)
    theta = math.pi * rho
    sinc = np.where(rho > 0, np.sin(theta) / np.where(rho > 0, rho, 1.0), math.pi)
    dirs = np.cos(theta)[..., None] * f + (X * sinc)[..., None] * r + (Y * sinc)[..., None] * u
    dirs /= np.linalg.norm(dirs, axis=-1, keepdims=True)
    omega = math.pi * sinc * (k * k) / (w * h)
    valid = (theta <= math.pi / 2) & (rho <= 1.0)
    return dirs, np.where(valid, omega, 0.0), valid


def _union(n, i, j):
    """Root label (n,) of each node of the graph with edges (i, j): min-label propagation with pointer
    jumping."""
    lab = np.arange(n)
    if len(i) == 0:
        return lab
    while True:
        m = np.minimum(lab[i], lab[j])
        new = lab.copy()
        np.minimum.at(new, i, m)
        np.minimum.at(new, j, m)
        while True:                          # pointer jumping: every label points at its root
            jumped = new[new]
            if np.array_equal(jumped, new):
                break
            new = jumped
        if np.array_equal(new, lab):
            return lab
        lab = new


def _pairs(src, dst, offsets):
    """(y1, x1, y2, x2) of pixels set in ``src`` whose offset neighbour is set in ``dst``."""
    H, W = src.shape
    out = []
    for dy, dx in offsets:
        a = src[: H - dy, max(0, -dx): W - max(0, dx)]
        b = dst[dy:, max(0, dx): W + min(0, dx)]
        ys, xs = np.nonzero(a & b)
        if len(ys):
            x1 = xs + max(0, -dx)
            out.append((ys, x1, ys + dy, x1 + dx))
    return out


def _components(mask, directions, link_angle_rad, pixel_angle_rad):
    """Labels (H, W) int (-1 outside ``mask``) of single-linkage groups: 8-neighbours always link; then
    groups link where two of their border pixels are at most ``link_angle_rad`` apart."""
    labels = np.full(mask.shape, -1)
    n = int(mask.sum())
    if n == 0:
        return labels
    ys, xs = np.nonzero(mask)
    y0, y1, x0, x1 = ys.min(), ys.max() + 1, xs.min(), xs.max() + 1
    reach = int(math.ceil(link_angle_rad / max(pixel_angle_rad, 1e-12) * math.pi / 2)) + 1
    y0, x0 = max(0, y0 - reach), max(0, x0 - reach)
    y1, x1 = min(mask.shape[0], y1 + reach), min(mask.shape[1], x1 + reach)
    m = mask[y0:y1, x0:x1]
    d = directions[y0:y1, x0:x1]
    index = np.full(m.shape, -1)
    index[m] = np.arange(n)
    near = _pairs(m, m, [(0, 1), (1, -1), (1, 0), (1, 1)])
    lab = _union(n, np.concatenate([index[a, b] for a, b, _, _ in near] or [np.zeros(0, int)]),
                 np.concatenate([index[c, e] for _, _, c, e in near] or [np.zeros(0, int)]))
    if len(np.unique(lab)) > 1:
        pad = np.pad(m, 1)
        border = m & ~(pad[:-2, :-2] & pad[:-2, 1:-1] & pad[:-2, 2:] & pad[1:-1, :-2] & pad[1:-1, 2:]
                       & pad[2:, :-2] & pad[2:, 1:-1] & pad[2:, 2:])
        far = [(dy, dx) for dy in range(0, reach + 1) for dx in range(-reach, reach + 1)
               if (dy > 0 or dx > 0) and max(abs(dx), dy) > 1]
        cos_link = math.cos(link_angle_rad)
        ii, jj = [], []
        for a, b, c, e in _pairs(border, border, far):
            i, j = index[a, b], index[c, e]
            keep = (lab[i] != lab[j]) & (np.einsum("ij,ij->i", d[a, b], d[c, e]) >= cos_link)
            ii.append(lab[i[keep]])
            jj.append(lab[j[keep]])
        if ii:
            lab = _union(n, np.concatenate(ii), np.concatenate(jj))[lab]
    _, dense = np.unique(lab, return_inverse=True)
    sub = np.full(m.shape, -1)
    sub[m] = dense
    labels[y0:y1, x0:x1] = sub
    return labels


def find_glare_sources(luminance, directions, solid_angles, valid, view_direction, up=(0.0, 0.0, 1.0), *,
                       threshold_cd_m2=THRESHOLD_CD_M2, threshold_factor=None, task=None,
                       merge_angle_rad=MERGE_ANGLE_RAD, peak_cd_m2=PEAK_CD_M2,
                       peak_merge_angle_rad=PEAK_MERGE_ANGLE_RAD):
    """Glare sources of a luminance picture, as evalglare finds them (module docstring).

    ``threshold_factor``: the threshold is that multiple of the task zone's mean luminance (``task``
    given) or of the picture's mean luminance (solid-angle weighted over the valid pixels); None with
    a ``task``: 5 (evalglare's default); None without one: ``threshold_cd_m2``. ``task``: (direction
    (3,), opening angle rad): the pixels within half the opening angle of the direction (evalglare's
    ``-t x y angle``). ``peak_cd_m2`` None: no peak extraction.
    Returns (sources, threshold cd/m², reference luminance cd/m² or None): sources are dicts with
    ``luminance`` (cd/m²), ``solid_angle`` (sr), ``direction``, ``sigma_deg``, ``tau_deg``,
    ``elevation_deg``, ``position_index``, ``pixels``, ``border_solid_angle`` (sr, of its pixels with a
    neighbour outside it), ``peak`` (True for an extracted peak).
    """
    L = np.asarray(luminance, float)
    dirs = np.asarray(directions, float)
    w = np.asarray(solid_angles, float)
    ok = np.asarray(valid, bool) & (w > 0)
    if L.shape != ok.shape or dirs.shape != L.shape + (3,):
        raise ValueError(f"luminance {L.shape}, directions {dirs.shape} and solid angles {w.shape} do not match")
    if not np.all(np.isfinite(L[ok])) or np.any(L[ok] < 0):
        raise ValueError("luminance must be finite and >= 0 cd/m² on the valid pixels")
    reference = None
    if task is not None or threshold_factor is not None:
        factor = TASK_FACTOR if threshold_factor is None else float(threshold_factor)
        if not factor > 0:
            raise ValueError(f"threshold_factor must be > 0, got {threshold_factor!r}")
        zone = ok
        if task is not None:
            t_dir, opening = task
            t = np.asarray(t_dir, float)
            t = t / np.linalg.norm(t)
            zone = ok & (dirs @ t >= math.cos(float(opening) / 2))
            if not zone.any():
                raise ValueError("the task zone holds no pixel of the picture")
        reference = float(np.sum(L[zone] * w[zone]) / np.sum(w[zone]))
        threshold = factor * reference
    else:
        threshold = float(threshold_cd_m2)
        if not threshold > 0:
            raise ValueError(f"threshold_cd_m2 must be > 0, got {threshold_cd_m2!r}")
    bright = ok & (L > threshold)
    pixel_angle = float(np.sqrt(np.max(w[ok]))) if ok.any() else 1.0
    labels = _components(bright, dirs, merge_angle_rad, pixel_angle)
    if peak_cd_m2 is not None and np.any(bright & (L >= peak_cd_m2)):
        peaks = _components(bright & (L >= peak_cd_m2), dirs, peak_merge_angle_rad, pixel_angle)
        top = labels.max() + 1
        labels = np.where(peaks >= 0, top + peaks, labels)
        n_first = top
    else:
        n_first = labels.max() + 1
    pad = np.pad(labels, 1, constant_values=-2)
    inner = np.ones(labels.shape, bool)
    for dy in (0, 1, 2):
        for dx in (0, 1, 2):
            inner &= pad[dy: dy + labels.shape[0], dx: dx + labels.shape[1]] == labels
    sources = []
    for k in range(labels.max() + 1):
        sel = labels == k
        if not sel.any():
            continue
        lw = L[sel] * w[sel]
        omega = float(w[sel].sum())
        centre = (lw[:, None] * dirs[sel]).sum(axis=0)
        centre /= np.linalg.norm(centre)
        sigma, tau, elev = glare.view_angles(view_direction, centre, up)
        sources.append({"luminance": float(lw.sum() / omega), "solid_angle": omega, "direction": centre.tolist(),
                        "sigma_deg": float(sigma), "tau_deg": float(tau), "elevation_deg": float(elev),
                        "position_index": float(position_index_dgp(sigma, tau, elev)), "pixels": int(sel.sum()),
                        "border_solid_angle": float(w[sel & ~inner].sum()), "peak": bool(k >= n_first)})
    return sources, threshold, reference


@dataclasses.dataclass
class DGPResult(AsDict):
    """DGP of one picture. Luminances cd/m², solid angles sr, illuminances lx."""

    dgp: float
    dgp_class: str
    dgp_pixel_error: float            #: DGP's uncertainty from the sources' partly covered border pixels
    vertical_illuminance: float       #: E_v from the picture (sum of L cos(theta) omega), lx
    direct_illuminance: float         #: the glare sources' part of E_v, lx
    mean_luminance: float             #: solid-angle weighted mean over the valid pixels, cd/m²
    threshold_cd_m2: float
    sources: list
    low_light_correction: bool
    notes: list = dataclasses.field(default_factory=list)


def dgp_from_picture(luminance, directions, solid_angles, valid, view_direction, up=(0.0, 0.0, 1.0), *,
                     vertical_illuminance=None, low_light_correction=False, **detection):
    """DGP of a luminance picture (cd/m²) whose pixels look along ``directions`` with ``solid_angles``.

    ``vertical_illuminance`` (lx): E_v measured otherwise (evalglare's ``-i``); None: from the picture.
    ``detection``: the keywords of :func:`find_glare_sources`. Returns :class:`DGPResult`.
    """
    L = np.asarray(luminance, float)
    dirs = np.asarray(directions, float)
    w = np.asarray(solid_angles, float)
    ok = np.asarray(valid, bool) & (w > 0)
    f, _u, _r = glare.view_frame(view_direction, up)
    cos_t = np.clip(dirs @ f, 0.0, 1.0)
    sources, threshold, _reference = find_glare_sources(L, dirs, w, ok, view_direction, up, **detection)
    ev_picture = float(np.sum((L * cos_t * w)[ok]))
    ev = ev_picture if vertical_illuminance is None else float(vertical_illuminance)
    notes = []
    if not ev > 0:
        raise ValueError(f"no light reaches the eye (E_v {ev:.3g} lx): DGP is not defined")
    bright = ok & (L > threshold)
    e_dir = float(np.sum((L * cos_t * w)[bright]))
    value = dgp(ev, [s["luminance"] for s in sources], [s["solid_angle"] for s in sources],
                [s["position_index"] for s in sources], low_light_correction=low_light_correction)
    # pixelation: a source's border pixels are partly covered; half their solid angle is taken as
    # uncertain (in or out), which moves the sum by that share of each source's term
    terms = np.array([s["luminance"] ** 2 * s["solid_angle"] / s["position_index"] ** 2 for s in sources])
    total = float(terms.sum())
    x = total / ev ** EV_EXPONENT
    shares = np.array([0.5 * s["border_solid_angle"] / s["solid_angle"] for s in sources])
    pixel_error = C_LOG / math.log(10) * x / (1 + x) * float(terms @ shares) / total if total > 0 else 0.0
    if ev < 380:
        notes.append(f"E_v {ev:.0f} lx is below 380 lx: DGP was fitted on brighter scenes and may underestimate "
                     "glare here (evalglare's notice)")
    return DGPResult(dgp=value, dgp_class=dgp_class(value), dgp_pixel_error=pixel_error, vertical_illuminance=ev, direct_illuminance=e_dir,
                     mean_luminance=float(np.sum((L * w)[ok]) / np.sum(w[ok])), threshold_cd_m2=threshold,
                     sources=sources, low_light_correction=bool(low_light_correction), notes=notes)


def radiance_picture(luminance, view_direction, up=(0.0, 0.0, 1.0), eye=(0.0, 0.0, 0.0), fov_deg=180.0):
    """Bytes of a Radiance picture (RGBE, flat scanlines, top row first) of ``luminance`` (H, W) cd/m²
    as grey R = G = B = L / 179 (Radiance's white efficacy), with its angular-fisheye VIEW in the
    header, as evalglare reads it. Pure: the caller writes the bytes. Every pixel's largest mantissa
    byte is >= 128, so no pixel reads as an old-style run-length marker (1, 1, 1, n)."""
    v = np.asarray(luminance, float) / 179.0
    if v.ndim != 2 or not np.all(np.isfinite(v)) or np.any(v < 0):
        raise ValueError("a Radiance picture needs a 2-D array of finite luminances >= 0")
    m, e = np.frexp(v)
    small = v < 1e-32
    mant = np.where(small, 0, np.floor(m * 256)).astype(np.uint8)
    ex = np.where(small, 0, e + 128).astype(np.uint8)
    h, w = v.shape
    vd, vu, vp = (" ".join(f"{float(c):.9g}" for c in vec) for vec in (view_direction, up, eye))
    head = (f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\nVIEW= -vta -vp {vp} -vd {vd} -vu {vu} -vh {fov_deg:g} "
            f"-vv {fov_deg:g}\n\n-Y {h} +X {w}\n").encode()
    return head + np.stack([mant, mant, mant, ex], axis=-1).tobytes()


# --- annual DGP from hourly eye illuminances (imageless; measure/analyses/annual_dgp.py) -----------------------

#: Solid angle of the sun's disc (sr): 0.533 deg across, 2 pi (1 - cos 0.2665 deg) = 6.80e-5 sr.
SUN_SOLID_ANGLE_SR = 2.0 * math.pi * (1.0 - math.cos(math.radians(0.533 / 2)))


def sun_glare_source(view_direction, sun_direction, direct_normal_lux, sun_at_eye_lux, up=(0.0, 0.0, 1.0)):
    """The sun's disc as the glare source of each hour, from the direct sun at the eye.

    ``sun_direction`` (T, 3) unit vectors towards the sun, ``direct_normal_lux`` (T,) E_dn, ``sun_at_eye_lux``
    (T,) the direct sun's illuminance on the eye's plane (E_dn cos x what reaches the eye: 0 when
    blocked, the panes' transmittance when seen through glass; ``measure.analyses.annual.direct_sun``).
    Returns (seen (T,) bool, luminance (T,) cd/m^2, position index (T,)): seen where the sun is in the
    front hemisphere and its direct light reaches the eye; L = E_dn / omega_sun x (E_sun / (E_dn cos)),
    the disc's luminance as transmitted; P (:func:`position_index_dgp`) at the disc's centre, 1 where
    not seen (unused there).
    """
    s = np.asarray(sun_direction, float).reshape(-1, 3)
    e_dn = np.asarray(direct_normal_lux, float).reshape(-1)
    e_eye = np.asarray(sun_at_eye_lux, float).reshape(-1)
    f, _u, _r = glare.view_frame(view_direction, up)
    cos = s @ f
    seen = (cos > 0) & (e_dn > 0) & (e_eye > 0) & np.isfinite(e_eye)
    with np.errstate(invalid="ignore", divide="ignore"):
        reach = np.where(seen, e_eye / np.where(seen, e_dn * cos, 1.0), 0.0)  # 1 in the open, T through a pane
    luminance = np.where(seen, e_dn * reach / SUN_SOLID_ANGLE_SR, 0.0)
    p = np.ones(len(s))
    if seen.any():
        sigma, tau, elev = glare.view_angles(f, s[seen], up)
        p[seen] = position_index_dgp(sigma, tau, elev)
    return seen, luminance, p


def hourly_dgp(vertical_illuminance, sun_luminance, sun_position_index, *, vertical_illuminance_std_error=None,
               sun_solid_angle=SUN_SOLID_ANGLE_SR, low_light_correction=False):
    """Hourly DGP, the imageless annual way (Wienold 2009, "Dynamic daylight glare evaluation", Building
    Simulation 2009, 944-951): full DGP (:func:`dgp`) with the sun's disc as the one glare source at the
    hours where it is seen (``sun_luminance`` > 0), the simplified DGPs (:func:`dgp_simplified`) at the
    others. DGPs has no contrast term: the sky or a bright pane seen from the eye is not a source there,
    so it is the lower envelope of DGP where no sun is seen.

    Arrays (T,): E_v (lx, the sun included), L_sun (cd/m^2, 0 where not seen), P. Returns (DGP (T,),
    standard error (T,)): first order from ``vertical_illuminance_std_error`` (0 where not given); where
    the value is capped at 1 and stays there 2 standard errors lower, 0. NaN E_v gives NaN.
    ``low_light_correction``: :func:`low_light_factor` on both (as :func:`dgp` takes it).
    """
    ev = np.asarray(vertical_illuminance, float).reshape(-1)
    L = np.broadcast_to(np.asarray(sun_luminance, float), ev.shape)
    p = np.broadcast_to(np.asarray(sun_position_index, float), ev.shape)
    se_ev = np.zeros_like(ev) if vertical_illuminance_std_error is None else \
        np.broadcast_to(np.asarray(vertical_illuminance_std_error, float), ev.shape)
    sun = (L > 0) & (ev > 0)
    value = SIMPLIFIED_SLOPE * ev + SIMPLIFIED_OFFSET
    slope = np.full_like(ev, SIMPLIFIED_SLOPE)
    if sun.any():
        e = ev[sun]
        x = L[sun] ** 2 * float(sun_solid_angle) / (p[sun] ** 2 * e ** EV_EXPONENT)
        value[sun] = C_EV * e + C_LOG * np.log10(1.0 + x) + C_0
        slope[sun] = C_EV - C_LOG / math.log(10) * x / (1.0 + x) * EV_EXPONENT / e
    if low_light_correction:
        g = low_light_factor(ev)
        dg = np.where(ev < 1000.0, 0.024 * g * (1.0 - g), 0.0)
        slope = slope * g + value * dg
        value = value * g
    se = np.abs(slope) * se_ev
    capped = value >= 1.0
    se = np.where(capped & (value - 2.0 * se >= 1.0), 0.0, se)
    return np.minimum(value, 1.0), se
