"""Draws docs/resize/side_by_side.jpg: each photo, then widened 1.5x by cv2.resize, by
multicage.content_aware_resize (the default proposal and parameters), and by ImageMagick's
-liquid-rescale (seam carving) where `convert` is installed.

    PYTHONPATH=build/python /usr/bin/python3 docs/resize/make_side_by_side.py
"""
import os
import shutil
import subprocess
import sys
import tempfile

import cv2
import numpy as np

import multicage

HERE = os.path.dirname(os.path.abspath(__file__))
BENCH = os.path.join(HERE, "..", "..", "samples", "data", "propose_bench")
PHOTOS = ["messi5.jpg", "astronaut.jpg", "megamind_dinner.jpg"]
FACTOR = 1.5
ROW_HEIGHT = 240


def liquid_rescale(image, size):
    if shutil.which("convert") is None:
        return None
    with tempfile.TemporaryDirectory() as tmp:
        src, dst = os.path.join(tmp, "in.png"), os.path.join(tmp, "out.png")
        cv2.imwrite(src, image)
        subprocess.run(["convert", src, "-liquid-rescale", "%dx%d!" % size, dst], check=True)
        return cv2.imread(dst)


def labelled(image, text):
    scale = ROW_HEIGHT / image.shape[0]
    out = cv2.resize(image, (round(image.shape[1] * scale), ROW_HEIGHT), interpolation=cv2.INTER_AREA)
    cv2.rectangle(out, (0, 0), (8 + 9 * len(text), 22), (0, 0, 0), -1)
    cv2.putText(out, text, (4, 16), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (255, 255, 255), 1, cv2.LINE_AA)
    return np.pad(out, ((0, 0), (0, 6), (0, 0)), constant_values=255)


def main():
    rows = []
    for name in PHOTOS:
        image = multicage.imread(os.path.join(BENCH, name))
        h, w = image.shape[:2]
        size = (round(w * FACTOR), h)
        cells = [labelled(image, "input %dx%d" % (w, h)),
                 labelled(cv2.resize(image, size), "cv::resize"),
                 labelled(multicage.content_aware_resize(image, size), "multicage resize")]
        liquid = liquid_rescale(image, size)
        if liquid is not None:
            cells.append(labelled(liquid, "liquid rescale (ImageMagick)"))
        rows.append(np.hstack(cells))
    width = max(r.shape[1] for r in rows)
    rows = [np.pad(r, ((0, 6), (0, width - r.shape[1]), (0, 0)), constant_values=255) for r in rows]
    out = os.path.join(HERE, "side_by_side.jpg")
    cv2.imwrite(out, np.vstack(rows), [cv2.IMWRITE_JPEG_QUALITY, 85])
    print("wrote", out)


if __name__ == "__main__":
    sys.exit(main())
