"""EN 12464-1 compliance table (pure): values, maintenance factor, margins, marginal results."""

import math

import pytest

from radiometer.radiometry.metrics import compliance


def test_task_table_values_and_sources():
    office = compliance.TASKS["office_writing"]
    assert (office.maintained_lx, office.uniformity, office.ugr_limit, office.ra) == (500, 0.60, 19, 80)
    assert all(t.source.startswith("EN 12464-1") for t in compliance.TASKS.values())
    with pytest.raises(ValueError):
        compliance.requirement("spaceship")
    own = compliance.requirement(maintained_lx=400, uniformity=0.5)
    assert own.source == "user-given" and own.ugr_limit is None


def test_assess_pass_fail_and_margins():
    req = compliance.TASKS["office_writing"]
    rows = compliance.assess(req, average_lx=700.0, minimum_lx=450.0, maintenance_factor=0.8, average_rel_se=0.002,
                             minimum_rel_se=0.01, ugr=[("desk", 17.2, 0.05), ("door", 19.6, 0.05)], ra=None)
    by = {r.quantity: r for r in rows}
    assert by["Ēm"].achieved == pytest.approx(560.0) and by["Ēm"].margin == pytest.approx(60.0)
    assert by["Ēm"].status == "pass"
    assert by["U0"].achieved == pytest.approx(450 / 700) and by["U0"].status == "pass"
    assert by["UGR (desk)"].status == "pass" and by["UGR (desk)"].margin == pytest.approx(1.8)
    assert by["UGR (door)"].status == "fail" and by["UGR (door)"].margin == pytest.approx(-0.6)
    assert by["Ra"].status == "not assessed"
    assert compliance.overall(rows) == "fail"


def test_marginal_when_within_two_standard_errors():
    req = compliance.requirement(maintained_lx=500)
    rows = compliance.assess(req, average_lx=630.0, minimum_lx=400.0, maintenance_factor=0.8, average_rel_se=0.01)
    assert rows[0].achieved == pytest.approx(504.0) and rows[0].status == "marginal"  # 4 lx < 2 x 5.04 lx
    assert compliance.overall(rows) == "marginal"
    with pytest.raises(ValueError):
        compliance.assess(req, average_lx=1, minimum_lx=1, maintenance_factor=1.5)
    rows = compliance.assess(compliance.TASKS["corridor"], average_lx=200, minimum_lx=100, maintenance_factor=1.0,
                             ugr=[("x", -math.inf, math.nan)], ra=82)
    assert compliance.overall(rows) == "pass"


def test_quoted_rows_are_marked_indicative_and_user_rows_are_not():
    """The standard's text could not be checked: every quoted row says so; the user's own values do not."""
    assert all(t.indicative for t in compliance.TASKS.values())
    assert not compliance.requirement(maintained_lx=400).indicative
    assert compliance.TASKS["office_writing"].source == "EN 12464-1:2011 Table 5.26, ref. 5.26.2"
