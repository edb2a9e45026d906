"""pandas and numpy: the client returns DataFrames and arrays with them, and imports each only
when a method that returns one is called. Without it that method raises ImportError naming the
interpreter that lacks it and the package that brings it; its frame=False or array=False form
gives the same data as lists."""
import importlib
import sys

# Debian's package of each module (what scripts/install-deps.sh installs).
DEBIAN_PACKAGES = {"pandas": "python3-pandas", "numpy": "python3-numpy"}


def require(module, what, instead):
    """The imported module, or ImportError saying that `what` needs it, which interpreter
    cannot import it, how to install it, and `instead` (the method's form without it)."""
    try:
        return importlib.import_module(module)
    except ImportError as e:
        raise ImportError(
            "%s needs %s, which %s cannot import (%s): install Debian's %s "
            "(scripts/install-deps.sh) and run Debian's /usr/bin/python3, or install %s for this "
            "interpreter (%s -m pip install %s); %s"
            % (what, module, sys.executable, e, DEBIAN_PACKAGES[module], module, sys.executable,
               module, instead), name=module) from None
