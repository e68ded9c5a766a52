"""Map each Radiometer BRDF to the closest Cycles closure network and state its fidelity (no bpy).

``realise(model, method, **params) -> (terms, Fidelity)``. ``method`` is 'nodes' (a node group:
Cycles on any device and EEVEE) or 'osl' (a Script node: Cycles CPU with Open Shading Language).

Mapping table (what each model becomes). "exact" means the closure is the same formula AND the
measured ``rms_rel_diff`` against the library is <= 1e-3; everything else is "approximate" with its
measured numbers (closure parameters fitted where the formulas differ):

================== ======================================= ====================================
model              nodes                                   osl
================== ======================================= ====================================
lambert            Diffuse BSDF (exact)                    diffuse() (exact)
oren_nayar         Diffuse BSDF roughness: exact for       oren_nayar_diffuse_bsdf (same)
                   variant='cycles' (sigma = roughness),
                   else roughness fitted (~7 % RMS)
phong              Diffuse + Glossy GGX/Beckmann, fitted   diffuse + phong_ramp (exact)
                   (~65 % RMS: no Phong lobe in nodes)
blinn_phong        Glossy GGX/Beckmann, fitted (~66 %:     diffuse + phong_ramp, exponent
                   the lobe lacks 1/(4 cos_i cos_o) G)     fitted (~13-16 % RMS)
torrance_sparrow   Glossy/Metallic Beckmann, Smith G,      microfacet / generalized_schlick /
                   alpha fitted (~3 % RMS)                 conductor_bsdf (same fit)
ggx                Metallic (F82 white tint = Schlick, or  generalized_schlick_bsdf /
                   physical conductor for ior, eta+k);     conductor_bsdf / microfacet (exact)
                   Glossy when F = 1 (exact within node
                   limits: alpha <= 1, Metallic
                   alpha_y/alpha_x >= 0.1)
beckmann           same as ggx; approximate (~0.3 % RMS):  same
                   Cycles uses Walter's rational Smith
                   Lambda, the library the exact erf form
ward               Diffuse + anisotropic Glossy Beckmann   same
                   fitted (~7 % RMS)
ashikhmin_shirley  Diffuse + Glossy 'Ashikhmin-Shirley'    same
                   (F = 1) or Metallic GGX, fitted (~12 %)
mirror             Glossy/Metallic, roughness 0 (delta)    reflection / microfacet alpha 0
================== ======================================= ====================================

Blender roughness r gives alpha = r ** 2 in every Cycles microfacet node (kernel ``svm/closure.h``:
``sqr(saturatef(roughness))``; confirmed by rendering, tests/bpy/test_shading_validate.py).
"""

import functools
import math
from dataclasses import dataclass, field, replace

import numpy as np

from . import closures as C
from . import fit as F
from ..errors import RadiometerError

METHODS = ("nodes", "osl")
EXACT_RMS = 1e-3  # a mapping is called exact only if the formula matches AND this is measured


@dataclass
class Fidelity:
    """How closely a Cycles closure network reproduces a numpy BRDF.

    Attributes
    ----------
    kind : str
        'exact' or 'approximate'.
    rms_rel_diff : float
        Weighted RMS relative difference of f (dimensionless; see ``shading.fit``).
    albedo_diff : float
        Max absolute difference of the directional albedo at 0, 30, 60, 75 deg (dimensionless).
    closure : str
        What Cycles renders.
    fitted : dict
        Fitted closure parameters (alpha_x, alpha_y, weights ...).
    notes : str
    """

    kind: str
    rms_rel_diff: float
    albedo_diff: float
    closure: str
    fitted: dict = field(default_factory=dict)
    notes: str = ""
    model: str = ""
    method: str = "nodes"
    terms: list = field(default_factory=list)

    def summary(self):
        if self.kind == "exact":
            return "exact"
        return f"approximate: RMS {100 * self.rms_rel_diff:.1f} %, albedo \u0394 {self.albedo_diff:.3f}"

    def to_dict(self):
        return {"kind": self.kind, "rms_rel_diff": self.rms_rel_diff, "albedo_diff": self.albedo_diff,
                "closure": self.closure, "fitted": self.fitted, "notes": self.notes, "model": self.model,
                "method": self.method, "terms": [t.to_dict() for t in self.terms], "summary": self.summary()}


def _lib():
    from .. import brdf

    return brdf


