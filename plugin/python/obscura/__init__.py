# The obscura package: the compiled module (_obscura, pybind11) and pure-Python helpers
# (obscura.farm). `import obscura` gives the compiled module's names, as before the split.
from ._obscura import *  # noqa: F401,F403
from ._obscura import __doc__, __version__  # noqa: F401
