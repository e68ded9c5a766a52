"""The scene's luminous efficacy K (lm/W) as the api hands it down (issue 30: host code takes settings as
arguments; measure/ reads no UI property group).

The api (``radiometer.api``, the one place beside the operators and panels that reads the add-on's
settings) installs at import the function that reads a scene's efficacy setting (:func:`install`);
measure/ asks :func:`of` and never touches a property group. A reader rather than one value per call,
because measurements run on scenes the api call never saw: Radiometer's temporary render scenes
(:func:`follow`: they read as the user's scene), the files a batch opens and the copies a cluster worker
opens (the worker registers the add-on, which imports the api). Without a reader (the api not imported,
e.g. pure-measure tests) every scene reads None: the caller's default, 683 lm/W.
"""

import contextlib

_READER = [None]
_FOLLOWS = {}  # temporary scene (as_pointer) -> the scene whose efficacy it reads


def install(reader):
    """``reader(scene) -> K lm/W or None``: how the api reads a scene's efficacy setting."""
    _READER[0] = reader


def of(scene):
    """K (lm/W) of ``scene`` as the api reads it, or None (no reader, or the scene has no setting)."""
    seen = set()
    while scene is not None and scene.as_pointer() in _FOLLOWS and scene.as_pointer() not in seen:
        seen.add(scene.as_pointer())
        scene = _FOLLOWS[scene.as_pointer()]
    reader = _READER[0]
    return None if reader is None or scene is None else reader(scene)


@contextlib.contextmanager
def follow(scene, like):
    """While open, ``scene`` (a temporary render scene) reads ``like``'s efficacy: readings in it mean what
    they mean in the user's scene."""
    key = scene.as_pointer()
    _FOLLOWS[key] = like
    try:
        yield
    finally:
        _FOLLOWS.pop(key, None)
