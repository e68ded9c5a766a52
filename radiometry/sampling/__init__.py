"""Monte Carlo sampling and statistics: per-meter allocation, batch means and intervals, pooled fields, convergence fits."""
