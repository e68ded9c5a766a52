"""Issue 21, finding 8: one error type at the API boundary.

A hypothesis property test throws generated garbage (wrong types, shapes, NaN/inf, huge, empty and
negative values) at one argument of every public ``api`` function at a time, the others valid and
cheap (a point light of radius 0 over a 'Work Plane', analytic method, preview quality), and accepts
only a result or a ``RadiometerError`` with a one-line message. Examples per function are few and
the search is derandomised, so the test is bounded and repeatable; the scene fingerprint is the same
after every refused call. The 49 bad inputs of the issue that escaped as other exceptions are also
listed explicitly.
"""

import inspect
import math

import bpy
import numpy as np
import pytest
from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

from radiometer import api
from radiometer.errors import RadiometerError
from radiometer.measure.blender.scene_guard import scene_fingerprint

GARBAGE = [None, "abc", "", b"x", 5, -1, 0, 1e308, -1e308, math.nan, math.inf, -math.inf, True, 10**30, [], [1, 2],
           [[math.nan] * 3], {}, {"a": 1}, object(), (1, 2, 3, 4), "Scene", np.zeros((2, 2)), np.full(3, np.inf),
           [[0, 0, 1]] * 2, -0.0, 1e-320]

garbage = st.one_of(
    st.sampled_from(GARBAGE),
    st.floats(allow_nan=True, allow_infinity=True).filter(lambda x: not 0.0 < abs(x) < 1e6 or math.isnan(x)),
    st.text(max_size=4).filter(lambda t: t not in ("auto", "hybrid", "render", "analytic", "nodes", "osl",
                                                   "exact", "sh9", "world")),
    st.lists(st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=2)), max_size=5),
    st.integers(min_value=-(10**20), max_value=-1),
)


@pytest.fixture
def scene(clean_blender, build, tmp_path):
    s = bpy.context.scene
    s.render.engine = "CYCLES"
    build.black_world(s)
    build.light(s, "POINT", (0, 0, 2), energy=100.0, shadow_soft_size=0.0)
    build.plane(s, size=1.0, name="Work Plane")
    return s


def base_calls(tmp_path):
    """Valid, cheap keyword sets per function (positional arguments named)."""
    ies = tmp_path / "lamp.ies"
    if tmp_path.is_dir():
        ies.write_text("IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 100\n0 90 180\n0\n100 80 30\n")
    return {
        "measure_illuminance": dict(location=(0, 0, 0.5), normal=(0, 0, 1), method="analytic"),
        "predict_illuminance": dict(location=(0, 0, 0.5), normal=(0, 0, 1)),
        "measure_luminance": dict(location=(0, 0, 0.5), direction=(0, 0, -1), quality="preview"),
        "capture_radiance_map": dict(location=(0, 0, 0.5), path=str(tmp_path / "m.exr"), resolution=4,
                                     quality="preview"),
        "measure_meters": dict(objects=None),
        "check_inverse_square": dict(light="point", method="analytic", distances=[1.0, 2.0]),
        "check_cosine_law": dict(light="point", method="analytic", angles_deg=[0.0, 30.0]),
        "illuminance_grid": dict(target="Work Plane", resolution=(2, 2), method="analytic"),
        "convergence_study": dict(location=(0, 0, 0.5), samples=(4,), replicas=2, targeted=False),
        "export_report": dict(out_dir=str(tmp_path / "report"), quality="preview", method="analytic",
                              convergence=False),
        "assign_brdf": dict(material=None, model="lambert"),
        "read_photometry": dict(path=str(ies)),
        "import_luminaire": dict(path=str(ies)),
        "goniometric_diagram": dict(source=str(ies), path=str(tmp_path / "g.png")),
        "irradiance_environment_map": dict(source="world", path=str(tmp_path / "e.exr"), resolution=(8, 4)),
        "world_illuminance": dict(normal=(0, 0, 1)),
        "calibrate_world": dict(illuminance_lux=100.0),
        "world_model": dict(),
        "mirror_ball_probe": dict(size=8, shape=(4, 8)),
        "spectral_reading": dict(location=(0, 0, 0.5), normal=(0, 0, 1)),
        "spectral_grid": dict(target="Work Plane", resolution=(2, 2)),
        "mesopic_reading": dict(location=(0, 0, 0.5), direction=(0, 0, -1), quality="preview"),
        "spectrum_metrics": dict(spectrum="A"),
        "mesopic_luminance": dict(photopic_cd_m2=1.0, sp_ratio=1.5),
    }


def public_functions():
    return {name: f for name, f in vars(api).items()
            if inspect.isfunction(f) and not name.startswith("_") and f.__module__ == api.__name__}


def test_every_public_api_function_has_the_boundary():
    missing = [name for name, f in public_functions().items() if not getattr(f, "__radiometer_boundary__", False)]
    assert missing == []


def call(name, kwargs):
    return getattr(api, name)(**kwargs)  # every argument by name


