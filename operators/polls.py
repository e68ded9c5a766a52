"""Operator polls: each condition with the tooltip line that says why an operator is greyed out."""


def needs(cls, ok, message):
    """``ok`` as a bool; where it is false, ``message`` becomes the operator's poll tooltip. Chain with
    ``and`` so a later condition is only evaluated when the earlier ones hold."""
    if not ok:
        cls.poll_message_set(message)
    return bool(ok)


def registered(cls, context, settings="radiometer"):
    """The scene exists and carries Radiometer's ``settings`` property group (the add-on is registered)."""
    return needs(cls, context.scene is not None and hasattr(context.scene, settings),
                 "Radiometer is not registered for this scene")
