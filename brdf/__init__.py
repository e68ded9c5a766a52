"""Pure-numpy BRDF reference library of Radiometer (no bpy, no mathutils).

Conventions
-----------
* Directions ``wi`` (towards the light) and ``wo`` (towards the viewer) are arrays of shape
  (..., 3) in the LOCAL shading frame: x = tangent, y = bitangent, z = normal; both point away
  from the surface. Use :func:`frame.to_local` to convert from world space. Inputs are normalised;
  a NaN component gives NaN for that element only; infinite components are limit directions.
* :func:`evaluate` returns the BRDF f in 1/sr WITHOUT the cosine factor, always RGB (..., 3);
  scalar parameters broadcast to RGB. f = 0 when cos θi <= 0 or cos θo <= 0.
* ``alpha`` is the microfacet slope parameter; Blender's "Roughness" r maps to alpha = r².
  Height-correlated Smith G2 = 1/(1 + Λ(wi) + Λ(wo)) (ggx, beckmann, as in Cycles);
  torrance_sparrow uses the V-cavity G.
* Microfacet models and mirror take Fresnel from exactly one of ``f0`` (Schlick, scalar or RGB,
  default 1 = no Fresnel), ``ior`` (exact dielectric) or ``eta`` + ``k`` (exact conductor, RGB).
* Parameters are validated: NaN or out-of-range values raise ValueError naming the parameter and
  its range. Directions may be anything.
* All models here are reciprocal; ward, ashikhmin_shirley (and microfacet models with
  alpha_x != alpha_y) are anisotropic.

Public API
----------
names(), evaluate(model, wi, wo, **params), albedo(model, theta_i, **params),
sample(model, wo, u, **params), pdf(model, wi, wo, **params), describe(model),
reflectance(cos_theta, **fresnel_params); submodules frame, fresnel, microfacet, models, plots.

How to add a model (checklist)
------------------------------
1. Subclass ``models.Model`` in ``models.py``: set ``name`` (registry key), ``doc``,
   ``references`` (an independent source for every formula) and ``params`` (``Param`` entries
   with default, min, max, kind, unit, description; add ``FRESNEL_PARAMS``/``ALPHA_PARAMS``
   and ``has_fresnel = True`` for microfacet-style models).
2. Implement ``f(wi, wo, p)`` for unit directions above the horizon, vectorised over leading
   axes, returning (..., 3) with no cosine factor; guard divisions (comment why) so that every
   finite input gives a finite result without numpy warnings.
3. If it can be importance-sampled, implement ``sample(wo, u1, u2, p) -> (wi, pdf)`` and
   ``pdf(wi, wo, p)`` (density over the sphere); otherwise set ``samplable = False``.
4. Put cross-parameter constraints (e.g. kd + ks <= 1) in ``check(p)``; set ``reciprocal`` and
   ``isotropic`` truthfully.
5. Register the instance in ``models.MODELS``; add representative parameters to the test tables in
   ``tests/test_brdf_*.py`` (``MODEL_PARAMS``) and a closed-form check from an independent source.
"""

from . import fresnel, frame, microfacet, models
from .registry import albedo, describe, evaluate, names, pdf, reflectance, sample

__all__ = ["names", "evaluate", "albedo", "sample", "pdf", "describe", "reflectance",
           "frame", "fresnel", "microfacet", "models"]
