"""The camera: models (the linear 3x4 camera and the paper's bicubic warp), their
calibration and file format, the calibration marker finder, image files and a
simulated camera. Plain numpy; nothing here knows RCL."""
from .calibration import Calibration
from .images import ImageError, as_grey, read_image
from .marker import find_mark
from .models import BicubicWarp, CameraModelError, FitReport, LinearCamera
from .sources import ImageFiles

__all__ = ["Calibration", "BicubicWarp", "LinearCamera", "FitReport", "CameraModelError", "ImageError",
           "ImageFiles", "find_mark", "read_image", "as_grey"]
