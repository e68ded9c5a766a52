"""Issue 31: does the daylight factor's `auto` (sky component through the tilted pane in closed form, the openings
as emitters for the rest) read below a whole render under the tilted roof pane? The roof room of
bench/coverage_daylight_emitters.py (a 1 x 1 m opening with a 6 mm pane tilted 30 deg with the roof), its 5 points,
`auto` and `render` at one target over seeds 0..N-1, printed per seed and as means with their standard errors:

    python bench/roof_pane_split.py black0 0.003 3   # black room, black ground: the sky through the pane alone
    python bench/roof_pane_split.py black 0.004 2    # black room, ground 0.2: the sky and the ground through it
    python bench/roof_pane_split.py full 0.005 2     # the room's reflectances: the reflected part too

The printed runs are kept in bench/roof_pane_split.md.
"""
import os
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [HERE, os.path.join(HERE, "..", "tests", "bpy"), os.path.join(HERE, "..", "tests")]
import numpy as np  # noqa: E402

import coverage_daylight_emitters as c  # noqa: E402
from radiometer import api  # noqa: E402

room = c._room()
specs = c.scene_specs(room)
desc, quads, glass, points, normals, pane = specs["roof"]
variant = sys.argv[1]  # black0 / black / full
if variant.startswith("black"):
    room.RHO.update({k: 0.0 for k in room.RHO})
scene = c.build(room, quads, glass, pane)
g = 0.0 if variant == "black0" else 0.2
pts, nrm = np.asarray(points, float), np.asarray(normals, float)
target = float(sys.argv[2])
for method in ("auto", "render"):
    vals = []
    for k in range(int(sys.argv[3])):
        t0 = time.perf_counter()
        rs = api.daylight_factor(pts, nrm, scene=scene, target_rel_error=target, seed=k, ground_reflectance=g, method=method)
        vals.append([(r.daylight_factor, r.rel_std_error * r.daylight_factor) for r in rs])
        print(method, k, f"{time.perf_counter()-t0:.1f}s", [f"{a:.4f}" for a, b in vals[-1]], flush=True)
    v = np.array(vals)
    m = v[:, :, 0].mean(0); se = np.sqrt((v[:, :, 1] ** 2).sum(0)) / len(v)
    print("MEAN", method, " ".join(f"{a:.4f}+-{b:.4f}" for a, b in zip(m, se)), flush=True)
    if method == "auto":
        r0 = rs[0]
        print([ (getattr(r, "sky_component", None), getattr(r, "externally_reflected", None), getattr(r, "internally_reflected", None)) for r in rs])
        print(r0.notes)
