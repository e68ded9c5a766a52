"""Reference values from luxpy 1.12.5's CIE S 026 toolbox, run in its own interpreter (test-only).

luxpy 1.12.5 ships look-up tables pickled under numpy 2 (``numpy._core``); under the pinned numpy 1.26
it imports only with ``numpy._core`` aliased to ``numpy.core``, an alias that must not leak into the
test process (compiled modules imported after it would load numpy's core twice). So this script runs
in a subprocess: JSON in on stdin ({"spectra": [[401 values at 380-780 nm, 1 nm], ...],
"mesopic": [[L_p, S/P], ...]}), JSON out on stdout.
"""

import json
import sys

import numpy as np
import scipy.interpolate  # noqa: F401  (compiled against numpy's real core, before the alias)
import scipy.optimize  # noqa: F401
import scipy.spatial  # noqa: F401
import scipy.special  # noqa: F401
import numpy.core
import numpy.core.multiarray
import numpy.core.numeric

sys.modules.setdefault("numpy._core", numpy.core)
sys.modules.setdefault("numpy._core.numeric", numpy.core.numeric)
sys.modules.setdefault("numpy._core.multiarray", numpy.core.multiarray)

import luxpy as lx  # noqa: E402
from luxpy.toolboxes import photbiochem as ph  # noqa: E402


def main():
    request = json.load(sys.stdin)
    wl = np.arange(380.0, 781.0)
    out = {"version": lx.__version__}
    spectra = np.array(request.get("spectra", []), float)
    if spectra.size:
        sid = np.vstack([wl, spectra])
        out["elr"] = ph.spd_to_aopicELR(sid.copy()).tolist()           # W/lm, l, m, s, rh, mel
        der, ev = ph.spd_to_aopicDER(sid.copy(), out="DER,Ev")
        out["der"] = der.tolist()
        out["ev"] = np.ravel(ev).tolist()                               # lx (K_m 683.002)
        out["edi"] = ph.spd_to_aopicEDI(sid.copy()).tolist()            # lx
        out["eeas"] = ph.spd_to_aopicE(sid.copy()).tolist()             # W/m2
    if request.get("mesopic"):
        lp, sp = np.array(request["mesopic"], float).T
        lmes, m = lx.get_cie_mesopic_adaptation(lp, SP=sp)
        out["mesopic"] = [np.ravel(lmes).tolist(), np.ravel(m).tolist()]
    a = lx._CIE_ILLUMINANTS["A"]
    out["A_1nm"] = a[1][(a[0] >= 380) & (a[0] <= 780)].tolist()
    d = lx._CIE_D65
    out["D65_1nm"] = d[1][(d[0] >= 380) & (d[0] <= 780)].tolist()
    out["action_spectra"] = ph._ACTIONSPECTRA_CIES026[1:].tolist()   # l, m, s, rh, mel
    json.dump(out, sys.stdout)


if __name__ == "__main__":
    main()
