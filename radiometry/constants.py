"""Physical and photometric constants, SI units named in each constant.

References
----------
- BIPM, *The International System of Units (SI)*, 9th ed. (2019): K_cd = 683 lm/W at 540 THz, exact c, h, k.
- G. Ward Larson, R. Shakespeare, *Rendering with Radiance* (1998): 179 lm/W luminous efficacy of
  equal-energy white over the visible range, the factor Radiance's tools use (``WHTEFFICACY``).
"""

#: Maximum luminous efficacy of photopic vision, lm/W (SI definition of the candela, 540e12 Hz).
K_M_LM_PER_W = 683.0

#: Luminous efficacy of equal-energy white radiation as used by Radiance, lm/W.
K_RADIANCE_WHITE_LM_PER_W = 179.0

#: Speed of light in vacuum, m/s (exact).
SPEED_OF_LIGHT_M_PER_S = 299_792_458.0

#: Planck constant, J s (exact).
PLANCK_J_S = 6.626_070_15e-34

#: Boltzmann constant, J/K (exact).
BOLTZMANN_J_PER_K = 1.380_649e-23

#: Second radiation constant c2 = h c / k, m K.
C2_M_K = PLANCK_J_S * SPEED_OF_LIGHT_M_PER_S / BOLTZMANN_J_PER_K

#: Wavelength range of the photometric integrals, nm.
VISIBLE_RANGE_NM = (360.0, 830.0)
