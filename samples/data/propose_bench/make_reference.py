#!/usr/bin/env python3
"""Makes the hand-made reference masks of the proposal benchmark from their inputs.

Each NAME.ref.json holds what a person decided by looking at NAME.jpg: a GrabCut rectangle
and strokes (sure foreground "fg", sure background "bg", polylines with a width), and/or
polygons ("polygons": filled as object, "cuts": filled as background, applied after GrabCut),
plus the boxes ([x, y, w, h]) of each face a person sees ("faces"), of each eye ("eyes") and of
other features a person would protect ("features"). This script turns
them into NAME_mask.png (255: the object) so a reference can be reviewed and redone:

    /usr/bin/python3 make_reference.py [NAME ...] [--overlay DIR]

--overlay writes NAME_ref.png (mask edge, strokes, boxes over the photo) for review.
"""
import json
import os
import sys

import cv2
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def strokes(mask, items, value):
    for s in items:
        pts = np.array(s["points"], np.int32).reshape(-1, 1, 2)
        cv2.polylines(mask, [pts], False, value, int(s.get("width", 6)))
        for p in s["points"]:
            cv2.circle(mask, tuple(int(v) for v in p), int(s.get("width", 6)) // 2, value, -1)


def make(name):
    ref = json.load(open(os.path.join(HERE, name + ".ref.json")))
    img = cv2.imread(os.path.join(HERE, ref["photo"]))
    h, w = img.shape[:2]
    if "rect" in ref:
        x, y, rw, rh = ref["rect"]
        gc = np.full((h, w), cv2.GC_BGD, np.uint8)
        gc[max(0, y):y + rh, max(0, x):x + rw] = cv2.GC_PR_FGD
        strokes(gc, ref.get("fg", []), cv2.GC_FGD)
        strokes(gc, ref.get("bg", []), cv2.GC_BGD)
        bgd, fgd = np.zeros((1, 65), np.float64), np.zeros((1, 65), np.float64)
        cv2.setRNGSeed(0)
        cv2.grabCut(img, gc, None, bgd, fgd, 8, cv2.GC_INIT_WITH_MASK)
        mask = np.where((gc == cv2.GC_FGD) | (gc == cv2.GC_PR_FGD), 255, 0).astype(np.uint8)
    else:
        mask = np.zeros((h, w), np.uint8)
    for p in ref.get("polygons", []):
        cv2.fillPoly(mask, [np.array(p, np.int32)], 255)
    for p in ref.get("cuts", []):
        cv2.fillPoly(mask, [np.array(p, np.int32)], 0)
    # Keep the object's components that a stroke or polygon touches, or the largest one.
    n, lab, stats, _ = cv2.connectedComponentsWithStats(mask)
    if n > 2:
        keep = np.zeros(n, bool)
        keep[1 + np.argmax(stats[1:, cv2.CC_STAT_AREA])] = True
        for s in ref.get("fg", []):
            for p in s["points"]:
                keep[lab[int(p[1]), int(p[0])]] = True
        keep[0] = False
        mask = np.where(keep[lab], 255, 0).astype(np.uint8)
    cv2.imwrite(os.path.join(HERE, name + "_mask.png"), mask)
    return img, mask, ref


def overlay(img, mask, ref):
    out = img.copy()
    out[mask == 0] = (out[mask == 0] * 0.45).astype(np.uint8)
    cs, _ = cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    cv2.drawContours(out, cs, -1, (0, 255, 255), 1)
    if "rect" in ref:
        x, y, rw, rh = ref["rect"]
        cv2.rectangle(out, (x, y), (x + rw, y + rh), (255, 0, 0), 1)
    for s in ref.get("fg", []):
        cv2.polylines(out, [np.array(s["points"], np.int32)], False, (0, 255, 0), 2)
    for s in ref.get("bg", []):
        cv2.polylines(out, [np.array(s["points"], np.int32)], False, (0, 0, 255), 2)
    for key, width in (("faces", 2), ("eyes", 1), ("features", 1)):
        for x, y, fw, fh in ref.get(key, []):
            cv2.rectangle(out, (x, y), (x + fw, y + fh), (255, 0, 255), width)
    for y in range(0, out.shape[0], 50):
        cv2.putText(out, str(y), (1, y + 10), cv2.FONT_HERSHEY_PLAIN, 0.8, (255, 255, 255), 1)
    for x in range(50, out.shape[1], 50):
        cv2.putText(out, str(x), (x, 10), cv2.FONT_HERSHEY_PLAIN, 0.8, (255, 255, 255), 1)
    return out


if __name__ == "__main__":
    args = sys.argv[1:]
    outdir = None
    if "--overlay" in args:
        i = args.index("--overlay")
        outdir = args[i + 1]
        del args[i:i + 2]
    names = args or sorted(f[:-9] for f in os.listdir(HERE) if f.endswith(".ref.json"))
    for name in names:
        img, mask, ref = make(name)
        if outdir:
            cv2.imwrite(os.path.join(outdir, name + "_ref.png"), overlay(img, mask, ref))
        print(name, "object", round(100.0 * np.count_nonzero(mask) / mask.size, 1), "%")
