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
phong              Diffuse + 6 Toon (glossy) ramps drawing diffuse + phong_ramp (exact)
                   cos^n of the angle to the mirror
                   direction, normal tilted to the view
                   (~6 % RMS uniform set at n = 20)
blinn_phong        Glossy Beckmann/GGX, cos_o^p weight,    diffuse + microfacet, the same fit:
                   normal tilted to the view, fitted       the tilted normal is the Script's
                   (~5 % RMS uniform set at n = 50;        SpecularNormal (~5 % at n = 50)
                   ~23 % at n = 10: the lobe is wide and
                   a closure's 1/cos_i, which no weight
                   can undo (weights see the view, not
                   the light), dominates)
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
from . import laws as L
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
    pointwise: object = None  # shading.fit.Pointwise on the uniform direction set
    structure: dict = field(default_factory=dict)
    inputs: dict = field(default_factory=dict)
    coefficients: dict = field(default_factory=dict)

    def summary(self):
        if self.kind == "exact":
            return "exact"
        text = f"approximate: RMS {100 * self.rms_rel_diff:.1f} %, albedo \u0394 {self.albedo_diff:.3f}"
        pw = self.pointwise
        if pw is not None and pw.n:
            text += f"; ratio median {pw.median:.2f}, 95 % within {pw.p95:.2f}\u00d7, max {pw.max:.2f}\u00d7"
        return text

    def to_dict(self):
        return {"kind": self.kind, "rms_rel_diff": self.rms_rel_diff, "albedo_diff": self.albedo_diff,
                "closure": self.closure, "fitted": self.fitted, "notes": self.notes, "model": self.model,
                "method": self.method, "terms": [t.to_dict() for t in self.terms], "summary": self.summary(),
                "pointwise": self.pointwise.to_dict() if self.pointwise is not None else None,
                "structure": dict(self.structure), "coefficients": dict(self.coefficients)}


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
            names.append(("Diffuse BSDF" if method == "nodes" else "diffuse()")
                         + (" x (1-(1-cos_o/2)^5)" if t.view else ""))
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
            weight = ""
            for v in t.view:
                weight += f" x cos_o^{v[1]:.2f}" if v[0] == "pow" else ""
            tilt = f", normal tilted {t.tilt:.3g} towards the view" if t.tilt else ""
            names.append(f"{node} {dist} {rough}{weight}{tilt}")
        elif c == "toon":
            if names and names[-1].startswith("Toon BSDF"):
                continue  # the ramps of one Phong lobe are named once
            ramps = sum(1 for u in terms if u.closure == "toon")
            weight = "".join(f" x cos_o^{v[1]:.2f}" for v in t.view if v[0] == "pow")
            tilt = f", normal tilted {t.tilt:.3g} towards the view" if t.tilt else ""
            names.append(f"Toon BSDF (glossy) x {ramps} ramps{weight}{tilt}")
        elif c == "ashikhmin_shirley":
            names.append(f"Glossy BSDF Ashikhmin-Shirley alpha {t.alpha_x:.3g}, {t.alpha_y:.3g}")
    return " + ".join(names)


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


def realise(model, method="nodes", coefficients=None, **params):
    """Closure terms and fidelity for ``model`` with ``params`` (validated; see ``resolve_params``).

    ``coefficients`` (optional dict) evaluates the law with given fitted constants instead of
    refitting: what a group node renders after one of its inputs was edited directly.

    Returns
    -------
    terms : list of shading.closures.Term
    fidelity : Fidelity
    """
    if method not in METHODS:
        raise RadiometerError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    given = check_params(model, params)
    # The conductor Fresnel Cycles renders depends on the Blender version (closures.use_cycles_version).
    coef = tuple(sorted((k, _freeze(v)) for k, v in (coefficients or {}).items()))
    key = (model, method, tuple(sorted((k, _freeze(v)) for k, v in given.items())), coef, C._APPROXIMATE_CONDUCTOR)
    terms, fid = _realise_cached(key)
    return list(terms), fid


def _freeze(v):
    return tuple(v) if isinstance(v, list) else v


def mapping_for(model, method, params):
    """(structure, inputs, coefficients) that the group for ``model`` with ``params`` is built from."""
    _, fid = realise(model, method, **params)
    return fid.structure, fid.inputs, fid.coefficients


