"""RCL: a robot control language built on coordinate frames and transform equations.

Embedding starts with Session; see rcl.session. Importing the package is light: what it
offers (Session, Frame, vec, the errors) is imported when first named, so that the `rcl` command
can take a Ctrl-C from its first moments as it does later (rcl.launch).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any

__version__ = "0.1.0"

if TYPE_CHECKING:
    from .errors import Diagnostic, RclCancelled, RclError, RclRuntimeError, RclStaticError
    from .frame import Frame, vec
    from .session import Session

__all__ = ["Session", "Frame", "vec", "Diagnostic", "RclError", "RclStaticError",
           "RclRuntimeError", "RclCancelled", "__version__"]

_LAZY = {"Session": ".session", "Frame": ".frame", "vec": ".frame", "Diagnostic": ".errors", "RclError": ".errors",
         "RclStaticError": ".errors", "RclRuntimeError": ".errors", "RclCancelled": ".errors"}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        from importlib import import_module

        value = getattr(import_module(_LAZY[name], __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
