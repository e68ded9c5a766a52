"""Weather files checked (issue 33): each bad EPW gets one line naming the line, or a stated note.

The legal files are written here: a synthetic year (a clear-sky model scaled by a random daily
clearness; the weather is an input, not a reference) and two real TMY3 years shipped with pvlib
(Sand Point AK, Greensboro NC) rewritten as EPW. ladybug-core's EPW reader is the independent
cross-check of the values read.
"""

import datetime as dt
import os
import subprocess
import sys
import threading
import tracemalloc

import numpy as np
import pytest

from radiometer.radiometry.sun import epw, solar_position

LAT, LON, TZ = 51.5, -0.12, 0.0
HEADER = ["LOCATION,Testville,TS,XYZ,synthetic,000000,{lat},{lon},{tz},20.0",
          "DESIGN CONDITIONS,0", "TYPICAL/EXTREME PERIODS,0", "GROUND TEMPERATURES,0",
          "HOLIDAYS/DAYLIGHT SAVINGS,No,0,0,0", "COMMENTS 1,written by tests/test_epw_checks.py",
          "COMMENTS 2,", "DATA PERIODS,1,1,Data,Thursday, 1/ 1,12/31"]
FIRST = 9  # line number of the first record


def year_rows(leap=False, lat=LAT, lon=LON, tz=TZ, seed=7, minute=60):
    """Records (lists of field texts) of a whole year, local standard time UTC+tz."""
    year = 2024 if leap else 2026
    n = 8784 if leap else 8760
    zone = dt.timezone(dt.timedelta(hours=tz))
    start = dt.datetime(year, 1, 1, tzinfo=zone)
    mids = [start + dt.timedelta(hours=h + 0.5) for h in range(n)]
    pos = solar_position.solar_position(solar_position.unix_seconds(mids), lat, lon)
    sin_h = np.sin(np.radians(np.asarray(pos.elevation_deg, float)))
    k = np.repeat(np.random.default_rng(seed).uniform(0.0, 1.0, n // 24), 24)
    up = sin_h > 0.05
    dni = np.where(up, 900.0 * np.exp(-0.16 / np.maximum(sin_h, 0.05)) * k, 0.0).round()
    dhi = np.where(up, (10.0 + 60.0 * sin_h) * (1 + 1.5 * (1 - k)), 0.0).round()
    ghi = (dhi + dni * np.maximum(sin_h, 0)).round()
    rows = []
    for t, g, b, d in zip(mids, ghi, dni, dhi):
        end = t - dt.timedelta(minutes=30)
        f = [year, end.month, end.day, end.hour + 1, minute, "?9?9?9?9E0?9?9?9*9?9?9?9?9?9?9?9?9?9*9*9?9*9*9",
             12.0, 8.0, 70, 101325, 1415, 1415, 300, int(g), int(b), int(d), int(110 * g), int(100 * b),
             int(120 * d), 9999, 180, 3.0, 5, 3, 10.0, 77777, 9, 999999999, 10, 0.1, 0, 88, 0.2, 0, 1]
        rows.append([str(v) for v in f])
    return rows


_YEAR = {}


def year(leap=False):
    """A copy of the cached synthetic year's records."""
    if leap not in _YEAR:
        _YEAR[leap] = year_rows(leap)
    return [list(r) for r in _YEAR[leap]]


def text(rows, header=None, lat=LAT, lon=LON, tz=TZ):
    head = header if header is not None else [h.format(lat=lat, lon=lon, tz=tz) for h in HEADER]
    return "\n".join(head + [",".join(r) for r in rows]) + "\n"


def write(path, rows, **kw):
    path.write_text(text(rows, **kw), encoding="latin-1")
    return path


def refused(content, *match):
    """The one-line EPWError for this text; it must contain every string of ``match``."""
    with pytest.raises(epw.EPWError) as info:
        epw.parse_epw(content, source="t.epw")
    message = str(info.value)
    assert "\n" not in message and message.startswith("t.epw")
    for m in match:
        assert m in message, message
    return message


# --- files that are not weather files ------------------------------------------------------------

def test_directory_fifo_device_and_size_refused_before_reading(tmp_path):
    with pytest.raises(epw.EPWError, match="is a directory"):
        epw.read_epw(tmp_path)
    with pytest.raises(epw.EPWError, match="no such file"):
        epw.read_epw(tmp_path / "none.epw")
    with pytest.raises(epw.EPWError, match="not a regular file"):
        epw.read_epw("/dev/zero")
    big = tmp_path / "big.epw"
    with open(big, "wb") as fh:  # sparse: 148 MB on paper, nothing on disk
        fh.truncate(148_000_000)
    with pytest.raises(epw.EPWError, match=f"too large .*at most {epw.MAX_FILE_BYTES}"):
        epw.read_epw(big)
    fifo = tmp_path / "pipe.epw"
    os.mkfifo(fifo)
    out = {}

    def read():
        try:
            epw.read_epw(fifo)
        except epw.EPWError as exc:
            out["error"] = str(exc)

    reader = threading.Thread(target=read, daemon=True)
    reader.start()
    reader.join(10.0)
    if reader.is_alive():  # free the blocked reader so the test run can end, then fail
        with open(fifo, "w"):
            pass
        pytest.fail("reading a FIFO blocked")
    assert "not a regular file" in out["error"]


def test_binary_and_endless_lines_refused(tmp_path):
    zeros = tmp_path / "zeros.epw"
    zeros.write_bytes(b"\0" * 100_000)
    with pytest.raises(epw.EPWError, match="line 1: binary data"):
        epw.read_epw(zeros)
    long = tmp_path / "long.epw"
    long.write_bytes(b"LOCATION," + b"x" * (epw.MAX_LINE_BYTES + 10))
    with pytest.raises(epw.EPWError, match=f"line 1: longer than {epw.MAX_LINE_BYTES} bytes"):
        epw.read_epw(long)


# --- a year, or a period said so -----------------------------------------------------------------

def test_whole_years_read_clean(tmp_path):
    for leap in (False, True):
        w = epw.read_epw(write(tmp_path / "y.epw", year(leap)))
        assert w.count == (8784 if leap else 8760) and w.is_full_year
        assert w.notes == [] and w.usable.all()
        assert w.period.startswith(f"{w.count} hourly records from 1 January hour 1 (line 9) to 31 December hour 24")


def test_short_file_says_what_is_there(tmp_path):
    w = epw.parse_epw(text(year()[:100]))
    assert not w.is_full_year and w.count == 100
    assert w.period == "100 hourly records from 1 January hour 1 (line 9) to 5 January hour 4 (line 108)"


def test_leap_year_short_of_29_february_is_not_whole():
    rows = year(leap=True)
    del rows[-24:]  # 8760 records, but 31 December missing
    w = epw.parse_epw(text(rows))
    assert w.count == 8760 and not w.is_full_year


def test_a_year_may_start_in_july_and_wrap_once():
    rows = year()
    w = epw.parse_epw(text(rows[4344:] + rows[:4344]))
    assert w.is_full_year and w.period.startswith("8760 hourly records from 1 July hour 1")


def test_duplicated_missing_reversed_and_two_year_files_refused():
    rows = year()[:200]
    refused(text(rows[:50] + [rows[49]] + rows[50:]), "line 59:", "3 January hour 2 repeats line 58")
    refused(text(rows[:50] + rows[53:]), "line 59:", "3 January hour 6 follows 3 January hour 2", "3 hour(s) missing")
    refused(text(rows[::-1]), "line 10:", "goes back in time")
    refused(text(rows[:50] + [rows[51], rows[50]] + rows[52:]), "line 59:", "1 hour(s) missing")
    two = year() + year()
    refused(text(two), f"line {FIRST + 8760}:", "the year starts again", "two-year file")
    rows = year()
    refused(text(rows + rows[:30]), f"line {FIRST + 8760}:", "the year starts again")


def test_a_leap_day_may_be_skipped_but_not_other_days():
    rows = year(leap=True)
    no_leap = rows[:59 * 24] + rows[60 * 24:]  # 29 February left out
    w = epw.parse_epw(text(no_leap))
    assert w.count == 8760 and w.is_full_year
    no_march_1 = rows[:60 * 24] + rows[61 * 24:]
    refused(text(no_march_1), f"line {FIRST + 60 * 24}:", "2 March hour 1 follows 29 February hour 24",
            "24 hour(s) missing")


# --- dates and fields ----------------------------------------------------------------------------

def test_dates_validated():
    rows = year()[:24 * 60]
    feb30 = [list(r) for r in rows]
    feb30[24 * 58][2] = "30"   # 28 February hour 1 -> 30 February
    refused(text(feb30), f"line {FIRST + 24 * 58}: 30 February is not a date")
    for col, bad, what in ((1, "13", "month must be a whole number 1-12"), (2, "0", "day must be"),
                           (3, "25", "hour must be a whole number 1-24"), (3, "1.5", "hour must be"),
                           (4, "61", "minute must be a whole number 0-60"), (1, "x", "month is not a number")):
        edited = [list(r) for r in rows]
        edited[5][col] = bad
        refused(text(edited), "line 14:", what)


def test_minute_0_or_60_and_data_source_flags_accepted():
    for minute in (0, 60):
        rows = year_rows(minute=minute)[:48]
        rows[3][5] = "A7A7A7A7*0?9?9?9?9?9?9?9?9?9?9?9?9?9?9?9*_*9*9*9*9*9"
        w = epw.parse_epw(text(rows))
        assert w.count == 48 and (w.minute == minute).all()


def test_byte_order_mark_utf8_blank_lines_and_crlf_accepted(tmp_path):
    content = text(year()[:48]).replace("Testville", "São Tomé").replace("\n", "\r\n")
    lines = content.split("\r\n")
    content = "\r\n".join(lines[:8] + [""] + lines[8:20] + ["  "] + lines[20:])
    path = tmp_path / "bom.epw"
    path.write_bytes(b"\xef\xbb\xbf" + content.encode("utf-8"))
    w = epw.read_epw(path)
    assert w.city == "São Tomé" and w.count == 48 and w.line_numbers[0] == 10 and w.line_numbers[-1] == 58


def test_header_of_the_wrong_length_refused():
    lines = text(year()[:48]).splitlines()
    short = lines[:6] + lines[7:]   # COMMENTS 2 left out: the first record would be header line 8
    refused("\n".join(short), "line 8: an hourly record where header line 8 of 8 is expected", "the header has 7 lines")
    long = lines[:7] + ["COMMENTS 3,extra"] + lines[7:]
    refused("\n".join(long), "line 8:", "'COMMENTS 3,extra' where header line 8 of 8")
    twice = lines[:6] + ["COMMENTS 1,again"] + lines[7:]
    refused("\n".join(twice), "line 7: a second COMMENTS 1 header line")
    refused("\n".join(lines[:5]), "ends after 5 header lines")
    refused("\n".join(lines[:8]), "no hourly records")
    sub = lines[:7] + ["DATA PERIODS,1,4,Data,Sunday, 1/ 1,12/31"] + lines[8:]
    refused("\n".join(sub), "line 8:", "4 records per hour", "only hourly")


def test_non_finite_values_refused_naming_the_line():
    for bad in ("nan", "inf", "-inf", "NaN"):
        rows = year()[:48]
        rows[12][14] = bad
        refused(text(rows), "line 21: direct normal radiation is", "not a finite number")
    rows = year()[:48]
    rows[30][7] = "1e999"
    refused(text(rows), "line 39: dew-point temperature")


# --- irradiance against the sun -------------------------------------------------------------------

def _day_hours(rows, lat=LAT, lon=LON):
    """Indices of records with a full hour of sunshine (sun up at the hour's start)."""
    w = epw.parse_epw(text(rows))
    return np.flatnonzero((w.global_horizontal_w_m2 > 100) & (w.direct_normal_w_m2 > 0))


@pytest.mark.parametrize("value, kind", [("9999", "missing (9999) 5 h"), ("-20", "negative 5 h"),
                                         ("1000000000", "above the extraterrestrial 1367 W/m^2"),
                                         ("1500", "above the extraterrestrial 1367 W/m^2")])
def test_few_bad_direct_normal_hours_noted_and_left_out(value, kind):
    rows = year()
    day = _day_hours(rows)[1000:1005]
    for k in day:
        rows[k][14] = value
    w = epw.parse_epw(text(rows))
    note = [n for n in w.notes if n.startswith("direct normal radiation")]
    assert len(note) == 1 and kind in note[0] and f"lines {FIRST + day[0]}" in note[0], w.notes
    assert "left out of the metrics" in note[0]
    assert not w.usable[day].any() and w.usable.sum() == 8760 - 5


@pytest.mark.parametrize("value, what", [("9999", "9999 (missing)"), ("-5", "-5 W/m^2"), ("1e9", "1e+09 W/m^2")])
def test_bad_direct_normal_throughout_refused(value, what):
    rows = year()
    day = _day_hours(rows)
    for k in day:
        rows[k][14] = value
    message = refused(text(rows), f"line {FIRST + day[0]}: direct normal radiation {what}", "sun-up hours unusable")
    assert "more than 5 %" in message


def test_super_solar_horizontal_refused_or_noted():
    rows = year()
    day = _day_hours(rows)
    w0 = epw.parse_epw(text(rows))
    noon = [k for k in day if w0.hour[k] == 13][:3]
    for k in noon:
        rows[k][13] = "1380"   # above E0 sin(h) in winter London, below the solar constant
    w = epw.parse_epw(text(rows))
    note = [n for n in w.notes if n.startswith("global horizontal radiation")]
    assert len(note) == 1 and "above the extraterrestrial irradiance 3 h" in note[0] and "not used" in note[0]
    assert w.usable.all()  # global horizontal is not what the sky is built from
    for k in day:
        rows[k][15] = "1400"
    refused(text(rows), f"line {FIRST + day[0]}: diffuse horizontal radiation 1400 W/m^2")


def test_missing_at_night_taken_as_zero_with_a_note():
    rows = year()
    night = [k for k in range(len(rows)) if int(rows[k][3]) in (1, 2)][:40]
    for k in night:
        rows[k][14] = rows[k][15] = "9999"
    w = epw.parse_epw(text(rows))
    assert w.usable.all() and len(w.notes) == 1
    assert w.notes[0].startswith("40 hours with the sun below the horizon") and "taken as 0" in w.notes[0]


def test_sunshine_while_the_sun_is_down_warns_of_the_time_zone():
    rows = year()
    assert epw.parse_epw(text(rows, tz=TZ)).notes == []
    w = epw.parse_epw(text(rows, tz=TZ - 6))   # the same hours said to be 6 h west of UTC
    warn = [n for n in w.notes if n.startswith("warning: sunshine")]
    assert len(warn) == 1 and "time zone (UTC-6 h)" in warn[0]
    w = epw.parse_epw(text(rows, lon=LON + 90))   # the site 90 degrees east of the data's
    assert any("time zone (UTC+0 h) or the site" in n for n in w.notes)
    # a few misplaced hours (NIGHT_SUNSHINE_HOURS or fewer) stay quiet
    rows = year()
    nights = [k for k in range(len(rows)) if int(rows[k][3]) == 2][:epw.NIGHT_SUNSHINE_HOURS]
    for k in nights:
        rows[k][14] = "50"
    assert not any(n.startswith("warning") for n in epw.parse_epw(text(rows)).notes)
    rows[[k for k in range(len(rows)) if int(rows[k][3]) == 3][0]][14] = "50"
    assert any(n.startswith("warning") for n in epw.parse_epw(text(rows)).notes)


# --- real years and an independent reader ---------------------------------------------------------

def tmy3_as_epw(name, path):
    """A TMY3 file shipped with pvlib rewritten as EPW (TMY3 and EPW both give the hour ending at
    local standard time); irradiance, temperatures and pressure copied."""
    import pvlib

    src = os.path.join(os.path.dirname(pvlib.__file__), "data", name)
    with open(src, newline="") as fh:
        lines = fh.read().splitlines()
    meta = lines[0].split(",")
    head = [f"LOCATION,{meta[1]},{meta[2]},USA,TMY3,{meta[0]},{meta[4]},{meta[5]},{meta[3]},{meta[6]}"] + HEADER[1:]
    rows = []
    for line in lines[2:]:
        c = line.split(",")
        m, d, y = c[0].split("/")
        f = [y, int(m), int(d), int(c[1].split(":")[0]), 0, "?9", c[31], c[34], c[37], int(float(c[40]) * 100),
             9999, 9999, 9999, c[4], c[7], c[10], 999999, 999999, 999999, 9999, 180, 3.0, 5, 3, 10.0, 77777, 9,
             999999999, 10, 0.1, 0, 88, 0.2, 0, 1]
        rows.append([str(v) for v in f])
    path.write_text("\n".join(head + [",".join(r) for r in rows]) + "\n", encoding="latin-1")
    return path


@pytest.mark.parametrize("name", ["703165TY.csv", "723170TYA.CSV"])
def test_real_tmy3_years_read_without_notes(tmp_path, name):
    w = epw.read_epw(tmy3_as_epw(name, tmp_path / "tmy.epw"))
    assert w.is_full_year and w.notes == [] and w.usable.all()


def test_values_agree_with_ladybug(tmp_path):
    ladybug_epw = pytest.importorskip("ladybug.epw")
    rows = year(leap=True)
    rows[100][14] = "9999"   # a missing night value: NaN here; ladybug keeps the code
    header = [h.format(lat=LAT, lon=LON, tz=TZ).replace("SAVINGS,No", "SAVINGS,Yes") for h in HEADER]
    path = write(tmp_path / "y.epw", rows, header=header)  # "Yes": leap year observed
    w = epw.read_epw(path)
    ref = ladybug_epw.EPW(str(path))
    assert ref.is_leap_year and len(ref.direct_normal_radiation.values) == w.count == 8784
    loc = ref.location
    assert (w.city, w.latitude_deg, w.longitude_deg, w.time_zone_h, w.elevation_m) == (
        loc.city, loc.latitude, loc.longitude, loc.time_zone, loc.elevation)
    for mine, theirs in (("global_horizontal_w_m2", "global_horizontal_radiation"),
                         ("direct_normal_w_m2", "direct_normal_radiation"),
                         ("diffuse_horizontal_w_m2", "diffuse_horizontal_radiation"),
                         ("dry_bulb_c", "dry_bulb_temperature"), ("dew_point_c", "dew_point_temperature"),
                         ("pressure_pa", "atmospheric_station_pressure"),
                         ("global_horizontal_lux", "global_horizontal_illuminance"),
                         ("direct_normal_lux", "direct_normal_illuminance"),
                         ("diffuse_horizontal_lux", "diffuse_horizontal_illuminance")):
        theirs_values = np.asarray(getattr(ref, theirs).values, float)
        np.testing.assert_array_equal(np.nan_to_num(w.data[mine], nan=9999.0), theirs_values, err_msg=mine)
    dts = getattr(ref, "direct_normal_radiation").datetimes
    assert [(d.month, d.day, d.hour) for d in dts[:2]] == [(1, 1, 0), (1, 1, 1)]  # ladybug: hour - 1
    assert (w.month[-1], w.day[-1], w.hour[-1]) == (12, 31, 24) and (dts[-1].month, dts[-1].day, dts[-1].hour) == (
        12, 31, 23)


# --- memory ---------------------------------------------------------------------------------------

#: The reader's bound (module docstring): records in arrays of at most 8784 rows, one line at a time.
MEMORY_BOUND_BYTES = 8 * 1024 * 1024


def test_memory_bounded_whatever_the_file(tmp_path):
    """tracemalloc's peak while reading a leap year, and a leap year followed by blank lines (skipped,
    as EnergyPlus does) up to the size limit: read to its end, one bounded line at a time."""
    path = write(tmp_path / "leap.epw", year(leap=True))
    big = tmp_path / "big.epw"
    blank = b" " * (epw.MAX_LINE_BYTES - 1) + b"\n"
    with open(big, "wb") as fh:
        fh.write(path.read_bytes())
        while fh.tell() + len(blank) <= epw.MAX_FILE_BYTES:
            fh.write(blank)
    tracemalloc.start()
    try:
        assert epw.read_epw(path).is_full_year
        peak_year = tracemalloc.get_traced_memory()[1]
        tracemalloc.reset_peak()
        assert epw.read_epw(big).is_full_year
        peak_big = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    print(f"peak {peak_year / 1e6:.2f} MB reading a leap year ({path.stat().st_size / 1e6:.2f} MB), "
          f"{peak_big / 1e6:.2f} MB on a {big.stat().st_size / 1e6:.1f} MB file")
    assert peak_year < MEMORY_BOUND_BYTES and peak_big < MEMORY_BOUND_BYTES


def test_memory_of_a_process_reading_the_148_mb_files(tmp_path):
    """The issue's 148 MB file took 4.4 GB: now refused before reading (its size), in a process whose
    resident memory grows by less than 16 MiB."""
    big = tmp_path / "big.epw"
    with open(big, "wb") as fh:
        fh.truncate(148_000_000)
    code = ("import resource, sys\nfrom radiometer.radiometry.sun import epw\n"
            "before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss\n"
            "try:\n    epw.read_epw(sys.argv[1])\nexcept epw.EPWError as exc:\n    print(exc)\n"
            "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before)\n")
    out = subprocess.run([sys.executable, "-c", code, str(big)], capture_output=True, text=True, timeout=120,
                         env=dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path)))
    message, grown_kib = out.stdout.strip().splitlines()
    assert "too large" in message and int(grown_kib) < 16 * 1024


