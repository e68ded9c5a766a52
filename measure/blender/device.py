"""Which device a measurement renders on: the user's GPU where Cycles can use it, else the CPU.

Cycles bakes and renders on every GPU back-end (CUDA, OptiX, HIP, Metal, oneAPI); measurements used
to force ``cycles.device = "CPU"``. Now a measurement uses what the user configured in Blender's
preferences (*Preferences > System > Cycles Render Devices*: ``compute_device_type`` and the devices
ticked there), when the scene allows it:

* no back-end chosen (``NONE``, the factory setting), or none of its devices ticked: the CPU, as the
  user's own renders would (no note: that is the user's configuration);
* the scene uses Open Shading Language (``scene.cycles.shading_system``): OSL runs on the CPU and,
  since Blender 3.5, on OptiX only; any other GPU back-end falls back to the CPU, and the note says so;
* the render looks through the meter camera (``measure.analyses.daylight_coefficients``: the annual
  dome, the daylight factor rendered whole): an OSL custom camera, which Cycles supports only where OSL
  runs, the CPU and OptiX (the commit that added custom cameras, Blender pull request 129495), whatever
  the scene's shading system; the same fall-back and note.

Readings on a GPU agree with the CPU's within their stated errors (``tests/bpy/test_device.py``
checks it where a GPU exists; GPU and CPU kernels take different random sequences, so the numbers
differ by noise, not bias). The choice is pure data (:func:`choose`); :func:`measurement_device`
reads Blender's preferences for it.
"""

#: Back-ends that run Cycles' OSL shaders besides the CPU (Blender 3.5+).
OSL_BACKENDS = frozenset({"OPTIX"})


def choose(backend, enabled_gpu_devices, uses_osl, custom_camera=False):
    """(device "CPU" | "GPU", label, note or None) for a measurement.

    Parameters
    ----------
    backend : str
        ``compute_device_type`` from the Cycles preferences ("NONE", "CUDA", "OPTIX", "HIP", "METAL",
        "ONEAPI").
    enabled_gpu_devices : sequence of str
        Names of the ticked devices of that back-end (CPU entries left out).
    uses_osl : bool
        The scene renders with Open Shading Language.
    custom_camera : bool
        The render looks through an OSL custom camera (the meter camera).
    """
    if not backend or backend == "NONE":
        return "CPU", "CPU", None
    if not enabled_gpu_devices:
        return "CPU", "CPU", None
    if custom_camera and backend not in OSL_BACKENDS:
        return "CPU", "CPU", (f"rendered on the CPU: the meter camera is an OSL custom camera, which {backend} "
                              f"cannot run (custom cameras run on the CPU or OptiX)")
    if uses_osl and backend not in OSL_BACKENDS:
        return "CPU", "CPU", (f"rendered on the CPU: the scene uses OSL, which {backend} cannot run "
                              f"(OSL runs on the CPU or OptiX)")
    return "GPU", f"GPU {backend}: {', '.join(enabled_gpu_devices)}", None


def _cycles_preferences():
    import bpy

    addon = bpy.context.preferences.addons.get("cycles")
    return addon.preferences if addon is not None else None


def measurement_device(scene, custom_camera=False):
    """(device "CPU" | "GPU", label, note or None) for measuring ``scene`` (see the module docstring);
    ``custom_camera``: the render looks through the meter camera."""
    prefs = _cycles_preferences()
    backend = getattr(prefs, "compute_device_type", "NONE") if prefs is not None else "NONE"
    enabled = []
    if backend and backend != "NONE":
        try:
            devices = prefs.get_devices_for_type(backend)
        except (AttributeError, RuntimeError, TypeError, ValueError):
            devices = []
        enabled = [d.name for d in devices if getattr(d, "use", False) and getattr(d, "type", "CPU") != "CPU"]
    uses_osl = bool(getattr(getattr(scene, "cycles", None), "shading_system", False))
    return choose(backend, enabled, uses_osl, custom_camera)
