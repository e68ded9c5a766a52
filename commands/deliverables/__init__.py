"""Deliverable subcommands beside the report: compliance (EN 12464-1), illuminance-image, circadian (WELL v2 L03)."""
