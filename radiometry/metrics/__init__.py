"""Metrics over readings: plane statistics and grids, daylight metrics (sDA, ASE, UDI), EN 12464-1 compliance, glare indices, the inverse-square and cosine-law checks."""
