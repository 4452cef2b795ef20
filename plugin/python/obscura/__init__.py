# The obscura package: the compiled module (_obscura, pybind11) and pure-Python helpers
# (obscura.farm). `import obscura` gives the compiled module's names, as before the split.
from ._obscura import *  # noqa: F401,F403
from ._obscura import __doc__, __version__  # noqa: F401

# help(obscura) lists the classes too: they are this package's, not the compiled module's.
Camera.__module__ = Error.__module__ = __name__  # noqa: F405
__all__ = [name for name in dir() if not name.startswith("_") and name != "farm"]  # noqa: F405
