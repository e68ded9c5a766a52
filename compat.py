"""Differences between Blender 4.5 LTS and 5.x that Radiometer papers over (no bpy import needed)."""


def ensure_node_tree(idblock):
    """The node tree of a material or world, creating it on Blender 4.x.

    Blender 4.5 creates materials and worlds without a node tree until ``use_nodes`` is set; Blender 5
    always gives them one and deprecates ``use_nodes`` (reading or writing it warns), so the flag is
    only touched when the tree is missing.

    Parameters
    ----------
    idblock : bpy.types.Material or bpy.types.World
        Data-block whose shader node tree is wanted.

    Returns
    -------
    bpy.types.ShaderNodeTree
        ``idblock.node_tree`` (on 4.x the default tree: Principled BSDF + Material Output, or
        Background + World Output).

    References
    ----------
    Blender 5.0 release notes, Python API changes (``Material.use_nodes`` and ``World.use_nodes``
    deprecated): https://developer.blender.org/docs/release_notes/5.0/python_api/
    """
    if idblock.node_tree is None:
        idblock.use_nodes = True
    return idblock.node_tree


def active_node_tree(idblock):
    """The node tree Cycles renders a material or world with, or None when it renders without nodes.

    On Blender 4.x a data-block with ``use_nodes`` off is rendered from its plain colour (a world
    from ``World.color``, a material from ``Material.diffuse_color``) even if it keeps a node tree;
    Blender 5 always renders the tree, and ``use_nodes`` is not read there (it warns).

    Parameters
    ----------
    idblock : bpy.types.Material or bpy.types.World
        Data-block to inspect (not modified).

    Returns
    -------
    bpy.types.ShaderNodeTree or None

    References
    ----------
    Cycles' Blender sync, ``intern/cycles/blender/shader.cpp`` (``sync_world``/``sync_materials``:
    the node tree is used only when ``use_nodes`` is set, otherwise a Background or Diffuse shader
    of the data-block's colour).
    """
    import bpy

    tree = idblock.node_tree
    if tree is None or bpy.app.version >= (5, 0, 0):
        return tree
    return tree if idblock.use_nodes else None


def working_colour_space():
    """The blend file's scene-linear working colour space: the one place Radiometer reads it (RGB
    to CIE Y weights come from it, ``radiometry.photometry.efficacy.luminance_weights``). Blender 4.5 has no
    choice (``bpy.data.colorspace`` is new in 5.0): Linear Rec.709."""
    import bpy

    return bpy.data.colorspace.working_space if hasattr(bpy.data, "colorspace") else "Linear Rec.709"
