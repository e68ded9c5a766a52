"""Where a subcommand measures: points from a CSV file (``--points``) or the grid on a plane object
(``--plane`` with ``--spacing`` or ``--resolution``, laid out like every grid); with neither, the
scene's first work plane (a mesh named "Work Plane", as ``grid`` and ``report`` find it). Shared by
``sun-study``, ``daylight-factor`` and ``annual``, with the outputs they all take (``add_study_outputs``)."""


def add_arguments(parser):
    """``--points CSV`` | ``--plane NAME`` (default: the first work plane), and ``--spacing M`` |
    ``--resolution NX NY``."""
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--points", metavar="CSV", help="points as CSV rows x,y,z[,nx,ny,nz] (scene units; a "
                       "header line is skipped; normal default +Z)")
    where.add_argument("--plane", metavar="NAME", help="a grid over this plane object's local XY (its +Z side); "
                       "default with neither: the scene's first work plane (a mesh named 'Work Plane')")
    size = parser.add_mutually_exclusive_group()
    size.add_argument("--spacing", type=float, metavar="M", help="with --plane: cell size in m (default EN 12464-1)")
    size.add_argument("--resolution", type=int, nargs=2, metavar=("NX", "NY"), help="with --plane: points along x, y")


def add_study_outputs(parser, *, csv_help, png_help, quality_default="standard", quality_help=None):
    """What every daylight study takes after its own options: ``--quality``, ``--csv FILE``, ``--png FILE``
    and the cluster's ``--workers`` / ``--scheduler`` (``_cluster``)."""
    from . import _cluster

    parser.add_argument("--quality", choices=("preview", "standard", "reference"), default=quality_default,
                        help=quality_help)
    parser.add_argument("--csv", metavar="FILE", help=csv_help)
    parser.add_argument("--png", metavar="FILE", help=png_help)
    _cluster.add_arguments(parser)


def from_args(args, scene):
    """(locations (N, 3), normals (N, 3)) that ``--points`` or ``--plane`` name; one-line errors."""
    from ..errors import RadiometerError

    default_plane(args, scene)
    if args.points:
        if args.spacing is not None or args.resolution is not None:
            raise RadiometerError("--spacing/--resolution go with --plane, not --points")
        return read_points(args.points)
    return plane_points(scene, args.plane, args.spacing, args.resolution)


def default_plane(args, scene):
    """Neither ``--points`` nor ``--plane``: set ``args.plane`` to the scene's first work plane, or say
    in one line that there is none (before any work)."""
    if args.points or args.plane:
        return
    args.plane = plane_object(scene, None, instead="--plane NAME (a plane object) or --points CSV").name


def plane_object(scene, name, *, instead="--plane NAME"):
    """The object ``name`` (``--plane``) or, without a name, the scene's first work plane (``api.work_planes``);
    one-line errors that say what to give ``instead``."""
    from .. import api
    from ..errors import RadiometerError

    if name:
        ob = scene.objects.get(name)
        if ob is None:
            raise RadiometerError(f"no object named {name!r} in scene {scene.name!r}")
        return ob
    planes = api.work_planes(scene)
    if not planes:
        raise RadiometerError(f"no work plane in scene {scene.name!r}: give {instead}, or add a mesh named "
                              "'Work Plane'")
    return planes[0]


def read_points(path):
    """(locations (N, 3), normals (N, 3)) from a CSV file; RadiometerError naming the line otherwise."""
    import numpy as np

    from ..errors import RadiometerError

    try:
        with open(path, encoding="utf-8") as f:
            lines = f.read().splitlines()
    except (OSError, UnicodeDecodeError) as exc:
        raise RadiometerError(f"cannot read --points {path}: {getattr(exc, 'strerror', None) or exc}") from None
    rows = []
    for number, line in enumerate(lines, start=1):
        cells = [c.strip() for c in line.split(",")]
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        try:
            values = [float(c) for c in cells]
        except ValueError:
            if not rows and number == 1:
                continue  # a header
            raise RadiometerError(f"{path} line {number}: expected numbers x,y,z[,nx,ny,nz], got {line!r}") from None
        if len(values) not in (3, 6) or not all(np.isfinite(values)):
            raise RadiometerError(f"{path} line {number}: expected 3 or 6 finite numbers, got {line!r}")
        rows.append(values if len(values) == 6 else values + [0.0, 0.0, 1.0])
    if not rows:
        raise RadiometerError(f"{path}: no points")
    a = np.array(rows)
    return a[:, :3], a[:, 3:]


def plane_points(scene, name, spacing=None, resolution=None):
    """Cell centres (N, 3) and normals (N, 3) of the grid on a plane object, laid out as every grid is
    (``measure.analyses.grid.grid_layout``: EN 12464-1 spacing by default, at most 250 000 points)."""
    from .. import api

    return api.grid_points(name, scene=scene, resolution=resolution, spacing=spacing)
