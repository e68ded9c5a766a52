"""readings.batch_method: a batch whose meters were read by different methods says so."""

from types import SimpleNamespace

from radiometer.readings import batch_method


def test_one_method_is_named_and_a_mix_is_counted():
    r = [SimpleNamespace(method=m) for m in ("analytic", "hybrid", "analytic", "analytic")]
    assert batch_method(r[:1]) == "analytic"
    assert batch_method([r[0], r[2]]) == "analytic"
    assert batch_method(r) == "mixed: analytic 3, hybrid 1"
