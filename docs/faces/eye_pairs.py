#!/usr/bin/python3
"""The eye finder's pair rule measured on a corpus of faces (issue 21; modules/propose/src/eyes.cpp).

A Python model of findEyes (the same cascades, search width, scale steps and pair tests) run on
every face of 60 px or more that the frontal cascade finds, at the proposal's settings, in
opencv-doc's pictures and every tenth frame of Megamind.avi (apt-get install opencv-doc), each
picture at several sizes. It prints, per size, how many faces get a pair for each limit on the
ratio of the two eyes' sizes, and writes a contact sheet of the pairs a looser limit adds (green:
within the first looser limit, red: beyond it) to judge by eye.

    /usr/bin/python3 docs/faces/eye_pairs.py [--ratios 1.3,1.4,1.5] [--scales 0.85,1,1.15,1.3]
                                             [--sheet eye_pairs.jpg]

Run on 2026-11-28 (1.3 was the limit): faces 117/135/146/149 at 0.85/1/1.15/1.3 times; pairs
at 1.3: 74/78/96/90, at 1.4: 75/78/99/97, at 1.5: 78/80/102/100. The 11 pairs 1.4 adds are all
on the two eyes (the sheet); of the 11 more that 1.5 adds, two are on no face at all (picture
frames, a pixelated drawing) and two have a box on the brow and temple.
"""
import argparse
import glob

import cv2
import numpy as np

CASCADES = "/usr/share/opencv4/haarcascades/"
DOC = "/usr/share/doc/opencv-doc"
WIDTH = 160  # eyes.cpp: kSearchWidth


def eye_boxes(eyes, gray, face):
    """Both cascades' boxes in the upper 60% of the face, face pixels (eyes.cpp: findEyes)."""
    x, y, w, h = face
    upper = gray[y:y + int(round(0.6 * h)), x:x + w]
    if upper.shape[1] < w / 2 or upper.shape[0] < h / 4:
        return []
    k = WIDTH / w
    crop = cv2.resize(upper, None, fx=k, fy=k, interpolation=cv2.INTER_AREA if k < 1 else cv2.INTER_LINEAR)
    crop = cv2.equalizeHist(crop)
    boxes = []
    for c in eyes:
        found = c.detectMultiScale(crop, 1.05, 2, cv2.CASCADE_SCALE_IMAGE, (round(0.12 * WIDTH),) * 2,
                                   (round(0.45 * WIDTH),) * 2)
        boxes += [(bx / k, by / k, bw / k, bh / k) for (bx, by, bw, bh) in (found if len(found) else [])]
    return boxes


def best_pair(boxes, w, h, ratio):
    """eyes.cpp's pairCost and bestPair with `ratio` as the limit on the sizes: (a, b, sizes' ratio)."""
    best, pair = float("inf"), None
    for a in boxes:
        for b in boxes:
            ca, cb = (a[0] + a[2] / 2, a[1] + a[3] / 2), (b[0] + b[2] / 2, b[1] + b[3] / 2)
            dx, dy = cb[0] - ca[0], abs(cb[1] - ca[1])
            if not (ca[0] < 0.5 * w < cb[0]) or dx < 0.25 * w or dx > 0.55 * w or dy > 0.25 * dx:
                continue
            if any(v < 0.15 * h or v > 0.6 * h for v in (ca[1], cb[1])):
                continue
            big, small = max(a[2], b[2]), min(a[2], b[2])
            if big > ratio * small:
                continue
            cost = abs(0.5 * (ca[0] + cb[0]) - 0.5 * w) / w + dy / dx + (big - small) / big
            if cost < best:
                best, pair = cost, (a, b, big / small)
    return pair


def corpus():
    names = sorted(glob.glob(DOC + "/**/*.jpg", recursive=True) + glob.glob(DOC + "/**/*.png", recursive=True))
    for n in names:
        yield n.split("/")[-1], cv2.imread(n, cv2.IMREAD_COLOR)
    video = cv2.VideoCapture(DOC + "/examples/data/Megamind.avi")
    i = 0
    while True:
        ok, frame = video.read()
        if not ok:
            break
        if i % 10 == 0:
            yield "Megamind#%d" % i, frame
        i += 1


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--ratios", default="1.3,1.4,1.5")
    p.add_argument("--scales", default="0.85,1,1.15,1.3")
    p.add_argument("--sheet", default="eye_pairs.jpg")
    a = p.parse_args()
    ratios = [float(r) for r in a.ratios.split(",")]
    face_cascade = cv2.CascadeClassifier(CASCADES + "haarcascade_frontalface_alt2.xml")
    eyes = [cv2.CascadeClassifier(CASCADES + n) for n in ("haarcascade_eye.xml", "haarcascade_eye_tree_eyeglasses.xml")]
    pictures = [(n, im) for n, im in corpus() if im is not None and min(im.shape[:2]) >= 64]
    tiles = []
    for s in (float(v) for v in a.scales.split(",")):
        counts, faces = [0] * len(ratios), 0
        for name, im in pictures:
            im = cv2.resize(im, None, fx=s, fy=s, interpolation=cv2.INTER_AREA if s < 1 else cv2.INTER_LINEAR)
            gray = cv2.cvtColor(im, cv2.COLOR_BGR2GRAY)
            k = min(1.0, 320 / max(gray.shape))  # faces.cpp: faceWorkingSize
            small = cv2.resize(gray, None, fx=k, fy=k, interpolation=cv2.INTER_AREA) if k < 1 else gray
            found = face_cascade.detectMultiScale(small, 1.2, 2, cv2.CASCADE_SCALE_IMAGE, (24, 24))
            for box in (found if len(found) else []):
                x, y, w, h = (int(round(v / k)) for v in box)
                if w < 60:  # eyes.hpp: kEyeFaceMin
                    continue
                faces += 1
                boxes = eye_boxes(eyes, gray, (x, y, w, h))
                pairs = [best_pair(boxes, w, h, r) for r in ratios]
                counts = [c + (q is not None) for c, q in zip(counts, pairs)]
                if pairs[0] is None and pairs[-1] is not None:
                    tile = im[max(0, y):y + h, max(0, x):x + w].copy()
                    within = pairs[1] is not None
                    for e in pairs[-1][:2]:
                        cv2.rectangle(tile, (int(e[0]), int(e[1])), (int(e[0] + e[2]), int(e[1] + e[3])),
                                      (0, 255, 0) if within else (0, 0, 255), 2)
                    tile = cv2.resize(tile, (200, 200))
                    cv2.putText(tile, "%g %s %.2f" % (s, name[:14], pairs[-1][2]), (2, 195),
                                cv2.FONT_HERSHEY_SIMPLEX, 0.38, (255, 255, 0), 1)
                    tiles.append(tile)
        print("scale %g: %d faces; pairs %s" % (s, faces, ", ".join(
            "%d within %g" % (c, r) for c, r in zip(counts, ratios))))
    if tiles:
        while len(tiles) % 6:
            tiles.append(np.zeros_like(tiles[0]))
        cv2.imwrite(a.sheet, np.vstack([np.hstack(tiles[i:i + 6]) for i in range(0, len(tiles), 6)]))
        print("wrote", a.sheet)


if __name__ == "__main__":
    main()
