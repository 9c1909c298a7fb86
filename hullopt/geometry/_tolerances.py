"""Named tolerances shared by the kernel, the models and the analyses: what "zero" means for a length, for
two points, and for a denominator. Each is far below any real hull dimension and far above float64's rounding
of one, so a test against it only sorts out degenerate input (repeated points, empty sections) and never moves
a real result."""

#: m. A length (a segment, a breadth, a hull's extent) below this is zero: the segment is a repeated point,
#: the breadth an empty section; also the floor that keeps a division by such a length finite.
TINY_LENGTH = 1e-9

#: Dimensionless. Two points closer than this fraction of the scale of the geometry they belong to (its largest
#: coordinate, its breadth, its length; at least 1 m where so written) are the same point; a coordinate within
#: it of the centreline is on the centreline. Relative, so it holds for a model and for the full-size ship.
SAME_POINT = 1e-9

#: A denominator floor that only stops a division by zero (of a squared length, a wavenumber·length): far
#: below any value a real input gives, so it changes nothing else.
DIVISION_FLOOR = 1e-300
