"""Reading images into float arrays, whatever the file holds.

Images are numpy arrays of float64 in [0, 1]: (rows, columns) for grey,
(rows, columns, 3) for colour. 8- and 16-bit, palette, bilevel, grey+alpha,
RGBA, CMYK and float images are accepted; anything else is an ImageError
with a message a user can act on. A file whose EXIF data says the camera was
turned (a phone's photograph) is read the right way up, as a viewer shows it.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

LUMA = np.array([0.299, 0.587, 0.114])


class ImageError(ValueError):
    """A file that is not a usable image."""


MAX_PIXELS = 40_000_000  # an image larger than this (a 6,300 x 6,300 frame) is no camera's of a tray


def read_image(path: str | Path) -> np.ndarray:
    import warnings

    from PIL import Image, ImageOps, UnidentifiedImageError

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)  # the size is judged below
            with Image.open(path) as im:
                w, h = im.size
                if w * h > MAX_PIXELS:
                    raise ImageError(f"{path} is {w} x {h} px, more than the {MAX_PIXELS:,} pixels "
                                     f"rcl reads (a camera's image of a tray is far smaller)")
                im.load()
                ImageOps.exif_transpose(im, in_place=True)  # the right way up (no copy when it is)
                return image_array(im)
    except ImageError:
        raise
    except FileNotFoundError:
        raise ImageError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise ImageError(f"{path} is a folder, not an image") from None
    except UnidentifiedImageError:
        raise ImageError(f"{path} is not an image file (or not one Pillow can read)") from None
    except Image.DecompressionBombError as e:
        raise ImageError(f"{path} is too large to read safely: {e}") from None
    except (OSError, SyntaxError, ValueError) as e:
        raise ImageError(f"{path} cannot be read as an image (truncated or damaged?): {e}") from None


def image_array(im) -> np.ndarray:
    """A Pillow image as a float array in [0, 1]."""
    mode = im.mode
    if mode in ("P", "PA", "CMYK", "YCbCr", "LAB", "HSV", "RGBA", "RGBX", "1", "LA", "La", "RGBa"):
        im = im.convert("RGB" if mode not in ("1", "LA", "La") else "L")
        mode = im.mode
    a = np.asarray(im)
    if mode in ("L", "RGB"):
        out = a.astype(float) / 255.0
    elif mode.startswith("I;16") or (mode == "I" and a.max(initial=0) <= 65535 and a.min(initial=0) >= 0):
        out = a.astype(float) / 65535.0
    elif mode in ("I", "F"):
        out = a.astype(float)
        if not np.all(np.isfinite(out)):
            raise ImageError("the image holds values that are not finite numbers (NaN or infinity)")
        lo, hi = out.min(initial=0.0), out.max(initial=0.0)
        out = (out - lo) / (hi - lo) if hi > lo else np.zeros_like(out)
    else:
        raise ImageError(f"images of mode {mode} are not supported")
    if out.ndim == 3 and out.shape[2] > 3:
        out = out[:, :, :3]
    if out.size == 0:
        raise ImageError("the image is empty")
    return out


def as_grey(image: np.ndarray) -> np.ndarray:
    """A float grey image from a grey or colour array (any numeric dtype)."""
    a = np.asarray(image)
    if a.dtype == np.uint8:
        a = a / 255.0
    elif a.dtype == np.uint16:
        a = a / 65535.0
    else:
        a = a.astype(float, copy=False)
    if a.ndim == 3 and a.shape[2] in (3, 4):
        a = a[:, :, :3] @ LUMA
    if a.ndim != 2:
        raise ImageError(f"an image is rows x columns (x 3 colours), not shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ImageError("the image holds values that are not finite numbers (NaN or infinity)")
    return a
