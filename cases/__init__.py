"""Built-in scenes. Each module ``cases/<name>.py`` defines a function ``<name>(**params)``
returning a :class:`taisph.Scene`; ``python -m taisph <name>`` runs it.

This folder is installed as the package ``taisph.cases``.
"""

import importlib
import pkgutil

CASES = {}
for _info in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name):
    if _info.name.startswith("_"):
        continue
    _module = importlib.import_module(f"{__name__}.{_info.name}")
    _func = getattr(_module, _info.name, None)
    if callable(_func):
        CASES[_info.name] = _func
        globals()[_info.name] = _func

__all__ = sorted(CASES)