def param_specs(model):
    """{name: spec dict} from ``describe(model)``; options (e.g. variant) get kind 'option'."""
    d = _lib().describe(model)
    specs = {s["name"]: dict(s) for s in (d.get("parameters") or d.get("params") or [])}
    for name, opt in (d.get("options") or {}).items():
        specs[name] = {"name": name, "kind": "option", "default": opt["default"], "values": list(opt["values"]),
                       "optional": False, "unit": "", "description": f"one of {', '.join(map(str, opt['values']))}"}
    return specs


def check_params(model, params):
    """Validate user parameters (names, shapes, finiteness, ranges); return them cleaned."""
    lib = _lib()
    if model not in lib.names():
        raise RadiometerError(f"unknown BRDF model {model!r}; choose one of {', '.join(lib.names())}")
    specs = param_specs(model)
    unknown = [k for k in params if k not in specs]
    if unknown:
        raise RadiometerError(f"{model} has no parameter {', '.join(unknown)}; it takes {', '.join(specs)}")
    out = {}
    for name, value in params.items():
        spec = specs[name]
        if spec["kind"] == "option":
            if value not in spec["values"]:
                raise RadiometerError(f"{model}.{name} must be one of {spec['values']}, got {value!r}")
            out[name] = value
            continue
        try:
            arr = np.asarray(value, dtype=float)
        except (TypeError, ValueError):
            raise RadiometerError(f"{model}.{name} must be a number, got {value!r}") from None
        if spec.get("kind") == "color":
            if arr.ndim == 0:
                arr = np.full(3, float(arr))
            if arr.shape != (3,):
                raise RadiometerError(f"{model}.{name} must be one number or three (RGB), got {value!r}")
        elif arr.ndim != 0:
            raise RadiometerError(f"{model}.{name} must be one number, got {value!r}")
        if not np.all(np.isfinite(arr)):
            raise RadiometerError(f"{model}.{name} must be finite, got {value!r}")
        lo, hi = spec.get("min"), spec.get("max")
        unit = f" {spec['unit']}" if spec.get("unit") not in (None, "", "1") else ""
        if lo is not None and np.any(arr < lo):
            raise RadiometerError(f"{model}.{name} = {value!r}{unit} is below its minimum {lo}{unit}")
        if hi is not None and np.any(arr > hi):
            raise RadiometerError(f"{model}.{name} = {value!r}{unit} is above its maximum {hi}{unit}")
        out[name] = arr.tolist() if arr.ndim else float(arr)
    # cross-parameter rules (kd + ks <= 1, one Fresnel mode ...) belong to the library: ask it
    try:
        lib.evaluate(model, np.array([0.0, 0.0, 1.0]), np.array([0.0, 0.0, 1.0]), **out)
    except ValueError as exc:
        raise RadiometerError(f"{model}: {exc}") from None
    return out


def resolve_params(model, params):
    """Defaults from ``describe(model)`` updated by ``params`` (validated); optional ones may be None.

    Raises
    ------
    RadiometerError
        Unknown model or parameter, wrong colour length, NaN/inf, outside [min, max], or a
        cross-parameter rule of the library (e.g. kd + ks <= 1, one Fresnel mode).
    """
    given = check_params(model, params)
    out = {}
    for name, spec in param_specs(model).items():
        out[name] = given.get(name, spec.get("default"))
    return out


def _rgb(v, default=1.0):
    if v is None:
        v = default
    return tuple(float(x) for x in np.broadcast_to(np.asarray(v, dtype=float), (3,)))


def _alphas(p, default=0.3):
    ax = p.get("alpha_x")
    ay = p.get("alpha_y")
    a = p.get("alpha", default)
    if ax is None or ay is None:
        return float(a), float(a)
    return float(ax), float(ay)


def _fresnel(p, given):
    """(fresnel, f0, ior, k) as the library chooses it: eta+k (conductor), ior (dielectric) or f0 (Schlick)."""
    if p.get("eta") is not None and p.get("k") is not None:
        return "conductor", (1.0,) * 3, _rgb(p.get("eta")), _rgb(p.get("k"), 0.0)
    if p.get("ior") is not None:
        # Cycles' conductor Fresnel with k = 0 is the exact dielectric Fresnel (outside incidence)
        return "conductor", (1.0,) * 3, _rgb(p.get("ior")), (0.0, 0.0, 0.0)
    f0 = _rgb(p.get("f0"), 1.0)
    if all(abs(v - 1.0) < 1e-12 for v in f0):
        return "none", (1.0,) * 3, (1.5,) * 3, (0.0,) * 3  # Schlick with f0 = 1 is F = 1
    return "schlick", f0, (1.5,) * 3, (0.0,) * 3


