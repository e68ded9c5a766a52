"""The scene's luminous efficacy K (lm/W), as its Radiometer settings say: the one place in measure/ that
reads a property group (issue 30: host code takes settings as arguments), until the request built once at
the api carries the efficacy down (``tests/test_import_contract.py`` lists it, dated)."""


def efficacy_setting(scene):
    """K (lm/W) of ``scene``'s Radiometer settings, or None where the add-on's properties are not registered."""
    settings = getattr(scene, "radiometer", None)
    return None if settings is None else float(getattr(settings, "efficacy", 0.0) or 0.0)


def copy_efficacy(source, target):
    """Give scene ``target`` the efficacy settings of scene ``source`` (both registered), so that readings
    in a temporary scene mean what they mean in the user's."""
    src, dst = getattr(source, "radiometer", None), getattr(target, "radiometer", None)
    if src is not None and dst is not None:
        dst.efficacy_convention = src.efficacy_convention
        dst.efficacy = src.efficacy
