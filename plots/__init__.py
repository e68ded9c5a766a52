"""PNG plots of analysis results. Each function takes plain numbers and a path and returns the path.

matplotlib is imported inside the functions (Agg backend), so importing this package is cheap and
works where matplotlib is missing until a plot is asked for.
"""


def pyplot():
    """matplotlib.pyplot with the non-interactive Agg backend (no window, safe in Blender)."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt
