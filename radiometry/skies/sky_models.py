"""The sky models, by name (pure numpy): ``SKY_MODELS``, the one place a sky name is looked up.

Every sky name the add-on takes goes through :func:`sky_model`: ``api.set_cie_sky(sky_type=...)``,
``api.sun_study(sky=...)``, the CLI's ``sun-study --sky`` choices, the *Set CIE Sky* operator's list,
the world tag that ``measure/capture/world_capture.py`` reads back into an emitter, the CIE Sky panel
and the Radiance export's ``gensky`` line. A model is one object with:

* ``name`` (its key), ``label`` (what a person reads: "CIE sky type 12"), ``description``;
* ``sky_type``: what the model's formula module takes and the world tag stores ("overcast", 1..15);
* ``needs_sun``: True when its luminance depends on the sun's position;
* ``relative_luminance(directions, sun_direction)``: L / Lz above the horizon;
* ``sky_integral(normals, sun_direction)``: (I, error) with E = Lz I(n), sr;
* ``world(sun_direction, zenith_radiance, ground_radiance, node=...)``: the environment emitter the
  meter integrates (``radiometry.emitters.environment.EnvironmentEmitter``);
* ``gensky_flag``: the ``gensky`` option of the same sky, or None (the Radiance export then writes
  only its exact brightfunc).

How to add a sky model
----------------------
1. Its formula, pure and cited, in ``radiometry/skies/`` (as ``cie_sky.py``): relative luminance, the
   exact (or error-bounded) integral over the hemisphere for any plane, the emitter the meter
   integrates; tested against its source's tables or an independent integration.
2. One entry in ``SKY_MODELS`` below: a class with the attributes above (as :class:`CIESky`). The
   api's checks, the CLI's ``sun-study --sky`` choices, the operator's list and the panel follow from
   the mapping (``tests/test_sky_models.py`` checks it).
3. Its shader: ``measure/authoring/sky.py`` ``build_sky_tree`` writes the formula as world nodes (the
   world tag's fingerprint makes an edited tree fall back to rendering); a test that the rendered
   world reads what the emitter integrates (``tests/bpy/test_cie_sky_world.py``).
4. Its Radiance brightfunc: ``radiometry/skies/radiance_sky.py`` ``sky_cal`` (and ``gensky_flag``
   when ``gensky`` has the same sky), checked against Radiance in ``tests/bpy/test_radiance_export.py``.
"""

import dataclasses
import numbers

from . import cie_sky

__all__ = ["SKY_MODELS", "CIESky", "sky_model", "sky_names"]


@dataclasses.dataclass(frozen=True)
class CIESky:
    """One CIE sky: the traditional overcast sky or an ISO 15469 general sky type (``cie_sky``)."""

    name: str
    sky_type: object
    label: str
    description: str
    gensky_flag: str = None

    @property
    def needs_sun(self):
        return cie_sky.needs_sun(self.sky_type)

    def relative_luminance(self, directions, sun_direction=None):
        return cie_sky.relative_luminance(directions, self.sky_type, sun_direction)

    def sky_integral(self, normals, sun_direction=None):
        return cie_sky.sky_integral(normals, self.sky_type, sun_direction)

    def world(self, sun_direction, zenith_radiance, ground_radiance, **kwargs):
        return cie_sky.CIESkyWorld(self.sky_type, sun_direction, zenith_radiance, ground_radiance, **kwargs)


#: Every sky model by name. "overcast": the traditional CIE overcast sky, L = Lz (1 + 2 cos Z) / 3
#: (Moon & Spencer 1942), the daylight factor's sky; "cie:1" .. "cie:15": ISO 15469 / CIE S 011 general
#: skies. gensky's -c is the overcast sky, its -s the nearest line to type 12 (``radiance_sky``).
SKY_MODELS = {
    "overcast": CIESky("overcast", "overcast", "CIE overcast sky",
                       "traditional CIE overcast sky, L = Lz (1 + 2 cos Z) / 3 (Moon & Spencer), the daylight-factor "
                       "sky",
                       gensky_flag="-c"),
    **{f"cie:{t}": CIESky(f"cie:{t}", t, f"CIE sky type {t}", f"ISO 15469 type {t}: {row[7]}",
                          gensky_flag="-s" if t == 12 else None)
       for t, row in cie_sky.CIE_GENERAL_SKIES.items()},
}


def sky_names():
    """The names ``SKY_MODELS`` holds, in its order (what the CLI and the operator offer)."""
    return tuple(SKY_MODELS)


def sky_model(name):
    """The model called ``name``: a key of ``SKY_MODELS`` (any case), or a model's ``sky_type`` (the CIE
    types also as "7", "cie7", "type7"); ValueError naming every model otherwise."""
    if isinstance(name, str):
        key = name.strip().lower()
        if key in SKY_MODELS:
            return SKY_MODELS[key]
        for prefix in ("cie:", "cie", "type"):
            if key.startswith(prefix):
                key = key[len(prefix):].strip()
                break
        key = int(key) if key.isdigit() else key
    elif isinstance(name, numbers.Integral) and not isinstance(name, bool):
        key = int(name)
    else:
        key = None  # floats, bools and other objects name no sky
    for model in SKY_MODELS.values():
        if key is not None and type(key) is type(model.sky_type) and key == model.sky_type:
            return model
    raise ValueError(f"unknown sky type {name!r}: use one of {', '.join(SKY_MODELS)}")
