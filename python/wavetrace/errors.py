"""The exceptions wavetrace raises. Their messages are the command line's.

- ``WavetraceError``: the base; raised itself only for an internal error (a bug), never a
  panic crossing into Python.
- ``InputError``: bad input — an option's value, a scene, a config, an image's shape
  (also a ``ValueError``).
- ``UnknownOptionError``: an option name ``render`` does not take (also a ``TypeError``, as
  an unexpected keyword argument is in Python).
- ``RenderError``: the work could not be done — no GPU adapter, a device error, a file that
  could not be written (also a ``RuntimeError``).
"""


class WavetraceError(Exception):
    """Base class of wavetrace's exceptions."""


class InputError(WavetraceError, ValueError):
    """Bad input: the message names the option, file or field and the reason."""


class UnknownOptionError(InputError, TypeError):
    """An option name that ``render`` does not take."""


class RenderError(WavetraceError, RuntimeError):
    """The render or experiment could not run (no adapter, a device error, an unwritable file)."""