def _f_model(model, given):
    lib = _lib()
    kwargs = dict(given)  # only what the user gave: the library applies its own defaults

    def f(wi, wo):
        return np.asarray(lib.evaluate(model, wi, wo, **kwargs), dtype=float) * np.ones(3)

    return f


def _describe_closures(terms, method):
    names = []
    for t in terms:
        c = t.closure
        if c == "diffuse":
            names.append("Diffuse BSDF" if method == "nodes" else "diffuse()")
        elif c == "oren_nayar":
            names.append(f"Diffuse BSDF roughness {t.roughness:.3g}" if method == "nodes"
                         else f"oren_nayar_diffuse_bsdf({t.roughness:.3g})")
        elif c == "phong_ramp":
            names.append(f"phong_ramp(n={t.exponent:.4g})")
        elif c in ("microfacet", "mirror"):
            dist = "Beckmann" if t.distribution == "beckmann" else "GGX"
            aniso = "" if abs(t.alpha_x - t.alpha_y) < 1e-12 else f", alpha_y {t.alpha_y:.3g}"
            rough = "roughness 0 (delta)" if c == "mirror" else f"alpha {t.alpha_x:.3g}{aniso}"
            if method == "nodes":
                node = {"none": "Glossy BSDF", "schlick": "Metallic BSDF (F82, white tint = Schlick)",
                        "conductor": "Metallic BSDF (physical conductor)"}[t.fresnel]
            else:
                node = {"none": "microfacet()", "schlick": "generalized_schlick_bsdf()",
                        "conductor": "conductor_bsdf()"}[t.fresnel]
            names.append(f"{node} {dist} {rough}")
        elif c == "ashikhmin_shirley":
            names.append(f"Glossy BSDF Ashikhmin-Shirley alpha {t.alpha_x:.3g}, {t.alpha_y:.3g}")
    return " + ".join(names)


def limit_for_nodes(terms):
    """The terms as Blender's nodes can realise them (roughness <= 1, anisotropy ranges, scalar weights)."""
    out = []
    for t in terms:
        if t.closure in ("microfacet", "ashikhmin_shirley"):
            ax, ay = t.alpha_x, t.alpha_y
            if t.closure == "microfacet" and t.fresnel != "none":
                lo, hi = min(ax, ay), max(ax, ay)
                lo = max(lo, 0.1 * hi)  # Metallic: aspect^2 = 1 - 0.9 a >= 0.1
                a = min(math.sqrt(lo * hi), 1.0)
                r = math.sqrt(lo / hi)
                lo, hi = a * r, a / r
                ax, ay = (hi, lo) if ax >= ay else (lo, hi)
                w = sum(t.color) / 3.0
                t = replace(t, color=(w, w, w))
            else:
                a = min(math.sqrt(ax * ay), 1.0)
                ratio = min(max(ax / ay, 1e-4 * 1.0001), 1e4 / 1.0001)  # Glossy |anisotropy| <= 0.99
                ax, ay = a * math.sqrt(ratio), a / math.sqrt(ratio)
            if t.closure == "ashikhmin_shirley":
                ax, ay = min(ax, 1.0), min(ay, 1.0)
            t = replace(t, alpha_x=ax, alpha_y=ay)
        elif t.closure == "oren_nayar":
            t = replace(t, roughness=min(max(t.roughness, 0.0), 1.0))
        out.append(t)
    return out


def _microfacet_candidates(lobe_alpha, fresnel=("none", (1.0,) * 3, (1.5,) * 3, (0.0,) * 3),
                           aniso=False, distributions=("ggx", "beckmann"), diffuse=True, spec_linear="rgb",
                           diffuse_color=None):
    """Candidates 'microfacet lobe (+ diffuse)'; ``diffuse_color`` fixes the diffuse term (the model's kd)."""
    fr, f0, ior, k = fresnel
    cands = []
    for dist in distributions:
        def build(x, dist=dist):
            ax = float(x[0])
            ay = float(x[1]) if aniso else ax
            terms = [C.Term("microfacet", distribution=dist, alpha_x=ax, alpha_y=ay, fresnel=fr, f0=f0, ior=ior, k=k)]
            if diffuse:
                terms.insert(0, C.Term("diffuse", color=diffuse_color or (1.0, 1.0, 1.0)))
            return terms

        lin = ((None if diffuse_color else "rgb",) if diffuse else ()) + (spec_linear,)
        x0 = tuple(lobe_alpha) if aniso else (lobe_alpha[0],)
        cands.append(F.Candidate(
            name=f"{'diffuse + ' if diffuse else ''}{dist} microfacet", build=build, x0=x0, linear=lin,
            bounds=((math.log(1e-3), 0.0),) * len(x0),
            fitted_names=("alpha_x", "alpha_y") if aniso else ("alpha",)))
    return cands