# --- fuzz -----------------------------------------------------------------------------------------

def _fuzz_cases():
    from hypothesis import strategies as st

    cell = st.one_of(st.sampled_from(["9999", "-1", "nan", "inf", "-inf", "1e309", "1e9", "", " ", "0", "60", "61",
                                      "24", "25", "29", "30", "31", "2", "13", "1.5", "x", "\ufeff1", "99.9"]),
                     st.integers(-10**12, 10**12).map(str), st.floats().map(repr), st.text(max_size=6))
    line = st.integers(0, 60)
    op = st.one_of(
        st.tuples(st.just("delete"), line), st.tuples(st.just("duplicate"), line),
        st.tuples(st.just("swap"), line, line), st.tuples(st.just("cell"), line, st.integers(0, 36), cell),
        st.tuples(st.just("cut"), line, st.integers(0, 200)), st.tuples(st.just("insert"), line, st.text(max_size=40)),
        st.tuples(st.just("bytes"), line, st.binary(max_size=40)),
        st.tuples(st.just("column"), st.integers(1, 5), st.integers(0, 36), cell))  # every n-th record
    return st.lists(op, min_size=1, max_size=4)


def _mutate(ops):
    lines = [ln.encode("latin-1") for ln in text(year()[4000:4048]).splitlines()]
    for o in ops:
        i = o[1] % len(lines) if lines else 0
        if not lines:
            break
        if o[0] == "delete":
            del lines[i]
        elif o[0] == "duplicate":
            lines.insert(i, lines[i])
        elif o[0] == "swap":
            j = o[2] % len(lines)
            lines[i], lines[j] = lines[j], lines[i]
        elif o[0] == "cell":
            cells = lines[i].split(b",")
            cells[o[2] % len(cells)] = o[3].encode("utf-8")
            lines[i] = b",".join(cells)
        elif o[0] == "cut":
            lines[i] = lines[i][:o[2]]
        elif o[0] == "column":
            for k in range(8, len(lines), o[1]):
                cells = lines[k].split(b",")
                cells[o[2] % len(cells)] = o[3].encode("utf-8")
                lines[k] = b",".join(cells)
        elif o[0] == "insert":
            lines.insert(i, o[2].encode("utf-8"))
        else:
            lines[i] = o[2]
    return b"\n".join(lines) + b"\n"


