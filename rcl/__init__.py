"""RCL: a robot control language built on coordinate frames and transform equations.

Embedding starts with Session; see rcl.session.
"""
__version__ = "0.1.0"

from .errors import Diagnostic, RclCancelled, RclError, RclRuntimeError, RclStaticError  # noqa: E402
from .frame import Frame, vec  # noqa: E402
from .session import Session  # noqa: E402

__all__ = ["Session", "Frame", "vec", "Diagnostic", "RclError", "RclStaticError",
           "RclRuntimeError", "RclCancelled", "__version__"]