@functools.lru_cache(maxsize=256)
def _realise_cached(key):
    model, method, items, coef_items, _approximate_conductor = key
    given = {k: (list(v) if isinstance(v, tuple) else v) for k, v in items}
    p = {name: given.get(name, spec.get("default")) for name, spec in param_specs(model).items()}
    structure = L.structure_of(model, given | {"variant": p.get("variant")})
    x = L.input_values(model, structure, p)
    f_model = _f_model(model, given)
    notes = []
    fitted = bool(coef_items) or L.needs_fit(model, method, structure)
    if coef_items:
        coef = {k: v for k, v in coef_items}
    elif fitted:
        width = _lobe_width(model, p)
        best = None
        for dist in L.DISTRIBUTIONS.get(model, (None,)):
            extra = {"distribution": dist} if dist else {}

            def build(c, extra=extra):
                return L.numeric_terms(model, method, structure, x, dict(c, **extra))

            c, cost = F.fit_coefficients(build, L.coefficient_specs(model, method), f_model, width)
            if best is None or cost < best[1]:
                best = (dict(c, **extra), cost)
        coef = best[0]
    else:
        coef = {}
    terms = L.numeric_terms(model, method, structure, x, coef)
    raw = L.law(L.NumpyOps, model, method, structure, x, coef)
    clamped = any(t.closure == "microfacet" and (abs(float(np.asarray(r.alpha_x)) - t.alpha_x) > 1e-9
                                                 or abs(float(np.asarray(r.alpha_y)) - t.alpha_y) > 1e-9)
                  for r, t in zip(raw, terms))
    if clamped:
        notes.append("closure parameters clamped to what Blender's nodes accept")
    if any(t.closure == "mirror" for t in terms):
        rms, dalb = 0.0, 0.0
        pw = F.Pointwise(0.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0)
        notes.append("delta lobe: both are perfect mirrors; not measurable with a point light")
    else:
        rms, dalb = F.measure(terms, f_model, _lobe_width(model, p))
        pw = F.measure_pointwise(lambda a, b: C.evaluate_terms(terms, a, b), f_model)
    notes += _NOTES.get(model, [])
    if fitted:
        notes.append("fitted coefficients are constants in the group; inputs drive the closures through them "
                     "(re-apply to refit)")
    analytic_exact = not fitted and not clamped and model not in ("beckmann",)
    kind = "exact" if analytic_exact and rms <= EXACT_RMS and pw.max - 1.0 <= EXACT_RMS else "approximate"
    fid = Fidelity(kind=kind, rms_rel_diff=rms, albedo_diff=dalb, closure=_describe_closures(terms, method),
                   fitted=dict(coef), notes="; ".join(notes), model=model, method=method, terms=list(terms),
                   pointwise=pw, structure=structure, inputs=x, coefficients=dict(coef))
    return list(terms), fid


_NOTES = {
    "beckmann": ["Cycles' Beckmann uses Walter et al.'s rational Smith-Lambda approximation"],
    "oren_nayar": [],
    "torrance_sparrow": ["V-cavity G replaced by the height-correlated Smith G of Cycles' Beckmann; alpha scaled"],
    "ward": ["Ward's lobe realised by an anisotropic microfacet lobe (F = 1), alphas and weight fitted"],
    "phong": [],
    "blinn_phong": [],
    "ashikhmin_shirley": ["specular: GGX with the model's Schlick Fresnel (F0 = Rs); diffuse: Lambert with the "
                          "model's view factor, its light factor fitted as a constant"],
}


def _lobe_width(model, p):
    if model in ("phong", "blinn_phong"):
        return 1.0 / math.sqrt(float(p.get("n", 10.0)) + 1.0)
    if model == "ashikhmin_shirley":
        return math.sqrt(2.0 / (max(float(p.get("n_u", 100.0)), float(p.get("n_v", 10.0))) + 2.0))
    if model in ("ggx", "beckmann", "torrance_sparrow", "ward"):
        vals = [v for v in (p.get("alpha"), p.get("alpha_x"), p.get("alpha_y")) if v is not None]
        return min(vals) if vals else 0.2
    return 0.5
