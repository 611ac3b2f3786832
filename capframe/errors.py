"""User-facing errors.

Every problem caused by input (a file, a field, a value) raises :class:`InputError` with a
one-line message that names the offending file/field/value and what was expected. The CLI prints
such errors as a single line and exits with status 2; anything else is a bug and keeps its traceback.
"""

# Longest user-supplied text (an instruction, a list of names) quoted whole in a message or a
# progress line, and longest error message.
CLIP_CHARS = 160
MESSAGE_CHARS = 1000


def clip(text: str, limit: int = CLIP_CHARS) -> str:
    """``text`` shortened to at most ``limit`` characters by eliding its middle (the start and
    the end are kept: a message's file and field, its expectation), so that a 10,000-character
    instruction quoted in a message leaves it one readable line."""
    if len(text) <= limit:
        return text
    marker = f" … ({len(text)} characters in all) … "
    keep = max(limit - len(marker), 0)
    head = keep * 2 // 3
    return text[:head] + marker + text[len(text) - (keep - head) :]


class InputError(ValueError):
    """Bad user input: a malformed file, a missing field, an out-of-range value.

    The message is kept one line (line breaks of quoted input become spaces) of at most
    :data:`MESSAGE_CHARS` characters (:func:`clip`), whatever input it quotes."""

    def __init__(self, message: str, *, source: str | None = None):
        self.source = source
        text = f"{source}: {message}" if source else message
        super().__init__(clip(" ".join(text.splitlines()), MESSAGE_CHARS))


class ModelError(RuntimeError):
    """A model backend failed after its bounded retries: a server unreachable, refusing, timing
    out or answering outside the schema; local weights that cannot be loaded or decoded.

    One line naming the endpoint (or weights), the model and the fault; never an API key. The CLI
    prints it as one line and exits with status 3, and no result of the failing command is written."""

    def __init__(self, message: str):
        super().__init__(clip(" ".join(message.splitlines()), MESSAGE_CHARS))
