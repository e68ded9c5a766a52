"""The sky models' extension point (issue 30): one mapping, ``SKY_MODELS`` (radiometry/skies/sky_models.py,
re-exported as ``api.SKY_MODELS``), that every sky name goes through: the api's check, the CLI's
``sun-study --sky`` choices, the Radiance export's gensky line. A new entry appears everywhere.
Blender-free (tests/bpy/test_cie_sky_world.py checks the operator's list and the sun study's check)."""

import argparse
import dataclasses

import numpy as np
import pytest

from radiometer import api
from radiometer.commands.daylight import sun_study
from radiometer.errors import RadiometerError
from radiometer.radiometry.skies import cie_sky, radiance_sky, sky_models


def _sun_study_parser():
    parser = argparse.ArgumentParser()
    sun_study.add_arguments(parser)
    return parser, next(a for a in parser._actions if a.dest == "sky")


def test_every_cie_sky_is_one_entry_and_its_names_resolve_to_it():
    assert api.SKY_MODELS is sky_models.SKY_MODELS
    assert tuple(api.SKY_MODELS) == ("overcast",) + tuple(f"cie:{t}" for t in cie_sky.CIE_GENERAL_SKIES)
    for name, model in api.SKY_MODELS.items():
        assert model.name == name and api.sky_model(name) is model and api.sky_model(model.sky_type) is model
        assert model.needs_sun == cie_sky.needs_sun(model.sky_type)
    assert api.sky_model(12) is api.sky_model("12") is api.sky_model("CIE:12") is api.SKY_MODELS["cie:12"]
    assert api.sky_model(np.int64(7)) is api.SKY_MODELS["cie:7"]
    assert len({m.label for m in api.SKY_MODELS.values()}) == len(api.SKY_MODELS)
    for bad in (16, 0, "clear", 12.0, True, None, "cie:16"):
        with pytest.raises(RadiometerError, match="unknown sky type.*overcast, cie:1, cie:2"):
            api.sky_model(bad)


def test_a_model_answers_what_its_formula_module_answers():
    sun = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    model = api.SKY_MODELS["cie:12"]
    normals = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0]])
    np.testing.assert_array_equal(model.sky_integral(normals, sun)[0], cie_sky.sky_integral(normals, 12, sun)[0])
    world = model.world(sun, 2.0, 0.1)
    assert isinstance(world, cie_sky.CIESkyWorld) and world.sky_type == 12 and world.zenith_radiance == 2.0


def test_the_cli_offers_exactly_the_mapped_skies():
    parser, sky = _sun_study_parser()
    assert tuple(sky.choices) == tuple(api.SKY_MODELS)
    base = ["--start", "2026-06-21T12:00", "--end", "2026-06-21T12:00", "--lat", "0", "--lon", "0", "--points", "p.csv"]
    assert parser.parse_args(base + ["--sky", "cie:12", "--sky-lux", "20000"]).sky == "cie:12"
    with pytest.raises(SystemExit):
        parser.parse_args(base + ["--sky", "clear"])


def test_a_new_entry_appears_in_the_cli_the_api_and_the_radiance_export(monkeypatch):
    uniform = dataclasses.replace(api.SKY_MODELS["cie:5"], name="test:uniform", label="test uniform sky",
                                  gensky_flag="-u")
    monkeypatch.setitem(sky_models.SKY_MODELS, "test:uniform", uniform)
    _parser, sky = _sun_study_parser()
    assert "test:uniform" in sky.choices
    assert api.sky_model("test:uniform") is uniform
    with pytest.raises(RadiometerError, match="test:uniform"):
        api.sky_model("nothing")
    assert " -u " in radiance_sky.gensky_command("test:uniform", None, 10_000.0, 0.2)
