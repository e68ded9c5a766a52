"""Photometry: luminous efficacy and photometric <-> Blender power (efficacy), photometric files (IES, EULUMDAT), colorimetry and the CIE tables."""
