"""Reports: the full analysis report and the client's report (HTML/PDF) assembled from the analyses."""
