"""User-facing errors. A ``HullError`` message is shown as one line, without a traceback."""


class HullError(ValueError):
    """Bad input from a user: the message names the file, line, field or parameter and what was expected."""


class HullWarning(UserWarning):
    """A hull read that looks implausible (a mesh in millimetres, in the wrong axes, upside down): the message
    names the hull, what looks wrong, the likely cause and the fix (:func:`hullopt.models.plausibility_warnings`).
    The CLI prints it as one ``warning: …`` line; ``--strict`` makes it a one-line error (exit code 2)."""


class FidelityWarning(HullWarning):
    """A run's parent whose feature curves miss the hull they were extracted from by more than the extraction's
    tolerances (``fidelity.met`` false): the run's parent, and its particulars, are the feature model's, not
    the file's. A run's report lists it among its warnings."""
