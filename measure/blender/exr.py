"""Read 32-bit EXR files written by Cycles: OpenEXR when installed, else Blender's OpenImageIO."""

import os
import sys

import numpy as np

from ...errors import RadiometerError


def _oiio():
    try:
        import OpenImageIO

        return OpenImageIO
    except ImportError:
        import bpy

        # Inside the bpy wheel OIIO ships in Blender's own site-packages, which is not on sys.path.
        site = os.path.join(bpy.utils.resource_path("LOCAL"), "python", "lib",
                            f"python{sys.version_info.major}.{sys.version_info.minor}", "site-packages")
        if site not in sys.path and os.path.isdir(site):
            sys.path.append(site)
        import OpenImageIO

        return OpenImageIO


def _with_openexr(path, read):
    """``read(OpenEXR)`` where OpenEXR is installed, else None (the caller reads with OpenImageIO); a broken file
    is one RadiometerError."""
    try:
        import OpenEXR
    except ImportError:
        return None
    try:
        return read(OpenEXR)
    except Exception as exc:  # OpenEXR raises RuntimeError/KeyError for broken files
        raise RadiometerError(f"cannot read EXR {path}: {exc}") from None


def read_rgb(path):
    """(H, W, 3) float64 array, top row first. Clear error for missing or corrupt files."""
    if not os.path.isfile(path):
        raise RadiometerError(f"render output missing: {path}")

    def read(openexr):
        with openexr.File(path) as f:
            channels = f.channels()
            if "RGBA" in channels:
                return np.array(channels["RGBA"].pixels, dtype=np.float64)[..., :3]
            if "RGB" in channels:
                return np.array(channels["RGB"].pixels, dtype=np.float64)
            return np.stack([np.array(channels[c].pixels, dtype=np.float64) for c in ("R", "G", "B")], axis=-1)

    px = _with_openexr(path, read)
    if px is not None:
        return px
    oiio = _oiio()
    buf = oiio.ImageBuf(path)
    if buf.has_error:
        raise RadiometerError(f"cannot read EXR {path}: {buf.geterror()}")
    return np.asarray(buf.get_pixels(oiio.FLOAT), dtype=np.float64)[..., :3]


def read_parts(path, select):
    """{key: {channel letter: (H, W) float32 array, top row first}} of the parts of a multi-part EXR (a
    multilayer render: parts "<view layer>.<pass>", channels "<part>.R" ...) for which ``select(part name)``
    returns a key (None: skipped). OpenEXR when installed, else Blender's OpenImageIO (all the extension
    has inside Blender). Clear error for missing or corrupt files."""
    if not os.path.isfile(path):
        raise RadiometerError(f"render output missing: {path}")
    def read(openexr):
        with openexr.File(path, separate_channels=True) as f:
            return {key: {name.rpartition(".")[2]: np.asarray(ch.pixels) for name, ch in part.channels.items()}
                    for part, key in ((part, select(part.name())) for part in f.parts) if key is not None}

    out = _with_openexr(path, read)
    if out is not None:
        return out
    out = {}
    oiio = _oiio()
    inp = oiio.ImageInput.open(path)
    if inp is None:
        raise RadiometerError(f"cannot read EXR {path}: {oiio.geterror()}")
    try:
        sub = 0
        while inp.seek_subimage(sub, 0):
            spec = inp.spec()
            key = select(str(spec.getattribute("name") or ""))
            if key is not None:
                px = inp.read_image(oiio.FLOAT)
                if px is None:
                    raise RadiometerError(f"cannot read EXR {path}: {inp.geterror()}")
                px = np.asarray(px).reshape(spec.height, spec.width, spec.nchannels)
                out[key] = {name.rpartition(".")[2]: px[..., i] for i, name in enumerate(spec.channelnames)}
            sub += 1
    finally:
        inp.close()
    return out
