#!/usr/bin/python3
"""Draws docs/propose/iterations_sheet.jpg: the default proposal of an earlier build (GrabCut
stopped after two iterations everywhere) beside this build's (the GrabCuts from the frame
inward go on until their labels settle), on photos where the two differ.

    # the earlier build's Python module, e.g. main at 8b07f14 built in /tmp/old/build:
    PYTHONPATH=/tmp/old/build/python /usr/bin/python3 docs/propose/make_iterations_sheet.py \\
        --dump /tmp/before
    PYTHONPATH=build/python /usr/bin/python3 docs/propose/make_iterations_sheet.py \\
        --before /tmp/before [OUT.jpg]

Photos: four of the benchmark's (samples/data/propose_bench) and four outside it, from
Debian's opencv-doc and python3-skimage, each scaled to at most 720 px.
"""
import argparse
import os

import cv2
import numpy as np

import multicage as mc

HERE = os.path.dirname(os.path.abspath(__file__))
BENCH = os.path.join(HERE, "..", "..", "samples", "data", "propose_bench")
OPENCV = "/usr/share/doc/opencv-doc/examples/data"
SKIMAGE = "/usr/lib/python3/dist-packages/skimage/data"
PHOTOS = [os.path.join(BENCH, n + ".jpg") for n in ("squirrel", "robin", "chelsea", "apple")] + [
    os.path.join(OPENCV, "chicky_512.png"),
    os.path.join(OPENCV, "home.jpg"),
    os.path.join(OPENCV, "stuff.jpg"),
    os.path.join(SKIMAGE, "motorcycle_left.png"),
]
TILE = 360


def photos():
    for path in PHOTOS:
        img = cv2.imread(path, cv2.IMREAD_COLOR)
        if img is None:
            print("skipped (not installed): " + path)
            continue
        s = min(1.0, 720.0 / max(img.shape[:2]))
        if s < 1.0:
            img = cv2.resize(img, None, fx=s, fy=s, interpolation=cv2.INTER_AREA)
        yield os.path.splitext(os.path.basename(path))[0], img


def draw(img, cage, label):
    out = img.copy()
    depths = [cage.depth(i) for i in range(cage.polygon_count)]
    for i in range(cage.polygon_count):
        colour = (0, 215, 255) if depths[i] == min(depths) else (255, 128, 0)
        poly = np.int32(np.round(np.array(cage.polygon(i)).reshape(-1, 2)))
        cv2.polylines(out, [poly], True, colour, max(2, img.shape[1] // 240), cv2.LINE_AA)
    s = TILE / img.shape[1]
    out = cv2.resize(out, (TILE, int(round(img.shape[0] * s))), interpolation=cv2.INTER_AREA)
    cv2.rectangle(out, (0, 0), (TILE, 18), (30, 30, 30), cv2.FILLED)
    cv2.putText(out, label, (4, 13), cv2.FONT_HERSHEY_SIMPLEX, 0.45, (255, 255, 255), 1,
                cv2.LINE_AA)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dump", help="only save this build's proposals as cage files here")
    ap.add_argument("--before", help="cage files saved by --dump from the earlier build")
    ap.add_argument("out", nargs="?", default=os.path.join(HERE, "iterations_sheet.jpg"))
    a = ap.parse_args()
    if a.dump:
        os.makedirs(a.dump, exist_ok=True)
        for name, img in photos():
            mc.propose_multicage(img).save(os.path.join(a.dump, name + ".yml"))
        print("saved the proposals in " + a.dump)
        return
    if not a.before:
        ap.error("--before DIR (from a --dump of the earlier build) or --dump DIR")
    rows = []
    for name, img in photos():
        before = mc.Multicage.load(os.path.join(a.before, name + ".yml"))
        rows.append(np.hstack([draw(img, before, name + ": two iterations"),
                               draw(img, mc.propose_multicage(img), name + ": until settled")]))
    height = max(r.shape[0] for r in rows)
    rows = [cv2.copyMakeBorder(r, 0, height - r.shape[0], 0, 0, cv2.BORDER_CONSTANT,
                               value=(30, 30, 30)) for r in rows]
    pairs = [np.hstack(rows[i:i + 2]) if i + 1 < len(rows) else
             np.hstack([rows[i], np.full_like(rows[i], 30)]) for i in range(0, len(rows), 2)]
    cv2.imwrite(a.out, np.vstack(pairs), [cv2.IMWRITE_JPEG_QUALITY, 85])
    print("wrote " + a.out)


if __name__ == "__main__":
    main()
