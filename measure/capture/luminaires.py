"""Photometric luminaires as Blender lights: import a file, and read an IES node tree back exactly.

Import (:func:`import_luminaire`): a POINT light of radius 0 whose node tree is
Geometry.Incoming -> Vector Transform (NORMAL, world -> object) -> Mapping (VECTOR, rotation
z = -90 deg, scale (1, -1, 1)) -> IES Texture (internal text) -> Emission.Strength -> Light Output.
The text is :func:`radiometry.photometry.photometric_files.to_ies_text` of the file's type-C table expanded to
0-360 deg, so Cycles interprets no symmetry or TILT of its own. The Mapping turns Radiometer's
convention (vertical 0 deg = local -Z, C0 = local +X, C90 = local +Y) into Cycles' own IES frame,
which is mirrored (C0 along local -Y, C90 along local -X: measured, see the README). The light's
energy is 177.83 / K W (K = the scene's luminous efficacy), so Cycles renders I(theta, C) / K W/sr:
lux = K x luminance of the irradiance gives the file's candela back.

Recognition (:func:`photometric_table`): any light whose active output is
Emission <- IES Texture (vector unlinked, or the chain above with any Mapping rotation/scale),
with unlinked colour/strength inputs and a text/file Cycles can read, gets an
:class:`~radiometer.radiometry.emitters.photometric.Photometry` (``light_table``) read the way Cycles reads that text
(:func:`~radiometer.radiometry.photometry.photometric_files.cycles_ies_table`); anything else is left to
rendering.
"""

import functools
import math
import os

import bpy
import numpy as np

from ...errors import RadiometerError
from ...radiometry.constants import K_M_LM_PER_W
from ...radiometry.photometry import photometric_files as pf

#: Custom properties Radiometer puts on an imported light's data.
PROP_SOURCE = "radiometer_photometric_file"
PROP_LUMENS = "radiometer_lumens"

_MAPPING_ROTATION = (0.0, 0.0, -math.pi / 2)
_MAPPING_SCALE = (1.0, -1.0, 1.0)


def scene_efficacy(scene):
    """K (lm/W) of ``scene``: a request (``measure.blender.request``), a scene or None; 683 lm/W where the
    setting is not above 0."""
    from ..blender import request as request_of

    value = request_of.of(scene).efficacy
    return value if value > 0.0 else K_M_LM_PER_W


# --- import ---------------------------------------------------------------------------------------

def _tilt_deg(rotation_euler):
    from mathutils import Euler, Vector

    down = Euler(rotation_euler, "XYZ").to_matrix() @ Vector((0.0, 0.0, -1.0))
    return math.degrees(math.acos(max(-1.0, min(1.0, -down.z))))


def build_node_tree(light_data, text):
    """Give ``light_data`` the IES node tree described in the module docstring."""
    light_data.use_nodes = True
    tree = light_data.node_tree
    tree.nodes.clear()
    out = tree.nodes.new("ShaderNodeOutputLight")
    emission = tree.nodes.new("ShaderNodeEmission")
    ies = tree.nodes.new("ShaderNodeTexIES")
    ies.mode = "INTERNAL"
    ies.ies = text
    mapping = tree.nodes.new("ShaderNodeMapping")
    mapping.vector_type = "VECTOR"
    mapping.inputs["Rotation"].default_value = _MAPPING_ROTATION
    mapping.inputs["Scale"].default_value = _MAPPING_SCALE
    transform = tree.nodes.new("ShaderNodeVectorTransform")
    transform.vector_type, transform.convert_from, transform.convert_to = "NORMAL", "WORLD", "OBJECT"
    geometry = tree.nodes.new("ShaderNodeNewGeometry")
    for k, node in enumerate((geometry, transform, mapping, ies, emission, out)):
        node.location = (-1000 + 200 * k, 0)
    mapping.label = "Radiometer: C0 = +X, C90 = +Y"
    tree.links.new(geometry.outputs["Incoming"], transform.inputs["Vector"])
    tree.links.new(transform.outputs["Vector"], mapping.inputs["Vector"])
    tree.links.new(mapping.outputs["Vector"], ies.inputs["Vector"])
    tree.links.new(ies.outputs["Fac"], emission.inputs["Strength"])
    tree.links.new(emission.outputs["Emission"], out.inputs["Surface"])
    return tree


