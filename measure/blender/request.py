"""One measurement request (issue 30): what every level of a measurement needs to know about the scene and
the caller, derived once and passed down instead of re-derived (the scene's photometry and unit scale, the
view layer) or written out again (quality, progress, cancelled, seed, ...) at every level.

The api builds it (:func:`build`) from its arguments and the add-on's settings (the efficacy is passed in;
measure/ reads no property group). Code below the api takes a ``request``; an entry point that is also
called with a bare scene (the analyses call each other, tests call the meter) turns what it was given into
one with :func:`of`, so a request handed down is used as it is and never rebuilt.

Conventions: ``scale_length`` is metres per scene unit (Cycles ignores it when it renders: a rendered
W per scene-unit^2 is W/m^2 x scale_length^2); ``efficacy`` is the luminous efficacy K (lm/W) that turns
the CIE Y weighted irradiance of the working colour space into lux (README "Conventions").
"""

import dataclasses

import numpy as np

from ...radiometry.constants import K_M_LM_PER_W
from . import efficacy as scene_efficacy

DEFAULT_EFFICACY = K_M_LM_PER_W  # 683 lm/W, Blender's glTF convention; see README "Conventions"

#: The accuracy fields of a request: a quality preset ("preview" 5 %, "standard" 1 %, "reference" 0.2 %
#: 1-sigma relative error), or a target fraction, a fixed sample count per meter, a time budget in seconds
#: and the absolute error floor in lux (None: the preset's). The meter takes them as keywords.
BUDGET_FIELDS = ("quality", "target_rel_error", "samples", "time_budget_s", "target_abs_error")


@dataclasses.dataclass(frozen=True, eq=False)
class Request:
    """A measurement's scene and caller, derived once. Immutable: :meth:`but` makes a changed copy (an
    analysis that reads one part at its own target or seed)."""

    scene: object
    view_layer: object
    scale_length: float  #: metres per scene unit
    colour_space: str  #: the scene's working colour space (the luminance weights' primaries)
    luminance_weights: tuple  #: CIE Y weights (3,) of that space
    efficacy: float  #: lm/W
    quality: object = None  #: a preset name, or None: "standard" (a study may tell "not given" apart)
    target_rel_error: object = None
    samples: object = None
    time_budget_s: object = None
    target_abs_error: object = None
    seed: int = 0
    progress: object = None  #: progress(done, total, seconds_left) or None
    cancelled: object = None  #: cancelled() -> bool or None
    client: object = None  #: a cluster client (batch work) or None

    @property
    def weights(self):
        """The CIE Y weights as a float64 (3,) array (a fresh copy: callers may scale it)."""
        return np.asarray(self.luminance_weights, float)

    @property
    def photometry(self):
        """(colour space name, luminance weights (3,), efficacy lm/W)."""
        return self.colour_space, self.weights, self.efficacy

    @property
    def unit_area(self):
        """m^2 per scene unit^2: Cycles renders W per scene unit^2 (divide by this for W/m^2)."""
        return self.scale_length ** 2

    def to_metres(self, values):
        """Scene units -> metres (float64 array)."""
        return np.asarray(values, float) * self.scale_length

    def preset(self):
        """The quality preset's settings (``radiometer.quality.preset``; "standard" when none was given)."""
        from ... import quality as quality_presets

        return quality_presets.preset(self.quality or "standard")

    def budget(self):
        """The accuracy settings as the meter's keywords (``BUDGET_FIELDS``)."""
        return {name: getattr(self, name) for name in BUDGET_FIELDS}

    def but(self, **changes):
        """A copy with ``changes``; ``scene=`` another scene re-derives what depends on it (a temporary
        render scene that reads as the user's keeps its efficacy)."""
        if "scene" in changes and changes["scene"] is not self.scene:
            scene = changes.pop("scene")
            fresh = build(scene, view_layer=changes.pop("view_layer", None), efficacy=self.efficacy)
            changes = {**{f.name: getattr(self, f.name) for f in dataclasses.fields(self)
                          if f.name not in ("scene", "view_layer", "scale_length", "colour_space",
                                            "luminance_weights", "efficacy")},
                       **changes}
            return dataclasses.replace(fresh, **changes)
        return dataclasses.replace(self, **changes)


def view_layer_of(scene):
    """The view layer that renders ``scene``: the context's when it is the context scene, else its first."""
    import bpy

    return bpy.context.view_layer if bpy.context.scene == scene else scene.view_layers[0]


def build(scene=None, *, view_layer=None, efficacy=None, **fields):
    """The request for ``scene`` (None: the context scene). ``efficacy``: K lm/W as the caller read it
    (the api: the add-on's setting); None asks ``efficacy.of`` (the reader the api installs, which also
    serves Radiometer's temporary scenes and files a batch opens) and falls back to 683 lm/W.
    ``fields``: the budget, seed, progress, cancelled and client (None keeps a field's default)."""
    import bpy

    from ...compat import working_colour_space
    from ...radiometry.photometry import efficacy as photometry

    scene = scene or bpy.context.scene
    if efficacy is None:
        efficacy = scene_efficacy.of(scene)
    efficacy = DEFAULT_EFFICACY if efficacy is None else float(efficacy)
    space = working_colour_space()
    weights = tuple(float(w) for w in photometry.luminance_weights(space))
    given = {k: v for k, v in fields.items() if v is not None}
    return Request(scene=scene, view_layer=view_layer or view_layer_of(scene),
                   scale_length=float(scene.unit_settings.scale_length), colour_space=space,
                   luminance_weights=weights, efficacy=efficacy, **given)


def of(source=None, **changes):
    """The request of ``source`` with ``changes`` that are not None: ``source`` a request (used as it is,
    never rebuilt), a scene (a request built for it: tests, scripts and the authoring tools called with
    a bare scene) or None (the context scene).

    The one door from an entry point's arguments to its request."""
    changes = {k: v for k, v in changes.items() if v is not None}
    if isinstance(source, Request):
        return source.but(**changes) if changes else source
    return build(source, **changes)
