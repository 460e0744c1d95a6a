"""The one exception type for mistakes a user can fix (bad file, name or value); the CLI prints it
as one sentence instead of a traceback."""


class UserError(Exception):
    """A problem with the user's input, stated as one clear sentence naming what is at fault."""