def import_luminaire(path, *, scene=None, location=(0.0, 0.0, 0.0), rotation_euler=(0.0, 0.0, 0.0), name=None):
    """Read ``path`` and add it to ``scene`` as a photometric point light; returns the object.

    Nothing is created when the file cannot be read (RadiometerError with the reader's line).
    TILT data, when present, is applied at the tilt of ``rotation_euler`` (the angle between
    the light's local -Z and the world's -Z) and recorded on the light. ``scene``: a request
    (``measure.blender.request``: its scene and efficacy), a scene or None (the context's).
    """
    from ..blender import request as request_of

    request = request_of.of(scene)
    scene = request.scene
    try:
        photometry = pf.read_photometry(path)
        if photometry.photometric_type != "C":
            raise RadiometerError(f"{path}: type {photometry.photometric_type} photometry (horizontal polar axis) "
                                  "cannot be placed as a light; only type C can")
        location = tuple(float(x) for x in location)
        rotation_euler = tuple(float(x) for x in rotation_euler)
        if len(location) != 3 or len(rotation_euler) != 3 or not all(map(math.isfinite, location + rotation_euler)):
            raise RadiometerError("location and rotation_euler need 3 finite numbers each")
        tilt_factor, tilt_deg = 1.0, None
        if photometry.tilt is not None:
            tilt_deg = _tilt_deg(rotation_euler)
            tilt_factor = photometry.tilt.factor(tilt_deg)
        text_body = pf.to_ies_text(photometry, factor=tilt_factor)
    except pf.PhotometricFileError as exc:
        raise RadiometerError(str(exc)) from None
    except (TypeError, ValueError) as exc:
        raise RadiometerError(f"{path}: {exc}") from None
    label = name or os.path.splitext(os.path.basename(os.fspath(path)))[0] or "Luminaire"
    efficacy = scene_efficacy(request)
    text = bpy.data.texts.new(f"{label}.ies")
    text.from_string(text_body)
    data = bpy.data.lights.new(label, "POINT")
    data.shadow_soft_size = 0.0
    data.energy = pf.CYCLES_IES_EFFICACY / efficacy
    build_node_tree(data, text)
    data[PROP_SOURCE] = os.path.abspath(os.fspath(path))
    data[PROP_LUMENS] = float(photometry.lumens * tilt_factor)
    if tilt_deg is not None:
        data["radiometer_tilt_factor"] = tilt_factor
    obj = bpy.data.objects.new(label, data)
    obj.location, obj.rotation_euler = location, rotation_euler
    scene.collection.objects.link(obj)
    return obj


# --- recognition ---------------------------------------------------------------------------------

def _link_from(socket):
    if not socket.is_linked:
        return None
    links = [link for link in socket.links if link.is_valid and not link.is_muted]
    return links[0].from_node if len(links) == 1 else None


def _active_output(tree):
    outputs = [n for n in tree.nodes if n.bl_idname == "ShaderNodeOutputLight" and not n.mute]
    active = [n for n in outputs if n.is_active_output] or outputs
    if len(active) != 1 or getattr(active[0], "target", "ALL") not in ("ALL", "CYCLES"):
        return None
    return active[0]