@pytest.mark.slow
def test_fuzz_malformed_weather_files_give_one_line(tmp_path_factory):
    """Malformed files (records deleted, duplicated, swapped, cut short, cells replaced by numbers, NaN,
    codes or text in one record or in every n-th, random text or bytes inserted): each is read (its notes one line each) or refused with
    one EPWError line; never another exception."""
    from hypothesis import HealthCheck, given, settings

    folder = tmp_path_factory.mktemp("fuzz")
    outcomes = {"read": 0, "refused": 0}

    @settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow], database=None)
    @given(_fuzz_cases())
    def check(ops):
        path = folder / "f.epw"
        data = _mutate(ops)
        path.write_bytes(data)
        try:
            epw.parse_epw(data.decode("latin-1"), source=str(path))
        except epw.EPWError as exc:
            assert str(exc) and "\n" not in str(exc)
        try:
            w = epw.read_epw(path)
        except epw.EPWError as exc:
            message = str(exc)
            assert message and "\n" not in message and message.startswith(str(path)), message
            outcomes["refused"] += 1
            return
        assert all(isinstance(n, str) and "\n" not in n for n in w.notes)
        assert w.usable.shape == (w.count,) and not w.is_full_year
        outcomes["read"] += 1

    check()
    print(outcomes)
    assert outcomes["refused"] > 0