def _realise(model, method, p, given):
    """terms, kind hint, candidates (None when exact), lobe width, notes."""
    notes = []
    if model == "lambert":
        return [C.Term("diffuse", color=_rgb(p.get("albedo"), 0.8))], None, 0.5, notes
    if model == "oren_nayar":
        albedo = _rgb(p.get("albedo"), 0.8)
        sigma = float(p.get("sigma") or 0.0)
        if p.get("variant") == "cycles":
            return [C.Term("oren_nayar", color=albedo, roughness=sigma)], None, 0.5, notes
        notes.append("classical Oren-Nayar sigma (rad) fitted to Cycles' energy-preserving Oren-Nayar roughness")

        def build(x):
            return [C.Term("oren_nayar", color=albedo, roughness=float(min(x[0], 1.0)))]

        cand = F.Candidate("oren_nayar", build, x0=(max(min(sigma, 1.0), 0.01),), linear=(None,),
                           bounds=((math.log(1e-3), 0.0),), fitted_names=("roughness",))
        return None, None, 0.5, [cand] + notes
    if model in ("ggx", "beckmann"):
        ax, ay = _alphas(p)
        fr = _fresnel(p, given)
        return [C.Term("microfacet", distribution=model, alpha_x=ax, alpha_y=ay, fresnel=fr[0], f0=fr[1],
                       ior=fr[2], k=fr[3])], None, min(ax, ay), notes
    if model == "mirror":
        fr = _fresnel(p, given)
        color = _rgb(p.get("reflectance") or p.get("albedo") or p.get("ks"), 1.0)
        return [C.Term("mirror", color=color, fresnel=fr[0], f0=fr[1], ior=fr[2], k=fr[3])], None, 0.01, notes
    if model == "phong":
        n = float(p.get("n", 10.0))
        kd, ks = _rgb(p.get("kd"), 0.0), _rgb(p.get("ks"), 1.0)
        width = 1.0 / math.sqrt(n + 1.0)
        if method == "osl":
            return [C.Term("diffuse", color=kd), C.Term("phong_ramp", color=ks, exponent=n)], None, width, notes
        notes.append("Phong lobe (around the mirror direction) fitted with a microfacet lobe")
        # Blinn-Phong half-vector exponent ~ 4 n_phong; Walter (2007): alpha ~ sqrt(2 / (n + 2))
        return None, None, width, _microfacet_candidates([math.sqrt(2.0 / (4 * n + 2.0))], diffuse_color=kd) + notes
    if model == "blinn_phong":
        n = float(p.get("n", 10.0))
        alpha = math.sqrt(2.0 / (n + 2.0))
        notes.append("Blinn-Phong exponent fitted with a microfacet alpha (Walter 2007: alpha ~ sqrt(2/(n+2)))")
        kd = _rgb(p.get("kd"), 0.0)
        cands = _microfacet_candidates([alpha], diffuse_color=kd)
        if method == "osl":
            # a Phong lobe around the mirror direction has no 1/cos factors either; n_phong ~ n / 4
            def build_phong(x):
                return [C.Term("diffuse", color=kd), C.Term("phong_ramp", exponent=float(x[0]))]

            cands.append(F.Candidate("diffuse + phong_ramp", build_phong, x0=(max(n / 4.0, 1.0),),
                                     linear=(None, "rgb"), bounds=((0.0, math.log(1e6)),),
                                     fitted_names=("phong_exponent",)))
        return None, None, alpha, cands + notes
    if model == "torrance_sparrow":
        ax, ay = _alphas(p)
        fr = _fresnel(p, given)
        notes.append("V-cavity G replaced by the height-correlated Smith G of Cycles' Beckmann; alpha refitted")
        cands = _microfacet_candidates([ax], fresnel=fr, distributions=("beckmann", "ggx"), diffuse=False,
                                       spec_linear="scalar")
        return None, None, ax, cands + notes
    if model == "ward":
        ax, ay = _alphas(p, 0.2)
        notes.append("Ward's Gaussian lobe fitted with an anisotropic Beckmann/GGX lobe (F = 1)")
        kd = _rgb(p.get("kd"), 0.0)
        return None, None, min(ax, ay), _microfacet_candidates([ax, ay], aniso=True, diffuse_color=kd) + notes
    if model == "ashikhmin_shirley":
        nu, nv = float(p.get("n_u", 100.0)), float(p.get("n_v", 100.0))
        rs = _rgb(p.get("Rs"), 0.05)
        ax, ay = math.sqrt(2.0 / (nu + 2.0)), math.sqrt(2.0 / (nv + 2.0))

        def build_as(x):
            return [C.Term("diffuse"), C.Term("ashikhmin_shirley", alpha_x=float(x[0]), alpha_y=float(x[1]))]

        cands = [F.Candidate("diffuse + Ashikhmin-Shirley lobe (F = 1)", build_as, x0=(ax, ay),
                             linear=("rgb", "rgb"), bounds=((math.log(1e-3), 0.0),) * 2,
                             fitted_names=("alpha_x", "alpha_y"))]
        cands += _microfacet_candidates([ax, ay], fresnel=("schlick", rs, (1.5,) * 3, (0.0,) * 3), aniso=True,
                                        distributions=("ggx",), spec_linear="scalar")
        notes.append("Fresnel-weighted AS lobe and coupled diffuse fitted (Cycles' AS closure has F = 1)")
        return None, None, min(ax, ay), cands + notes
    raise RadiometerError(f"no Cycles mapping for BRDF model {model!r}")


