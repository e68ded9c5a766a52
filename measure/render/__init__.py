"""Rendering for measurement: measurement-grade Cycles settings, sensor bakes and the adaptive, error-targeted render rounds."""
