"""The meter: illuminance and luminance at points (point_meter), meter objects in the scene and their stored readings, camera readings, sample floors and the live meter."""
