"""Named tolerances of the hydrostatics and stability solves."""

#: Relative tolerance of the root finds of a waterline height for a volume (the draft, the heeled level;
#: Newton with bisection, ``_roots.level_for_volume``): near float64's resolution, so the root is as exact as
#: the section integrals it inverts; also the tolerance on a step as this fraction of the bracket (the hull's
#: height).
BISECTION_TOL = 1e-12

#: rad. Two heels closer than this are the same heel (a heel on the criteria's grid, a heel at a limit angle):
#: far below any angle that matters, above the rounding of a grid of radians.
ANGLE_TOL = 1e-12
