"""The one filter of Blender's operator reports (measure.blender.op_reports.ReportFilter), as the API and the
CLI configure it: line by line, a partial last line kept until it ends or the filter closes."""

import io

import pytest

from radiometer.measure.blender.op_reports import ReportFilter


def test_api_drops_info_and_sends_warnings_and_errors_to_stderr():
    out, err = io.StringIO(), io.StringIO()
    f = ReportFilter(out, err)
    f.write("Info: Baking map saved to internal image\nresult 1\nWarn")
    f.write("ing: texture missing\nError: bake failed\ntail")
    assert out.getvalue() == "result 1\n" and err.getvalue() == "Warning: texture missing\nError: bake failed\n"
    f.close()
    assert out.getvalue() == "result 1\ntail"


def test_cli_drops_errors_too_and_has_no_descriptor():
    out, err = io.StringIO(), io.StringIO()
    f = ReportFilter(out, err, drop=("Info: ", "Error: "), to_stderr=("Warning: ",), has_descriptor=False)
    f.write("Info: Saved as x\nError: said again by the CLI in one line\nWarning: w\n42 lx\n")
    assert out.getvalue() == "42 lx\n" and err.getvalue() == "Warning: w\n"
    assert not f.isatty() and not f.closed
    with pytest.raises(OSError):
        f.fileno()
