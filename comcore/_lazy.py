"""Names a package exports that load on first use (its application layers stay unloaded).

``import comcore`` loads the core; the goal session, recordings, ROS messages and the test
strategies load when a program first touches them (``comcore.GoalSession``,
``comcore.recordings``). A package declares ``__getattr__, __dir__ = lazy_exports(__name__,
table)`` once, its table mapping each lazy name to the submodule that holds it (a
submodule's own name maps to itself), as scikit-image's ``lazy_loader`` does.
"""

from __future__ import annotations

import importlib

__all__ = ["lazy_exports"]


def lazy_exports(package: str, table: dict[str, str]):
    """The module ``__getattr__`` and ``__dir__`` that load ``table``'s names on first use.

    Examples
    --------
    >>> getattr_, dir_ = lazy_exports("comcore", {"ros": "ros"})
    >>> getattr_("ros").__name__
    'comcore.ros'
    >>> getattr_("nothing")
    Traceback (most recent call last):
    ...
    AttributeError: module 'comcore' has no attribute 'nothing'
    """
    namespace = importlib.import_module(package).__dict__

    def __getattr__(name: str):
        submodule = table.get(name)
        if submodule is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        module = importlib.import_module(f"{package}.{submodule}")
        value = module if name == submodule.rsplit(".", 1)[-1] else getattr(module, name)
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(table))

    return __getattr__, __dir__