def _vector_map(ies):
    """3x3 map applied to the object-space Incoming vector, or None when not a known chain."""
    vector = ies.inputs["Vector"]
    if not vector.is_linked:
        return np.eye(3)
    mapping = _link_from(vector)
    if mapping is None or mapping.bl_idname != "ShaderNodeMapping" or mapping.mute:
        return None
    if mapping.vector_type not in ("VECTOR", "POINT"):
        return None
    for key in ("Rotation", "Scale") + (("Location",) if mapping.vector_type == "POINT" else ()):
        if key in mapping.inputs and mapping.inputs[key].is_linked:
            return None
    if mapping.vector_type == "POINT" and any(abs(x) > 0.0 for x in mapping.inputs["Location"].default_value):
        return None
    transform = _link_from(mapping.inputs["Vector"])
    if (transform is None or transform.bl_idname != "ShaderNodeVectorTransform" or transform.mute
            or (transform.vector_type, transform.convert_from, transform.convert_to) != ("NORMAL", "WORLD", "OBJECT")):
        return None
    geometry = _link_from(transform.inputs["Vector"])
    if geometry is None or geometry.bl_idname != "ShaderNodeNewGeometry" or geometry.mute:
        return None
    if not any(link.from_socket.name == "Incoming" for link in transform.inputs["Vector"].links):
        return None
    from mathutils import Euler

    rotation = np.array(Euler(tuple(mapping.inputs["Rotation"].default_value), "XYZ").to_matrix(), dtype=np.float64)
    return rotation @ np.diag(np.array(mapping.inputs["Scale"].default_value, dtype=np.float64))


def _ies_text(ies):
    if ies.mode == "INTERNAL":
        return ies.ies.as_string() if ies.ies is not None else None
    path = bpy.path.abspath(ies.filepath) if ies.filepath else ""
    try:
        with open(path, encoding="latin-1") as fh:
            return fh.read()
    except OSError:
        return None


@functools.lru_cache(maxsize=32)
def _cycles_table(text):
    """``pf.cycles_ies_table(text)``, parsed once per distinct IES text (every capture reads every IES
    light's text; a scene has a handful of distinct files)."""
    return pf.cycles_ies_table(text)


@functools.lru_cache(maxsize=32)
def _file_opening(path, _stamp):
    """The luminous opening (m, or None) of the photometric file at ``path``; ``_stamp`` (mtime, size)
    keys the cache so an edited file is read again."""
    from ...radiometry.metrics.glare import luminous_opening_m

    return luminous_opening_m(pf.read_photometry(path).metadata)


@functools.lru_cache(maxsize=32)
def _text_opening(text, label):
    from ...radiometry.metrics.glare import luminous_opening_m

    return luminous_opening_m(pf.parse_ies(text, path=label).metadata)


def _luminous_opening(light_data, text):
    """((width, length, height) m or None, whether a file was read): the luminous opening glare rates,
    read once per capture from the file Radiometer imported the light from when it is still there, else
    from the light's IES text (as :func:`photometry_of_light` reads them)."""
    path = light_data.get(PROP_SOURCE) if hasattr(light_data, "get") else None
    try:
        if path and os.path.exists(path):
            st = os.stat(path)
            return _file_opening(path, (st.st_mtime_ns, st.st_size)), True
        return _text_opening(text, f"{getattr(light_data, 'name', 'light')} (IES texture)"), True
    except pf.PhotometricFileError:
        return None, False


def photometric_table(light_data):
    """(the light's ``Photometry`` table, None) for a recognised IES light, (None, reason) otherwise."""
    from ...radiometry.emitters import Photometry

    tree = getattr(light_data, "node_tree", None)
    if not getattr(light_data, "use_nodes", False) or tree is None:
        return None, "has no node tree"
    out = _active_output(tree)
    emission = _link_from(out.inputs["Surface"]) if out is not None else None
    if emission is None or emission.bl_idname != "ShaderNodeEmission" or emission.mute:
        return None, "uses a light node tree (textures or emission nodes)"
    if emission.inputs["Color"].is_linked or ("Weight" in emission.inputs and emission.inputs["Weight"].is_linked):
        return None, "uses a light node tree (textures or emission nodes)"
    ies = _link_from(emission.inputs["Strength"])
    if ies is None or ies.bl_idname != "ShaderNodeTexIES" or ies.mute or ies.inputs["Strength"].is_linked:
        return None, "uses a light node tree (textures or emission nodes)"
    vector_map = _vector_map(ies)
    if vector_map is None:
        return None, "uses an IES texture with a vector Radiometer does not model"
    if light_data.type != "POINT" or float(light_data.shadow_soft_size) != 0.0:
        return None, "uses an IES texture on a light other than a point of radius 0"
    text = _ies_text(ies)
    table = _cycles_table(text) if text else None
    if table is None:
        return None, "uses an IES texture whose file Cycles cannot read as type C"
    h, v, values = table
    colour = np.array(emission.inputs["Color"].default_value[:3], dtype=np.float64)
    scale = colour * float(ies.inputs["Strength"].default_value)   # Emission.Strength is the IES Fac
    source = ies.ies.name if ies.mode == "INTERNAL" and ies.ies is not None else os.path.basename(ies.filepath)
    opening, opening_read = _luminous_opening(light_data, text)
    try:
        return Photometry.light_table(h, v, values / (4.0 * np.pi), vector_map=vector_map, rgb_scale=scale,
                                      label=f"IES table {source!r}", luminous_opening=opening,
                                      opening_read=opening_read), None
    except ValueError as exc:
        return None, f"uses an IES texture Radiometer cannot model ({exc})"


