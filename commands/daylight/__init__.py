"""Daylight subcommands: sun, sun-study, daylight-factor, annual."""
