"""Plots are written as whole PNG files, and the sphere image follows its stated radiometric rule.

No wall-time assertions here (a loaded machine made them fail): plot timing belongs in `make bench`."""

import math

import numpy as np
import pytest

import radiometer.brdf as brdf
from radiometer.brdf import plots


@pytest.mark.parametrize("name,params", [("ggx", {"alpha": 0.2}), ("ward", {}), ("oren_nayar", {}), ("mirror", {})])
def test_plots_written(tmp_path, name, params):
    for fn in (plots.plot_lobes, plots.plot_albedo, plots.plot_sphere, plots.plot_summary):
        out = fn(name, tmp_path / f"{name}_{fn.__name__}.png", **params)
        with open(out, "rb") as fh:
            data = fh.read()
        assert data[:8] == b"\x89PNG\r\n\x1a\n"
        assert data.rstrip(b"\0").endswith(b"IEND\xaeB`\x82")  # whole file, not truncated


def test_sphere_lambert_matches_cosine_law():
    # Lambert sphere lit from the camera: L = ρ/π · cos θi · E, independent of the view (lecture: M = ρ E cos θs).
    img = plots.sphere_image("lambert", light_dir=(0, 0, 1), resolution=40, albedo=0.5)
    r = (np.arange(40) + 0.5) / 40 * 2 - 1
    x, y = np.meshgrid(r, -r)
    cos_t = np.sqrt(np.clip(1 - x * x - y * y, 0, 1))
    inside = x * x + y * y < 1
    np.testing.assert_allclose(img[inside][:, 0], 0.5 / math.pi * cos_t[inside], rtol=1e-9)
    assert np.all(np.isnan(img[~inside]))
