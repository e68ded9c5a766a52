"""`export-radiance`: the scene as a Radiance scene (geometry, sky, sensor grids, views, README)."""

HELP = ("write the scene for Radiance into OUT: scene.rad, sky.rad (+ gensky line), sky_overcast.rad, .pts per "
        "work plane and meters, .vf per camera, README.txt of what was not mappable")
NEEDS_SCENE = True


def add_arguments(parser):
    parser.add_argument("out", metavar="OUT", help="output folder (created if missing)")
    parser.add_argument("--resolution", type=int, nargs=2, metavar=("NX", "NY"),
                        help="work-plane grid points (default: EN 12464-1 spacing)")
    parser.add_argument("--spacing", type=float, metavar="M", help="work-plane grid spacing in metres")
    parser.add_argument("--ground-reflectance", type=float, default=0.2, metavar="RHO",
                        help="ground reflectance of the daylight factor's overcast sky (default 0.2)")


def run(args):
    import bpy

    from .. import api
    from . import _io

    _io.check_output_dir(args.out, "OUT folder")
    result = api.export_radiance(args.out, scene=bpy.context.scene, resolution=args.resolution,
                                 spacing=args.spacing, ground_reflectance=args.ground_reflectance)
    s = result["summary"]
    print(f"Radiance export: {s.get('triangles', 0)} triangles, {s.get('materials', 0)} materials, "
          f"{s.get('panes', 0)} panes, sky: {s.get('sky')}, {len(s.get('grids', []))} grids, "
          f"{len(s.get('meters', []))} meters, {len(s.get('views', []))} views")
    for line in result["unmapped"]:
        print(f"  not mapped: {line}")
    print(f"Wrote {len(result['files'])} files into {result['out_dir']} (README.txt says how to run them)")
    return result
