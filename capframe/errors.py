"""User-facing errors.

Every problem caused by input (a file, a field, a value) raises :class:`InputError` with a
one-line message that names the offending file/field/value and what was expected. The CLI prints
such errors as a single line and exits with status 2; anything else is a bug and keeps its traceback.
"""


class InputError(ValueError):
    """Bad user input: a malformed file, a missing field, an out-of-range value."""

    def __init__(self, message: str, *, source: str | None = None):
        self.source = source
        super().__init__(f"{source}: {message}" if source else message)
