"""The API prints nothing to stdout: Blender's "Info: Baking map saved to internal image..." report,
printed by bpy.ops for every bake, is kept off stdout (checked at the file descriptor, fd 1).

Cycles' one-time device probe at its first use in a process (a CUEW warning on machines without
CUDA, written by C code) is not the API's: the first measurement is made before the capture."""

import bpy

from radiometer import api

from .conftest import add_light, add_plane, make_black_world


def test_rendered_measurements_print_nothing_to_stdout(clean_blender, capfd):
    scene = bpy.context.scene
    make_black_world(scene)
    add_light(scene, "POINT", (0.0, 0.0, 2.0), energy=100.0, shadow_soft_size=0.1)
    add_plane(scene, size=4.0, location=(0.0, 0.0, 2.5), rotation=(3.14159265, 0.0, 0.0))  # a ceiling reflects
    api.measure_illuminance((0, 0, 0), (0, 0, 1), method="render", samples=8)  # Cycles' first use
    capfd.readouterr()
    r = api.measure_illuminance([(0, 0, 0), (0.5, 0, 0)], [(0, 0, 1), (0, 0, 1)], method="render",
                                quality="preview")
    out, _err = capfd.readouterr()
    assert all(x.samples > 0 for x in r), "the test needs a real bake"
    assert out == "", out
