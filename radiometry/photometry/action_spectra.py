"""Beyond the photopic eye (pure numpy): CIE S 026 alpha-opic quantities, S/P ratio, CIE 191 mesopic.

Spectra are arrays whose last axis is sampled on :data:`.spectral.WAVELENGTHS_NM` (380-780 nm at
1 nm); leading axes broadcast. Every sum is CIE S 026/E:2018's: over 380-780 nm with 1 nm steps.

CIE S 026/E:2018 (alpha in S-cone, M-cone, L-cone, rhodopic, melanopic; action spectra s_alpha in
:mod:`._spectral_tables`, CIE's Table 2)
----------------------------------------------------------------------------------------------------
- alpha-opic ELR (efficacy of luminous radiation), W/lm: K_alpha,v = sum S s_alpha / (K_m sum S V),
  K_m = 683.002 lm/W (the value S 026 uses);
- alpha-opic DER (daylight efficacy ratio), dimensionless: K_alpha,v / K_alpha,v(D65), D65 being CIE's 1 nm
  table; 1 for D65 by definition;
- alpha-opic EDI (equivalent daylight (D65) illuminance), lx: E_v x DER;
- alpha-opic irradiance, W/m²: E_v x K_alpha,v.

Scotopic and mesopic
--------------------
- scotopic V'(lambda) is S 026's rhodopic action spectrum (the same CIE 1951 table); the S/P ratio is
  K'_m sum S V' / (K_m sum S V), K'_m = 1700.06 lm/W and K_m = 683.002 lm/W (CIE's pair, as luxpy);
- mesopic luminance by CIE 191:2010's iteration: m_0 = 0.5,
  L_mes,n = (m L_p + (1 - m) L_s V'(555 nm)) / (m + (1 - m) V'(555 nm)), V'(555 nm) = 683/1699,
  m_n = 0.7670 + 0.3334 log10(L_mes,n), clamped to [0, 1] (m = 1 at L_mes >= 5 cd/m², 0 at <= 0.005 cd/m²),
  iterated to a fixed point; L_s = L_p x S/P.
"""

import numpy as np

from . import _spectral_tables as tables
from ..constants import K_M_LM_PER_W

__all__ = ["ALPHA", "K_M_S026_LM_PER_W", "KP_M_LM_PER_W", "ACTION_SPECTRA", "PHOTOPIC_V", "SCOTOPIC_V",
           "alpha_opic_elr", "alpha_opic_der", "alpha_opic_edi", "alpha_opic_irradiance", "melanopic_der",
           "sp_ratio", "mesopic_luminance", "D65_ELR_W_PER_LM"]

#: The alpha-opic photoreceptors of CIE S 026, in the order of every array here.
ALPHA = ("s_cone", "m_cone", "l_cone", "rhodopic", "melanopic")

#: Maximum luminous efficacy of photopic vision as CIE S 026 uses it, lm/W.
K_M_S026_LM_PER_W = 683.002

#: Maximum luminous efficacy of scotopic vision, lm/W (CIE, paired with 683.002 lm/W).
KP_M_LM_PER_W = 1700.06

#: CIE S 026 action spectra s_alpha(lambda), shape (5, 401), rows in :data:`ALPHA` order.
ACTION_SPECTRA = np.stack([tables.S026_S_CONE, tables.S026_M_CONE, tables.S026_L_CONE, tables.S026_RHODOPIC,
                           tables.S026_MELANOPIC])

#: V(lambda) (CIE 018:2019) and V'(lambda) (CIE 1951) at 1 nm, 380-780 nm.
PHOTOPIC_V = tables.PHOTOPIC_V_1NM
SCOTOPIC_V = tables.S026_RHODOPIC

#: V'(lambda) at 555 nm as CIE 191:2010 takes it: K_m / 1699 = 683/1699.
_VP_555 = K_M_LM_PER_W / 1699.0
_MESOPIC_A, _MESOPIC_B = 0.7670, 0.3334
MESOPIC_RANGE_CD_M2 = (0.005, 5.0)


def _spectrum(spd):
    spd = np.asarray(spd, float)
    if spd.shape[-1:] != PHOTOPIC_V.shape:
        raise ValueError(f"a spectrum must be sampled at 380-780 nm, 1 nm ({PHOTOPIC_V.size} values in its last "
                         f"axis), got shape {spd.shape}")
    return spd