def accept(name, kwargs, strict=False):
    try:
        call(name, dict(kwargs))
    except RadiometerError as exc:
        text = str(exc)
        assert text and "\n" not in text.strip(), (name, kwargs, text)
        if strict:  # caught by an argument check, not by the boundary's safety net
            assert "unexpected" not in text, (name, kwargs, text)


def cases(tmp_path):
    out = []
    for name, kwargs in base_calls(tmp_path).items():
        f = getattr(api, name)
        for p, spec in inspect.signature(f).parameters.items():
            if spec.kind in (spec.VAR_KEYWORD, spec.VAR_POSITIONAL):
                continue
            out.append((name, p))
    return out


ALL_PARAMS = cases(__import__("pathlib").Path("/nonexistent"))


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted({n for n, _ in ALL_PARAMS}))
def test_garbage_in_any_argument_gives_a_result_or_one_radiometer_error(scene, tmp_path, monkeypatch, name):
    monkeypatch.chdir(tmp_path)  # a text that is a valid relative file name writes there, not into the repo
    params = [p for n, p in ALL_PARAMS if n == name]
    before = scene_fingerprint(scene)

    # No shrinking: a failure is reported as found (shrinking a slow call took minutes); bounded.
    @settings(max_examples=2 * len(params) + 2, deadline=None, derandomize=True, database=None,
              suppress_health_check=list(HealthCheck), phases=[Phase.explicit, Phase.generate])
    @given(param=st.sampled_from(params), value=garbage)
    def run(param, value):
        kwargs = base_calls(tmp_path)[name]
        if name in ("export_report",) and isinstance(value, str):
            value = "\0" + value  # a text would be a real folder name: a full report, not garbage
        kwargs[param] = value
        accept(name, kwargs)

    run()
    if name not in ("calibrate_world", "import_luminaire", "assign_brdf", "measure_meters"):  # these change the scene
        assert scene_fingerprint(scene) == before


# The bad inputs of the issue that escaped as ValueError, TypeError, IndexError, AttributeError,
# ZeroDivisionError, OverflowError, MemoryError or FileNotFoundError.
ISSUE_CASES = [
    ("measure_illuminance", dict(location="abc")),
    ("measure_illuminance", dict(normal=None)),
    ("measure_illuminance", dict(samples=1e308, method="render")),
    ("measure_illuminance", dict(seed=math.nan)),
    ("measure_illuminance", dict(progress=5, method="render")),
    ("measure_illuminance", dict(scene="Scene")),
    ("measure_illuminance", dict(location=np.zeros((4, 3)), normal=np.ones((3, 3)))),
    ("predict_illuminance", dict(location=[(0, 0, 0.5), (0, 0, 1)])),
    ("convergence_study", dict(replicas=0)),
    ("check_inverse_square", dict(tolerance=math.nan)),
    ("check_inverse_square", dict(plot="/nonexistent/folder/p.png")),
    ("capture_radiance_map", dict(resolution=10**9)),
    ("capture_radiance_map", dict(path="")),
    ("irradiance_environment_map", dict(resolution=(100000, 100000))),
    ("mirror_ball_probe", dict(size=10**9)),
]


@pytest.mark.parametrize("name, change", ISSUE_CASES, ids=[f"{n}-{'-'.join(c)}" for n, c in ISSUE_CASES])
def test_the_issues_bad_inputs_are_radiometer_errors(scene, tmp_path, name, change):
    kwargs = dict(base_calls(tmp_path)[name], **change)
    with pytest.raises(RadiometerError) as info:
        call(name, kwargs)
    assert "\n" not in str(info.value) and "unexpected" not in str(info.value)


def test_meter_exactly_at_a_radius_0_light_is_an_error_or_finite(scene):
    # ZeroDivisionError before: a meter exactly at a point light of radius 0.
    try:
        r = api.measure_illuminance((0, 0, 2), (0, 0, 1), method="analytic")
    except RadiometerError as exc:
        assert "\n" not in str(exc)
    else:
        assert math.isfinite(r.illuminance)


def test_unexpected_errors_below_are_wrapped_with_context(scene, monkeypatch):
    from radiometer.measure.meter import point_meter as meter

    def broken(*args, **kwargs):
        raise ZeroDivisionError("float division by zero")

    monkeypatch.setattr(meter, "predict_illuminance", broken)
    with pytest.raises(RadiometerError, match=r"predict_illuminance: unexpected ZeroDivisionError") as info:
        api.predict_illuminance((0, 0, 0.5))
    assert isinstance(info.value.__cause__, ZeroDivisionError)  # the developer keeps the traceback


def test_a_non_finite_reading_is_an_error(scene):
    # A NaN light power reaches the meter: no NaN reading leaves the API.
    bpy.data.lights["point"].energy = math.nan
    with pytest.raises(RadiometerError) as info:
        api.measure_illuminance((0, 0, 0.5), method="analytic")
    assert "\n" not in str(info.value)
