"""The floor of the ridge finder's operators, and what OpenCV would buy. Run by hand:

    python benchmarks/operators.py

One pass of each image operator the ridge finder's stages before reading ends use, on a
working image of 256 x 256 and of 512 x 512 (the ridge finder works at 2-4 px/mm, so a 512 x
512 camera image gives one of these), with scipy/numpy as the finder uses them and, where the
`bench` extra is installed, with OpenCV's nearest equivalent; one thread each (BLAS and
OpenCV), best of 30. The finder's own stage times are benchmarks/vision.py's; this says how
much of them is the operators themselves, and whether OpenCV (not a runtime dependency) would
make the 10 ms target reachable.
"""
from __future__ import annotations

import time


def best_ms(f, n: int = 30) -> float:
    f()
    times = []
    for _ in range(n):
        t = time.perf_counter()
        f()
        times.append(time.perf_counter() - t)
    return 1000.0 * min(times)


def main() -> None:
    # benchmarks/machine.py, imported here as tests load some of these files as modules
    from machine import describe, one_thread

    one_thread()  # before numpy is first imported
    import numpy as np
    from scipy import ndimage

    try:
        import cv2

        cv2.setNumThreads(1)
    except ImportError:
        cv2 = None
    print(describe())
    print("one pass of each operator, ms (best of 30, one thread); OpenCV where installed (pip install '.[bench]')\n")
    print(f"| operator | {'256 scipy':>9} | {'256 cv2':>7} | {'512 scipy':>9} | {'512 cv2':>7} |")
    print("|---|---|---|---|---|")
    rng = np.random.default_rng(0)
    rows = [row for size in (256, 512) for row in _timed(size, rng, ndimage, cv2)]
    names = list(dict.fromkeys(r[1] for r in rows))
    for name in names:
        cells = []
        for size in (256, 512):
            (_, _, a, b), = [r for r in rows if r[0] == size and r[1] == name]
            cells += [f"{a:9.2f}", f"{b:7.2f}" if b is not None else f"{'-':>7}"]
        print(f"| {name} | " + " | ".join(cells) + " |")


def _timed(size: int, rng, ndimage, cv2) -> list[tuple]:
    """(size, operator, scipy ms, OpenCV ms or None) for each operator on a size x size image."""
    import numpy as np

    f = rng.random((size, size)).astype(np.float32)
    colour = rng.random((size, size, 3)).astype(np.float32)
    mask = f > 0.7
    m8 = mask.astype(np.uint8)
    cases = []
    for sigma in (1.0, 2.0, 3.0):  # the ridge scales at 2-4 px/mm: 0.35-1.2 mm
        k = 2 * int(3.0 * sigma + 0.5) + 1
        cases.append((f"Gaussian, sigma {sigma:g} px",
                      lambda s=sigma: ndimage.gaussian_filter(f, s, mode="nearest", truncate=3.0),
                      cv2 and (lambda s=sigma, k=k: cv2.GaussianBlur(f, (k, k), s, borderType=cv2.BORDER_REPLICATE))))
    cases.append(("labelling, 8-connected", lambda: ndimage.label(mask, np.ones((3, 3))),
                  cv2 and (lambda: cv2.connectedComponents(m8, connectivity=8))))
    cases.append(("Euclidean distance transform", lambda: ndimage.distance_transform_edt(mask),
                  cv2 and (lambda: cv2.distanceTransform(m8, cv2.DIST_L2, cv2.DIST_MASK_PRECISE))))
    cases.append(("erosion by a 5 px disc", lambda: ndimage.binary_erosion(mask, _disc(5)),
                  cv2 and (lambda: cv2.erode(m8, _disc(5).astype(np.uint8)))))
    cases.append(("colour FFT and back", lambda: np.fft.irfft2(np.fft.rfft2(colour, axes=(0, 1)), axes=(0, 1)),
                  cv2 and (lambda: [cv2.idft(cv2.dft(colour[:, :, c])) for c in range(3)])))
    return [(size, name, best_ms(ours), best_ms(theirs) if theirs else None) for name, ours, theirs in cases]


def _disc(radius: int):
    import numpy as np

    y, x = np.mgrid[-radius:radius + 1, -radius:radius + 1]
    return x * x + y * y <= radius * radius


if __name__ == "__main__":
    main()