def alpha_opic_elr(spd):
    """alpha-opic efficacy of luminous radiation K_alpha,v (W/lm), shape ``spd.shape[:-1] + (5,)``.

    nan for a spectrum with no photopic content (sum S V = 0) or with nan/inf in it.
    """
    spd = _spectrum(spd)
    with np.errstate(divide="ignore", invalid="ignore"):
        photopic = K_M_S026_LM_PER_W * (spd @ PHOTOPIC_V)
        return (spd @ ACTION_SPECTRA.T) / np.where(photopic > 0, photopic, np.nan)[..., None]


#: alpha-opic ELR of D65 (W/lm), the denominators of every DER; the standard rounds them to
#: 0.8173, 1.4558, 1.6289, 1.4497, 1.3262 mW/lm (a test checks).
D65_ELR_W_PER_LM = alpha_opic_elr(tables.D65_1NM)


def alpha_opic_der(spd):
    """alpha-opic daylight (D65) efficacy ratio, dimensionless, shape ``spd.shape[:-1] + (5,)``."""
    return alpha_opic_elr(spd) / D65_ELR_W_PER_LM


def melanopic_der(spd):
    """Melanopic DER (mel-DER) of a spectrum: 1 for D65 by definition."""
    return alpha_opic_der(spd)[..., 4]


def alpha_opic_edi(spd, illuminance_lx):
    """alpha-opic equivalent daylight (D65) illuminance (lx) = E_v x DER, shape ``broadcast + (5,)``."""
    return np.asarray(illuminance_lx, float)[..., None] * alpha_opic_der(spd)


def alpha_opic_irradiance(spd, illuminance_lx):
    """alpha-opic irradiance E_e,alpha (W/m²) = E_v x K_alpha,v of light of spectrum ``spd`` at E_v lx."""
    return np.asarray(illuminance_lx, float)[..., None] * alpha_opic_elr(spd)


def sp_ratio(spd):
    """Scotopic-to-photopic ratio S/P = K'_m sum S V' / (K_m sum S V), dimensionless; nan without photopic light."""
    spd = _spectrum(spd)
    with np.errstate(divide="ignore", invalid="ignore"):
        p = K_M_S026_LM_PER_W * (spd @ PHOTOPIC_V)
        return KP_M_LM_PER_W * (spd @ SCOTOPIC_V) / np.where(p > 0, p, np.nan)


def _lmes(m, lp, ls):
    return (m * lp + (1.0 - m) * ls * _VP_555) / (m + (1.0 - m) * _VP_555)


def mesopic_luminance(photopic_cd_m2, sp, max_iterations=200):
    """CIE 191:2010 mesopic luminance (cd/m²) and adaptation coefficient m of L_p (cd/m²) at S/P ``sp``.

    Returns (L_mes, m), each of the broadcast shape. The iteration (module docstring) is a contraction
    for every L_p > 0 and S/P > 0; it stops when m changes by less than 1e-14. L_p <= 0, S/P <= 0 or
    non-finite inputs give nan. Where the fixed point has L_mes >= 5 cd/m² it is photopic (m = 1, L_mes = L_p);
    where L_mes <= 0.005 cd/m² scotopic (m = 0, L_mes = L_s). CIE 191 leaves which fixed point to take
    open where there are several (extreme S/P): this is the one reached from m = 0.5, as CIE 191 starts.
    """
    lp, sp = np.broadcast_arrays(np.asarray(photopic_cd_m2, float), np.asarray(sp, float))
    ok = np.isfinite(lp) & np.isfinite(sp) & (lp > 0) & (sp > 0)
    lp_ = np.where(ok, lp, 1.0)
    ls = lp_ * np.where(ok, sp, 1.0)
    m = np.full(lp_.shape, 0.5)
    for _ in range(max_iterations):
        new = np.clip(_MESOPIC_A + _MESOPIC_B * np.log10(_lmes(m, lp_, ls)), 0.0, 1.0)
        done = np.max(np.abs(new - m), initial=0.0) < 1e-14
        m = new
        if done:
            break
    lmes = _lmes(m, lp_, ls)
    return np.where(ok, lmes, np.nan)[()], np.where(ok, m, np.nan)[()]
