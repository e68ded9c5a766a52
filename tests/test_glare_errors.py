"""Glare's background E_ind = E_vertical - E_direct (issue 32): its own target, its error from both
readings, and "error unknown" with the cause, never ±inf / ±nan. Stub readings stand in for the meter."""

import json
import math
from types import SimpleNamespace

import numpy as np
import pytest

from radiometer.measure.analyses import glare
from radiometer.measure.blender.request import Request


def _request(quality):
    """A request as the api hands it down (no scene: the stub meter reads none)."""
    return Request(scene=None, view_layer=None, scale_length=1.0, colour_space="Linear Rec.709",
                   luminance_weights=(0.2126, 0.7152, 0.0722), efficacy=683.0, quality=quality)


class StubMeter:
    """measure_illuminance returning given (E lx, rel s.e., exact, notes) per (direct_only, seed); with
    ``parts`` (the meter's one run for both, issue 30) one reading per part, each part recorded as a call
    (total, then direct) with its own target."""

    def __init__(self, table):
        self.table, self.calls = table, []

    def measure_illuminance(self, _location, _normal, request, *, direct_only=False, parts=None, **_k):
        seed, target_rel_error = request.seed, request.target_rel_error
        if parts is not None:
            targets = target_rel_error if isinstance(target_rel_error, dict) else {}
            return {part: self.measure_illuminance(None, None, request.but(target_rel_error=targets.get(part)),
                                                   direct_only=part == "direct") for part in parts}
        self.calls.append((direct_only, seed, target_rel_error))
        e, rel, exact, notes = self.table[(direct_only, seed)]
        return SimpleNamespace(illuminance=e, rel_std_error=rel, exact=exact, notes=notes)


DARK = ("1 meter(s) found no rendered light in 65,536+ samples although lit surfaces or partly hidden lights lie "
        "above their horizon: light from a small bright region may be missing, so their error is unknown")


def test_unknown_direct_error_is_carried_with_its_cause():
    meter = StubMeter({(False, 0): (500.0, 0.01, False, []), (True, 0): (300.0, math.inf, False, [DARK])})
    b = glare._background((0, 0, 1.2), (0, 1, 0), _request("standard"), meter)
    assert math.isnan(b["rel"]) and "direct-only reading" in b["unknown"] and "no rendered light" in b["unknown"]
    assert len(meter.calls) == 2  # no second round: an unknown error is not a target to chase


def test_background_gets_its_own_target_from_both_readings():
    """E_v 1000 lx at 1 %, E_d 820 lx at 1 % (82 % direct, the issue's case): E_ind 180 lx at 7.9 %. The
    variance (1 % x 180 lx)² is split in proportion to the pilot errors (10 lx and 8.2 lx); the kept readings
    are the second, independent ones (seed 1)."""
    meter = StubMeter({(False, 0): (1000.0, 0.01, False, []), (True, 0): (820.0, 0.01, False, []),
                       (False, 1): (1001.0, 0.00109, False, []), (True, 1): (821.0, 0.00109, False, [])})
    b = glare._background((0, 0, 1.2), (0, 1, 0), _request("standard"), meter)
    share = 0.01 * 180.0 / math.hypot(10.0, 8.2)
    assert meter.calls[2] == (False, 1, pytest.approx(share * 10.0 / 1000.0))
    assert meter.calls[3] == (True, 1, pytest.approx(share * 8.2 / 820.0))
    assert b["e_ind"] == pytest.approx(180.0)
    assert b["rel"] == pytest.approx(math.hypot(1001 * 0.00109, 821 * 0.00109) / 180.0)
    assert b["rel"] < 0.011 and b["target"] == 0.01


def test_exact_direct_part_leaves_the_whole_budget_to_the_render():
    meter = StubMeter({(False, 0): (1000.0, 0.01, False, []), (True, 0): (820.0, 0.0, True, []),
                       (False, 1): (1000.0, 0.0018, False, []), (True, 1): (820.0, 0.0, True, [])})
    glare._background((0, 0, 1.2), (0, 1, 0), _request("standard"), meter)
    assert meter.calls[2][2] == pytest.approx(0.01 * 180.0 / 1000.0) and meter.calls[3][2] is None


def test_rendered_background_never_states_zero():
    meter = StubMeter({(False, 0): (500.0, 0.0, False, []), (True, 0): (300.0, 0.0, True, [])})
    b = glare._background((0, 0, 1.2), (0, 1, 0), _request("preview"), meter)
    assert math.isnan(b["rel"]) and "standard error of 0" in b["unknown"]


def test_result_words_never_print_inf_or_nan():
    g = glare.GlareResult(ugr=4.8, ugr_std_error=math.nan, background_luminance=48.007, indirect_illuminance=150.8,
                          total_illuminance=900.0, background_rel_std_error=math.nan, sources=[], left_out=[],
                          observer=(0, 0, 1.2), view_direction=(0, 1, 0), notes=[],
                          error_unknown="the direct-only reading: found no rendered light")
    text = g.summary()
    assert "error unknown (the direct-only reading" in text and "(error unknown)" in text
    assert "inf" not in text.replace("information", "") and "nan" not in text
    d = json.loads(json.dumps(g.to_dict()))
    assert d["ugr_std_error"] is None and d["background_rel_std_error"] is None and d["error_unknown"]
    known = glare.GlareResult(ugr=18.23, ugr_std_error=0.034, background_luminance=139.0, indirect_illuminance=436.7,
                              total_illuminance=2000.0, background_rel_std_error=0.0098, sources=[], left_out=[],
                              observer=(0, 0, 1.2), view_direction=(0, 1, 0), notes=[])
    assert "UGR 18.2 ±0.034" in known.summary()


def test_dark_reading_with_unknown_error_stays_unknown():
    """An eye outside a dark room: both readings 0 lx, the total one with an unknown error: unknown, said so."""
    meter = StubMeter({(False, 0): (0.0, math.inf, False, [DARK]), (True, 0): (0.0, 0.0, True, [])})
    b = glare._background((0, 0, 1.2), (0, 1, 0), _request("preview"), meter)
    assert math.isnan(b["rel"]) and "vertical illuminance reading" in b["unknown"]


def test_ies_opening_outline_follows_the_luminaire_axes():
    """LM-63 / EULUMDAT: length along C0-C180 (local X), width along C90-C270 (local Y); a circle (negative
    width) as a circumscribed polygon of its diameter."""
    axes = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # local X = world Y, local Y = -world X
    spec = SimpleNamespace(axes=axes, position=np.array([1.0, 2.0, 3.0]))
    outline = glare._opening_outline(spec, (0.2, 1.2, 0.0))  # width 0.2 m, length 1.2 m
    span = outline.max(axis=0) - outline.min(axis=0)
    assert span == pytest.approx([0.2, 1.2, 0.0])
    assert outline.mean(axis=0) == pytest.approx([1.0, 2.0, 3.0])
    disk = glare._opening_outline(spec, (-0.5, -0.5, 0.0))
    r = np.linalg.norm(disk - [1.0, 2.0, 3.0], axis=1)
    assert np.all(r >= 0.25) and np.all(r <= 0.25 / math.cos(math.pi / glare.OUTLINE_SIDES) + 1e-12)
    assert np.ptp(disk[:, 2]) == 0.0
