"""Physical constants and unit conversions, defined once (SI units; README "Conventions")."""

G = 9.80665  # m/s², standard gravity
RHO_SEA = 1025.0  # kg/m³, sea water
RHO_AIR = 1.225  # kg/m³, air (ISA sea level)
NU_SEA = 1.18831e-6  # m²/s, kinematic viscosity of sea water at 15 °C (ITTC)
KNOT = 1852.0 / 3600.0  # m/s per knot
