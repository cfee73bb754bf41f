"""The error the command line reports as ``companion: error: ...`` with exit status 2."""


class UserError(Exception):
    """Bad input from the user: a config or scenario file, a model file, an argument.

    Subclass it for each domain's errors; the message must say what is wrong and where.
    """
