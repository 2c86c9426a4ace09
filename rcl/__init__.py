"""RCL: a robot control language built on coordinate frames and transform equations.

Embedding starts with Session; see rcl.session.
"""
__version__ = "0.1.0"

from .errors import Diagnostic, RclCancelled, RclError, RclRuntimeError, RclStaticError
from .frame import Frame, vec
from .session import Session

__all__ = ["Session", "Frame", "vec", "Diagnostic", "RclError", "RclStaticError",
           "RclRuntimeError", "RclCancelled", "__version__"]
