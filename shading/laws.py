"""One description of every BRDF -> Cycles mapping, run by numpy AND by the node-group builder (no bpy).

A *law* turns the model's parameters (the group node's inputs) and a few fitted *coefficients* into
closure terms (``closures.Term``). It is written once against a tiny algebra ``X`` (add, mul, sqrt,
min ...). ``NumpyOps`` evaluates it on numbers (the replica used for fitting and for the stated
fidelity); ``shading.nodes.NodeOps`` evaluates the same code by creating Math nodes inside the
group, so changing an input on the group node changes the render exactly as the replica predicts.

Structure (which closures, which Fresnel mode, isotropic or anisotropic inputs) is fixed when the
group is built; continuous parameters are inputs. Coefficients of approximate mappings are refitted
when the BRDF is applied (panel, operator, API) and kept as constants in the group: editing an input
on the node directly moves the closures along the law with the last fitted coefficients, and the
panel's "Refit" (re-apply) refreshes them and the stated fidelity.

Node limits (Glossy |anisotropy| <= 0.99, Metallic alpha_y/alpha_x >= 0.1, roughness <= 1) are part
of the law for method 'nodes' (``node_alphas``), so the replica renders what Cycles renders.
"""

import math
from dataclasses import replace

import numpy as np

from . import closures as C

#: Fresnel structures of microfacet models (and mirror): the inputs each one exposes.
FRESNEL_INPUTS = {"schlick": ("f0",), "dielectric": ("ior",), "conductor": ("eta", "k")}


class NumpyOps:
    """The law algebra on floats (scalars) and RGB triples (numpy arrays of shape (3,))."""

    add, sub, mul, div = (staticmethod(f) for f in (np.add, np.subtract, np.multiply, np.divide))
    cos, minimum, maximum = (staticmethod(f) for f in (np.cos, np.minimum, np.maximum))

    @staticmethod
    def sqrt(a):
        return np.sqrt(np.maximum(a, 0.0))

    @staticmethod
    def pow(a, b):
        return np.power(np.maximum(a, 0.0), b)

    @staticmethod
    def less(a, b):
        """1.0 where a < b else 0.0."""
        return np.where(np.less(a, b), 1.0, 0.0)

    @staticmethod
    def select(cond, a, b):
        """a where cond (0/1) is 1, else b."""
        return np.where(np.asarray(cond) > 0.5, a, b)

    # colours (RGB) -------------------------------------------------------------------------
    @staticmethod
    def cscale(c, s):
        return np.asarray(c, dtype=float) * s

    @staticmethod
    def cmul(a, b):
        return np.asarray(a, dtype=float) * np.asarray(b, dtype=float)

    @staticmethod
    def cone_minus(c):
        return 1.0 - np.asarray(c, dtype=float)

    @staticmethod
    def cmean(c):
        return float(np.mean(c))


def _f(x):
    return float(np.asarray(x))


def _rgb(x):
    return tuple(float(v) for v in np.broadcast_to(np.asarray(x, dtype=float), (3,)))


# -- structure -----------------------------------------------------------------------------------

def structure_of(model, params):
    """Structural choices from the given parameters: fresnel mode, anisotropy, variant.

    Returns a dict with ``fresnel`` ('schlick' | 'dielectric' | 'conductor' or None), ``aniso``
    (bool) and ``variant`` (Oren-Nayar) as they fix the group's inputs.
    """
    s = {"fresnel": None, "aniso": False, "variant": None}
    if model in ("ggx", "beckmann", "torrance_sparrow", "mirror"):
        if params.get("eta") is not None or params.get("k") is not None:
            s["fresnel"] = "conductor"
        elif params.get("ior") is not None:
            s["fresnel"] = "dielectric"
        else:
            s["fresnel"] = "schlick"
    if model in ("ggx", "beckmann", "torrance_sparrow"):
        s["aniso"] = params.get("alpha_x") is not None or params.get("alpha_y") is not None
    if model in ("ward", "ashikhmin_shirley"):
        s["aniso"] = True
    if model == "oren_nayar":
        s["variant"] = params.get("variant") or "classic"
    return s


def input_names(model, structure):
    """Names of the model parameters that become group inputs, in the library's order."""
    if model == "lambert":
        return ["albedo"]
    if model == "oren_nayar":
        return ["albedo", "sigma"]
    if model in ("phong", "blinn_phong"):
        return ["kd", "ks", "n"]
    if model == "ward":
        return ["kd", "ks", "alpha_x", "alpha_y"]
    if model == "ashikhmin_shirley":
        return ["n_u", "n_v", "Rs", "Rd"]
    names = []
    if model in ("ggx", "beckmann", "torrance_sparrow"):
        names += ["alpha_x", "alpha_y"] if structure["aniso"] else ["alpha"]
    names += list(FRESNEL_INPUTS[structure["fresnel"]])
    return names


