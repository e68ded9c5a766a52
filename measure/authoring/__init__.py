"""Things Radiometer writes into the user's scene on request: CIE sky worlds, the sun at a place and time, lights' photometric power and world calibration."""
