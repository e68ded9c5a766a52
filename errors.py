"""Errors with messages meant for users (one line, says what is wrong and what to do)."""


class RadiometerError(Exception):
    """Bad input or an impossible request; the message is shown to the user as is."""


class MeasurementCancelled(RadiometerError):
    """The user cancelled a measurement (Esc); the scene has been restored."""