def input_values(model, structure, p):
    """Values of the inputs from resolved parameters ``p`` (library defaults filled in)."""
    out = {}
    for name in input_names(model, structure):
        v = p.get(name)
        if v is None and name in ("alpha_x", "alpha_y"):
            v = p.get("alpha", 0.2)
        if v is None and name == "ior":
            v = 1.5
        if v is None and name in ("eta", "k"):
            v = (0.143, 0.374, 1.442) if name == "eta" else (3.983, 2.386, 1.603)
        out[name] = v
    return out


# -- node limits ---------------------------------------------------------------------------------

def glossy_controls(X, ax, ay):
    """(roughness, anisotropy) of a Glossy BSDF for alphas (ax, ay): |anisotropy| <= 0.99, alpha <= 1."""
    alpha = X.minimum(X.sqrt(X.mul(ax, ay)), 1.0)
    ratio_lt = X.sqrt(X.div(ax, ay))  # < 1 when ax < ay
    aniso_lt = X.sub(1.0, ratio_lt)
    aniso_ge = X.sub(X.sqrt(X.div(ay, ax)), 1.0)
    aniso = X.select(X.less(ax, ay), aniso_lt, aniso_ge)
    aniso = X.maximum(X.minimum(aniso, 0.99), -0.99)
    return X.sqrt(alpha), aniso


def metallic_controls(X, ax, ay):
    """(roughness, anisotropy, rotation) of a Metallic BSDF: alpha_y/alpha_x >= 0.1, alpha <= 1."""
    lo, hi = X.minimum(ax, ay), X.maximum(ax, ay)
    lo = X.maximum(lo, X.mul(0.1, hi))
    alpha = X.minimum(X.sqrt(X.mul(lo, hi)), 1.0)
    aniso = X.div(X.sub(1.0, X.div(lo, hi)), 0.9)
    aniso = X.maximum(X.minimum(aniso, 1.0), 0.0)
    rotation = X.mul(X.less(ax, ay), 0.25)
    return X.sqrt(alpha), aniso, rotation


def cycles_alphas_glossy(roughness, aniso):
    """Alphas Cycles derives from Glossy controls (kernel svm/closure.h)."""
    a = roughness * roughness
    if aniso >= 0:
        return a * (1.0 - aniso), a / (1.0 - aniso)
    return a / (1.0 + aniso), a * (1.0 + aniso)


def cycles_alphas_metallic(roughness, aniso, rotation):
    a = roughness * roughness
    aspect = math.sqrt(max(1.0 - 0.9 * aniso, 0.0))
    ax, ay = a / aspect, a * aspect
    return (ay, ax) if rotation > 0.125 else (ax, ay)


def node_alphas(term, method):
    """The term with the alphas Cycles will use when the group sets them through node controls."""
    if method != "nodes" or term.closure not in ("microfacet",):
        return term
    X = NumpyOps
    if term.fresnel in ("schlick", "conductor"):
        r, a, rot = (_f(v) for v in metallic_controls(X, term.alpha_x, term.alpha_y))
        ax, ay = cycles_alphas_metallic(r, a, rot)
    else:
        r, a = (_f(v) for v in glossy_controls(X, term.alpha_x, term.alpha_y))
        ax, ay = cycles_alphas_glossy(r, a)
    return replace(term, alpha_x=ax, alpha_y=ay)


# -- the laws ------------------------------------------------------------------------------------

def _fresnel_fields(structure, x):
    fr = structure["fresnel"]
    if fr == "schlick":
        return {"fresnel": "schlick", "f0": x["f0"]}
    if fr == "dielectric":
        # Cycles' conductor Fresnel with k = 0 is the exact dielectric Fresnel (outside incidence)
        return {"fresnel": "conductor", "ior": ("rgb", x["ior"]), "k": (0.0, 0.0, 0.0)}
    return {"fresnel": "conductor", "ior": x["eta"], "k": x["k"]}


def _exp_alpha(X, n):
    """Walter et al. (2007) sec. 5.2: Beckmann alpha ~ sqrt(2 / (n + 2)) for a cos^n lobe."""
    return X.sqrt(X.div(2.0, X.add(n, 2.0)))


