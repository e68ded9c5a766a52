"""Light sources, one interface (:class:`.base.Emitter`), one module per kind; pure numpy, never bpy.

Kinds: :mod:`.point`, :mod:`.spot`, :mod:`.sun`, :mod:`.area`, :mod:`.photometric` (the Blender lights,
sharing :class:`.cycles_light.CyclesLight`), :mod:`.environment` (the world: constant, image, CIE sky),
:mod:`.emissive_mesh` (surfaces with an Emission shader, rendered only). See README.md here and
docs/emitters.md.
"""

from .base import Emitter, EmitterFlags, RayVisibility, SourceId
from .cycles_light import CyclesLight, from_blender_values, light_class
from .point import PointLight
from .spot import SpotLight
from .sun import SunLight
from .area import AreaLight
from .photometric import Photometry, PhotometricLight
from .environment import EnvironmentEmitter
from .emissive_mesh import EmissiveMesh

__all__ = ["Emitter", "EmitterFlags", "RayVisibility", "SourceId", "CyclesLight", "from_blender_values",
           "PointLight", "SpotLight", "SunLight", "AreaLight", "Photometry", "PhotometricLight",
           "EnvironmentEmitter", "EmissiveMesh", "light_class"]
