"""The api's boundary (validation.boundary): a call whose arguments do not fit the function's signature is the
caller's mistake, said in one line as RadiometerError naming the argument, not an "unexpected ... please report"
bug line; a TypeError raised below the call is still reported as unexpected (it is a bug)."""

import pytest

from radiometer import validation
from radiometer.errors import RadiometerError


@validation.boundary
def _measure(points, *, quality="standard"):
    if points == "bug":
        return len(3)  # a TypeError inside: a bug, not the caller's arguments
    return points


def test_a_wrong_keyword_is_the_callers_mistake():
    with pytest.raises(RadiometerError) as err:
        _measure([1], samples=512)
    text = str(err.value)
    assert "unexpected keyword argument 'samples'" in text and "please report" not in text
    assert "\n" not in text


def test_a_missing_argument_is_the_callers_mistake():
    with pytest.raises(RadiometerError, match="missing 1 required positional argument: 'points'") as err:
        _measure()
    assert "please report" not in str(err.value)


def test_a_type_error_below_the_call_is_still_a_bug():
    with pytest.raises(RadiometerError, match="unexpected TypeError.*please report"):
        _measure("bug")


def test_the_api_says_it_too():
    from radiometer import api

    with pytest.raises(RadiometerError, match="unexpected keyword argument 'samples'"):
        api.daylight_factor_grid(None, samples=512)
