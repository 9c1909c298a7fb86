"""User-facing errors. A ``HullError`` message is shown as one line, without a traceback."""


class HullError(ValueError):
    """Bad input from a user: the message names the file, line, field or parameter and what was expected."""