def realise(model, method="nodes", **params):
    """Closure terms and fidelity for ``model`` with ``params`` (validated; see ``resolve_params``).

    Returns
    -------
    terms : list of shading.closures.Term
    fidelity : Fidelity
    """
    if method not in METHODS:
        raise RadiometerError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    given = check_params(model, params)
    # The conductor Fresnel Cycles renders depends on the Blender version (closures.use_cycles_version).
    key = (model, method, tuple(sorted((k, _freeze(v)) for k, v in given.items())), C._APPROXIMATE_CONDUCTOR)
    terms, fid = _realise_cached(key)
    return list(terms), fid


def _same_terms(a, b, rtol=1e-9):
    if len(a) != len(b):
        return False
    for s, t in zip(a, b):
        if s.closure != t.closure:
            return False
        for name in ("alpha_x", "alpha_y", "roughness"):
            if not math.isclose(getattr(s, name), getattr(t, name), rel_tol=rtol, abs_tol=1e-12):
                return False
        if not np.allclose(s.color, t.color, rtol=rtol, atol=1e-12):
            return False
    return True


def _freeze(v):
    return tuple(v) if isinstance(v, list) else v


@functools.lru_cache(maxsize=256)
def _realise_cached(key):
    model, method, items, _approximate_conductor = key
    given = {k: (list(v) if isinstance(v, tuple) else v) for k, v in items}
    p = {name: given.get(name, spec.get("default")) for name, spec in param_specs(model).items()}
    terms, _, width, extra = _realise(model, method, p, set(given))
    cands = [c for c in extra if isinstance(c, F.Candidate)]
    notes = [s for s in extra if isinstance(s, str)]
    f_model = _f_model(model, given)
    fitted = {}
    if terms is None:
        result = F.fit(cands, f_model, lobe_width=width)
        terms = result.terms
        fitted = dict(result.fitted)
        fitted["closure"] = result.candidate
        analytic_exact = False
    else:
        analytic_exact = True
    if method == "nodes":
        limited = limit_for_nodes(terms)
        if not _same_terms(limited, terms):
            notes.append("closure parameters clamped to what Blender's nodes accept")
            analytic_exact = False
        terms = limited
    if any(t.closure == "mirror" for t in terms):
        rms, dalb = 0.0, 0.0
        notes.append("delta lobe: both are perfect mirrors; not measurable with a point light")
    else:
        rms, dalb = F.measure(terms, f_model, width)
    for t in terms:
        if t.closure in ("microfacet", "diffuse", "ashikhmin_shirley"):
            fitted.setdefault("weights", []).append([round(c, 6) for c in t.color])
    if model == "beckmann":
        notes.append("Cycles' Beckmann uses Walter et al.'s rational Smith-Lambda approximation")
    kind = "exact" if analytic_exact and rms <= EXACT_RMS else "approximate"
    fid = Fidelity(kind=kind, rms_rel_diff=rms, albedo_diff=dalb, closure=_describe_closures(terms, method),
                   fitted=fitted, notes="; ".join(notes), model=model, method=method, terms=list(terms))
    return list(terms), fid