def light_summary(light_data, scene=None):
    """Photometric summary of a light (imported or recognised), or None; for the panel."""
    table, _reason = photometric_table(light_data)
    if table is None:
        return None
    path = light_data.get(PROP_SOURCE)
    summary = {"source": path, "lumens": light_data.get(PROP_LUMENS)}
    if path and os.path.exists(path):
        try:
            summary.update(pf.read_photometry(path).summary())
        except pf.PhotometricFileError:
            pass
    return summary


#: Summaries by source (file path, its mtime and size; or the IES text): the panel draws on every redraw
#: and must not re-read and re-integrate the file each time (issue 17). A handful of luminaires at most.
_SUMMARIES = {}
_SUMMARY_CACHE_SIZE = 32


def _summary_key(obj):
    data = getattr(obj, "data", obj)
    path = data.get(PROP_SOURCE) if hasattr(data, "get") else None
    if path and os.path.exists(path):
        st = os.stat(path)
        return ("file", path, st.st_mtime_ns, st.st_size)
    tree = data.node_tree if getattr(data, "use_nodes", False) else None
    ies = next((n for n in tree.nodes if n.bl_idname == "ShaderNodeTexIES"), None) if tree is not None else None
    return ("text", getattr(obj, "name", ""), _ies_text(ies) if ies is not None else None)


def luminaire_summary(obj):
    """``photometry_of_light(obj).summary()``, kept while the file (or IES text) behind it is unchanged."""
    key = _summary_key(obj)
    summary = _SUMMARIES.get(key)
    if summary is None:
        summary = photometry_of_light(obj).summary()
        if len(_SUMMARIES) >= _SUMMARY_CACHE_SIZE:
            _SUMMARIES.pop(next(iter(_SUMMARIES)))
        _SUMMARIES[key] = summary
    return dict(summary)


def photometry_of_light(obj):
    """The ``Photometry`` behind a light object: its source file when Radiometer imported it and the
    file is still there, else its IES text read with Radiometer's own (LM-63) reader."""
    data = getattr(obj, "data", obj)
    if getattr(data, "type", None) not in ("POINT", "SPOT", "AREA", "SUN"):
        raise RadiometerError(f"{getattr(obj, 'name', obj)!r} is not a light")
    path = data.get(PROP_SOURCE) if hasattr(data, "get") else None
    if path and os.path.exists(path):
        try:
            return pf.read_photometry(path)
        except pf.PhotometricFileError as exc:
            raise RadiometerError(str(exc)) from None
    tree = data.node_tree if getattr(data, "use_nodes", False) else None
    ies = next((n for n in tree.nodes if n.bl_idname == "ShaderNodeTexIES"), None) if tree is not None else None
    text = _ies_text(ies) if ies is not None else None
    if not text:
        raise RadiometerError(f"light {getattr(obj, 'name', '?')!r} has no IES texture with a readable file")
    try:
        return pf.parse_ies(text, path=f"{getattr(obj, 'name', 'light')} (IES texture)")
    except pf.PhotometricFileError as exc:
        raise RadiometerError(str(exc)) from None
