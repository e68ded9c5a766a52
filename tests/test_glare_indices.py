"""The glare indices' extension point (issue 30): one mapping, ``api.GLARE_INDICES``, that the CLI's
``glare --index`` offers and dispatches on. Blender-free (no scene is rated here; tests/bpy/test_glare*.py
rate scenes through the same mapping)."""

import argparse

from radiometer import api
from radiometer.commands import glare


def test_every_index_is_an_api_function_with_its_cli_options_and_source_line():
    assert set(api.GLARE_INDICES) == set(glare.INDEX_OPTIONS) == set(glare.SOURCE_LINE) == {"ugr", "dgp"}
    assert api.GLARE_INDICES["ugr"] is api.glare_ugr and api.GLARE_INDICES["dgp"] is api.glare_dgp
    assert all(getattr(f, "__radiometer_boundary__", False) for f in api.GLARE_INDICES.values())


def test_the_cli_offers_exactly_the_mapped_indices():
    parser = argparse.ArgumentParser()
    glare.add_arguments(parser)
    index = next(a for a in parser._actions if a.dest == "index")
    assert tuple(index.choices) == tuple(api.GLARE_INDICES)
    args = parser.parse_args(["--index", "dgp", "--resolution", "48", "--threshold", "1500"])
    assert glare.INDEX_OPTIONS["dgp"](args) == {"resolution": 48, "threshold_cd_m2": 1500.0, "hdr_path": None}
    assert glare.INDEX_OPTIONS["ugr"](args) == {}
