"""False-colour isolux map of a work-plane grid, with a colour legend and labelled contour lines."""

import numpy as np

from . import pyplot


def isolux_png(path, lux, extent, *, title="", stats=None, levels=10, unit="lx"):
    """Write a false-colour image of ``lux`` (ny, nx) over ``extent`` = (x0, x1, y0, y1) in m.

    Each cell is drawn as a block (the value measured at its centre), with contour lines of a smooth
    interpolation on top and a colour bar in ``unit``. ``stats`` (avg, min, max, u0) goes in the title.
    """
    plt = pyplot()
    z = np.asarray(lux, float)
    x0, x1, y0, y1 = extent
    ny, nx = z.shape
    from matplotlib.colors import LogNorm

    fig, ax = plt.subplots(figsize=(6.4, 5.4))
    positive = z[z > 0]
    # A sun patch next to shade spans decades: a log scale keeps both readable.
    use_log = positive.size == z.size and positive.max() / positive.min() > 20
    norm = LogNorm(vmin=positive.min(), vmax=positive.max()) if use_log else None
    if use_log:
        levels = np.geomspace(positive.min(), positive.max(), levels + 2)[1:-1]
    image = ax.imshow(z, origin="lower", extent=(x0, x1, y0, y1), cmap="inferno", interpolation="nearest",
                      aspect="equal", norm=norm)
    bar = fig.colorbar(image, ax=ax, shrink=0.85)
    bar.set_label(f"illuminance ({unit})" + (", log scale" if use_log else ""))
    if nx >= 2 and ny >= 2 and np.ptp(z) > 0:
        xs = x0 + (np.arange(nx) + 0.5) * (x1 - x0) / nx
        ys = y0 + (np.arange(ny) + 0.5) * (y1 - y0) / ny
        lines = ax.contour(xs, ys, z, levels=levels, colors="white", linewidths=0.7)
        ax.clabel(lines, fmt="%.3g", fontsize=7, colors="white")
        bar.add_lines(lines)
    ax.set_xlabel("plane x (m)")
    ax.set_ylabel("plane y (m)")
    heading = title
    if stats:
        heading += (f"\nE_avg {stats['avg']:.4g} {unit}, E_min {stats['min']:.4g}, E_max {stats['max']:.4g}, "
                    f"U0 {stats['u0']:.3f}")
    ax.set_title(heading, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