def law(X, model, method, structure, x, c):
    """Closure terms (fields may be numbers or node sockets) for inputs ``x`` and coefficients ``c``.

    ``c`` holds fitted constants (numbers) and, for some laws, ``distribution``.
    """
    T = C.Term
    if model == "lambert":
        return [T("diffuse", color=x["albedo"])]
    if model == "oren_nayar":
        if structure["variant"] == "cycles":
            return [T("oren_nayar", color=x["albedo"], roughness=x["sigma"])]
        # classic sigma (rad) -> Cycles roughness: linear law, slope fitted
        return [T("oren_nayar", color=x["albedo"], roughness=X.minimum(X.mul(c["roughness_per_sigma"], x["sigma"]), 1.0))]
    if model in ("ggx", "beckmann"):
        ax = x["alpha_x"] if structure["aniso"] else x["alpha"]
        ay = x["alpha_y"] if structure["aniso"] else x["alpha"]
        return [T("microfacet", distribution=model, alpha_x=ax, alpha_y=ay, **_fresnel_fields(structure, x))]
    if model == "mirror":
        return [T("mirror", **_fresnel_fields(structure, x))]
    if model == "torrance_sparrow":
        ax = x["alpha_x"] if structure["aniso"] else x["alpha"]
        ay = x["alpha_y"] if structure["aniso"] else x["alpha"]
        s = c["alpha_scale"]
        return [T("microfacet", distribution="beckmann", alpha_x=X.mul(s, ax), alpha_y=X.mul(s, ay),
                  color=(c["weight"],) * 3, **_fresnel_fields(structure, x))]
    if model == "ward":
        return [T("diffuse", color=x["kd"]),
                T("microfacet", distribution=c.get("distribution", "beckmann"),
                  alpha_x=X.minimum(X.mul(c["alpha_x_scale"], x["alpha_x"]), 1.0),
                  alpha_y=X.minimum(X.mul(c["alpha_y_scale"], x["alpha_y"]), 1.0),
                  color=X.cscale(x["ks"], c["weight"]))]
    if model == "phong":
        if method == "osl":
            return [T("diffuse", color=x["kd"]), T("phong_ramp", color=x["ks"], exponent=x["n"])]
        return [T("diffuse", color=x["kd"])] + _phong_toon_terms(X, x, c)
    if model == "blinn_phong":
        alpha = X.minimum(X.mul(c["alpha_scale"], _exp_alpha(X, x["n"])), 1.0)
        # the normal tilted towards the viewer by ~ tilt tan(theta_o) / (n + 2) stands in for the lobe's
        # cos_i factor (issue 18: 21 % -> ~6 % RMS on the uniform set at n = 50); the Script node takes
        # it as its SpecularNormal (the diffuse lobe keeps the surface's normal)
        tilt = X.div(c["tilt"], X.add(x["n"], 2.0)) if "tilt" in c else 0.0
        return [T("diffuse", color=x["kd"]),
                T("microfacet", distribution=c.get("distribution", "beckmann"), alpha_x=alpha, alpha_y=alpha,
                  color=X.cscale(x["ks"], c["weight"]), view=(("pow", c["view_exponent"]),), tilt=tilt)]
    if model == "ashikhmin_shirley":
        # specular: GGX with Schlick Fresnel F0 = Rs (the model's own Fresnel), alphas from the exponents;
        # diffuse: Lambert weighted by the model's view factor 1-(1-cos_o/2)^5 (the light factor is fitted
        # as a constant): 28/23 Rd (1 - Rs) c_d.
        ax = X.minimum(X.mul(c["alpha_scale"], _exp_alpha(X, x["n_u"])), 1.0)
        ay = X.minimum(X.mul(c["alpha_scale"], _exp_alpha(X, x["n_v"])), 1.0)
        diffuse = X.cscale(X.cmul(x["Rd"], X.cone_minus(x["Rs"])), X.mul(28.0 / 23.0, c["diffuse_scale"]))
        return [T("diffuse", color=diffuse, view=(("as_diffuse",),)),
                T("microfacet", distribution=c.get("distribution", "beckmann"), alpha_x=ax, alpha_y=ay,
                  fresnel="schlick", f0=x["Rs"],
                  color=(c["weight"],) * 3)]
    raise ValueError(f"no Cycles mapping for BRDF model {model!r}")


#: Toon ramps that draw the Phong lobe for method 'nodes', and how far out they reach (in lobe widths).
PHONG_RAMPS = 6
PHONG_REACH = 3.5


def _phong_toon_terms(X, x, c):
    """The modified Phong lobe ks (n+2)/(2 pi) cos^n(a) cos(theta_i) as Cycles Toon (glossy) closures.

    A Toon closure's eval is I(a) / (2 pi (1 - cos a_s)) in the angle a between the light and the mirror
    direction of the view: Phong's own variable. PHONG_RAMPS nested ramps (full out to a_(j-1), linear to
    0 at a_j, knots a_j = j A / K, A = min(PHONG_REACH / sqrt(m + 1), pi/2)) sum to the piecewise-linear
    interpolant of g(a) = cos^m(a), m = n + exponent_offset, with weights (g_(j-1) - g_j) 2 pi (1 - cos a_j).
    The cos_i factor, which a closure's eval lacks, is cos_o^view_exponent times a normal tilted towards
    the viewer (``closures.tilted_normal``, tilt / (n + 2)); ``weight`` scales the lobe. All fitted.
    """
    T = C.Term
    k = PHONG_RAMPS
    m = X.add(x["n"], c["exponent_offset"])
    reach = X.minimum(X.div(PHONG_REACH, X.sqrt(X.add(m, 1.0))), math.pi / 2)
    scale = X.mul(c["weight"], X.add(x["n"], 2.0))  # (n + 2) / (2 pi) x the 2 pi of the ramps' pdf
    tilt = X.div(c["tilt"], X.add(x["n"], 2.0))
    knots = [X.mul(reach, j / k) for j in range(k + 1)]
    g = [X.pow(X.maximum(X.cos(a), 0.0), m) for a in knots[:-1]] + [0.0]
    terms = []
    for j in range(1, k + 1):
        w = X.mul(X.mul(X.sub(g[j - 1], g[j]), X.sub(1.0, X.cos(knots[j]))), scale)
        terms.append(T("toon", color=X.cscale(x["ks"], w), size=X.div(knots[j - 1], math.pi / 2),
                       smooth=X.div(X.sub(knots[j], knots[j - 1]), math.pi / 2), tilt=tilt,
                       view=(("pow", c["view_exponent"]),)))
    return terms


#: Coefficients to fit per model (name, start value, (lo, hi)); analytic starts from the references.
COEFFICIENTS = {
    "oren_nayar": [("roughness_per_sigma", 0.63, (0.05, 3.0))],
    "torrance_sparrow": [("alpha_scale", 1.0, (0.3, 3.0)), ("weight", 1.0, (0.2, 1.0))],
    "ward": [("alpha_x_scale", 1.0, (0.3, 3.0)), ("alpha_y_scale", 1.0, (0.3, 3.0)), ("weight", 1.0, (0.2, 1.5))],
    "phong": [("weight", 1.0, (0.3, 3.0)), ("view_exponent", 1.0, (0.05, 4.0)), ("exponent_offset", 1.0, (0.01, 8.0)),
              ("tilt", 0.5, (0.01, 4.0))],
    "blinn_phong": [("alpha_scale", 1.0, (0.1, 3.0)), ("weight", 1.0, (0.1, 4.0)), ("view_exponent", 1.0, (0.05, 4.0)),
                    ("tilt", 1.5, (0.01, 8.0))],
    "ashikhmin_shirley": [("alpha_scale", 1.0, (0.3, 3.0)), ("weight", 1.0, (0.2, 2.0)),
                          ("diffuse_scale", 0.9, (0.3, 1.5))],
}
DISTRIBUTIONS = {"blinn_phong": ("beckmann", "ggx"), "ward": ("beckmann", "ggx"),
                 "ashikhmin_shirley": ("beckmann", "ggx")}


def coefficient_specs(model, method):
    """The coefficients fitted for ``model`` realised by ``method`` (every one: the Script node has a
    SpecularNormal of its own for a tilted lobe)."""
    return list(COEFFICIENTS[model])


def needs_fit(model, method, structure):
    if model == "oren_nayar":
        return structure["variant"] != "cycles"
    if model == "phong" and method == "osl":
        return False
    return model in COEFFICIENTS


def numeric_terms(model, method, structure, x, c):
    """The replica: law on numbers, colours as RGB tuples, node limits applied for method 'nodes'."""
    terms = law(NumpyOps, model, method, structure, x, c)
    out = []
    for t in terms:
        kw = {}
        for name in ("color", "f0", "ior", "k"):
            v = getattr(t, name)
            if isinstance(v, tuple) and len(v) == 2 and v[0] == "rgb":
                v = v[1]
            kw[name] = _rgb(v)
        for name in ("alpha_x", "alpha_y", "roughness", "exponent", "size", "smooth", "tilt"):
            kw[name] = _f(getattr(t, name))
        view = tuple((f[0],) + tuple(float(v) for v in f[1:]) for f in t.view)
        t = replace(t, view=view, **kw)
        if t.closure == "oren_nayar":
            t = replace(t, roughness=min(max(t.roughness, 0.0), 1.0))
        out.append(node_alphas(t, method))
    return out
